"""Rewrite every example block of the README and docs/*.md from its example script.

Usage: python scripts/update_docs.py [--check]

With --check, only report which blocks differ (exit code 1 if any). See docs/examples/README.md.
"""

from __future__ import annotations

import argparse
import importlib.util
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BLOCK = re.compile(r"(<!-- example: (\S+) -->\n)(.*?)(<!-- end example -->)", re.S)


def load(relative: str):
    """Import an example module from its path relative to the repository."""
    path = ROOT / relative
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def documents() -> list[Path]:
    return [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


def blocks(text: str):
    """(example path, current block text) for every example block in ``text``."""
    return [(m.group(2), m.group(3)) for m in BLOCK.finditer(text)]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="only report differences")
    parser.add_argument(
        "--only", action="append", help="only the blocks of this example (docs/examples/NAME.py)"
    )
    args = parser.parse_args()
    stale = 0
    for doc in documents():
        text = doc.read_text()
        cache: dict[str, str] = {}

        def fresh(match, cache=cache):
            name = match.group(2)
            if args.only and Path(name).stem not in args.only:
                return match.group(0)
            if name not in cache:
                cache[name] = load(name).render()
            return match.group(1) + cache[name] + match.group(4)

        new = BLOCK.sub(fresh, text)
        if new != text:
            stale += 1
            print(f"{'stale' if args.check else 'updated'}: {doc.relative_to(ROOT)}")
            if not args.check:
                from vorobound.files import write_text

                write_text(doc, new)
    return 1 if args.check and stale else 0


if __name__ == "__main__":
    sys.exit(main())
