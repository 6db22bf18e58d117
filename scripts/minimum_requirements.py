"""Print the declared minimum version of every dependency as exact pins (``name==floor``).

Used by ``.ci/run`` to install the oldest versions ``pyproject.toml`` allows, so that a floor
that does not really work fails CI. Usage: python scripts/minimum_requirements.py [extra ...]
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

import tomllib

ROOT = Path(__file__).resolve().parents[1]
FLOOR = re.compile(r"^\s*([A-Za-z0-9_.\-\[\]]+)\s*>=\s*([0-9][^,;\s]*)")


def pins(extras: list[str]) -> list[str]:
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    requirements = list(project["dependencies"])
    for extra in extras:
        requirements += project["optional-dependencies"][extra]
    out = []
    for requirement in requirements:
        match = FLOOR.match(requirement)
        if not match:
            raise SystemExit(f"no '>=' floor in requirement {requirement!r}")
        out.append(f"{match.group(1)}=={match.group(2)}")
    return out


if __name__ == "__main__":
    print("\n".join(pins(sys.argv[1:])))
