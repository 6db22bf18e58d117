"""Write docs/api.md, the reference of vorobound's Python API, from the docstrings.

    python scripts/api_docs.py          # rewrite docs/api.md
    python scripts/api_docs.py --check  # exit 1 if docs/api.md differs (what the tests run)

The page lists every command's function (``vorobound.solve``, ...) with its signature and
docstring, and the fields of the result it returns.
"""

from __future__ import annotations

import dataclasses
import inspect
import sys
import typing
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "api.md"
FUNCTIONS = (
    "solve",
    "bound",
    "sweep",
    "advise",
    "certify",
    "check_certificate",
    "sample",
    "check",
    "lfs",
    "reconstruct",
    "triangle",
    "validate",
    "figure",
    "reproduce",
    "cheng",
)
COMMAND = {"bound": "bounds", "check_certificate": "certify --check"}


def _signature(function) -> str:
    lines = [f"vorobound.{function.__name__}("]
    for name, param in inspect.signature(function).parameters.items():
        if param.kind is param.KEYWORD_ONLY and not lines[-1].endswith("*,"):
            if len(lines) == 1:
                lines.append("    *,")
        default = "" if param.default is param.empty else f"={param.default!r}"
        lines.append(f"    {name}{default},")
    lines.append(")")
    return "\n".join(lines)


def _result_class(function):
    from vorobound.mesh import TriangleMesh  # named under TYPE_CHECKING in the API modules

    hints = typing.get_type_hints(function, localns={"TriangleMesh": TriangleMesh})
    result = hints.get("return")
    return result if dataclasses.is_dataclass(result) else None


def _fields(cls) -> list[str]:
    out = []
    docs = _field_docs(cls)
    for field in dataclasses.fields(cls):
        if not field.repr:
            continue
        line = f"- `{field.name}`"
        if field.name in docs:
            line += f": {docs[field.name]}"
        out.append(line)
    return out


def _field_docs(cls) -> dict[str, str]:
    """The string literal after each field in the class body (the attribute docstrings)."""
    import ast

    try:
        tree = ast.parse(inspect.getsource(cls))
    except (OSError, TypeError):
        return {}
    body = tree.body[0].body
    docs = {}
    for node, after in zip(body, body[1:], strict=False):
        if (
            isinstance(node, ast.AnnAssign)
            and isinstance(node.target, ast.Name)
            and isinstance(after, ast.Expr)
            and isinstance(after.value, ast.Constant)
            and isinstance(after.value.value, str)
        ):
            docs[node.target.id] = " ".join(after.value.value.split())
    return docs


def render() -> str:
    import vorobound

    parts = [
        "# Python API",
        "",
        "Generated from the docstrings by `python scripts/api_docs.py` (the tests check that it",
        "is current). Every command of the command line is a function here with keyword",
        "arguments named like its options; each returns a frozen result whose `to_dict()` is the",
        "command's `--json` object (with `vorobound_version`, `command` and `params`), whose",
        "`ok` is False where the command exits with 1, and whose repr is one short line.",
        "Errors are `vorobound.VoroboundError` subclasses (the command line's exit code 2).",
        "",
    ]
    for name in FUNCTIONS:
        if name not in dir(vorobound):
            continue
        function = getattr(vorobound, name)
        command = COMMAND.get(name, name)
        parts += [f"## `vorobound.{name}` (`vorobound {command}`)", ""]
        parts += ["```python", _signature(function), "```", ""]
        doc = inspect.cleandoc(function.__doc__ or "")
        parts += ["```text", doc, "```", ""]
        result = _result_class(function)
        if result is not None:
            parts += [f"Returns `{result.__name__}`, with the fields:", ""]
            parts += _fields(result) + [""]
    return "\n".join(parts).rstrip() + "\n"


def main() -> int:
    text = render()
    if "--check" in sys.argv[1:]:
        if not PAGE.exists() or PAGE.read_text(encoding="utf-8") != text:
            print("docs/api.md is stale: run python scripts/api_docs.py", file=sys.stderr)
            return 1
        return 0
    PAGE.write_text(text, encoding="utf-8")
    print(f"wrote {PAGE.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
