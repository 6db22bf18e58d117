"""The one renderer of the command line: JSON for programs, rich tables for people.

JSON never holds NaN or infinity: a value that cannot be computed is an error raised before
rendering, and a documented empty cell is ``null`` with its reason beside it.
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterable, Sequence


def jsonable(value):
    """Plain JSON types (see :func:`vorobound.api.result.jsonable`)."""
    from ..api.result import jsonable as plain

    return plain(value)


def json_text(payload, indent: int | None = 2) -> str:
    """``payload`` as JSON text (ASCII-safe)."""
    return json.dumps(jsonable(payload), indent=indent, allow_nan=False)


def print_json(payload) -> None:
    print(json_text(payload))


ATOMIC_CELL = 24
"""Cells with a digit and at most this many characters (numbers, counts, ranges) are never
broken across lines."""


def _atomic(cell: str) -> bool:
    return len(cell) <= ATOMIC_CELL and any(ch.isdigit() for ch in cell)


def print_table(title: str, columns: Sequence[str], rows: Iterable[Sequence[str]]) -> None:
    """A rich table that never cuts or breaks a number: a column of numbers is as wide as its
    widest number, text folds onto more lines, and when even the numbers do not fit the width
    of the terminal each row is printed as "column: value" lines instead. Output that is not a
    terminal is laid out as wide as it needs."""
    import shutil
    import sys

    from rich.console import Console
    from rich.table import Table

    from .notation import shows_unicode, to_ascii

    rows = [[str(cell) for cell in row] for row in rows]
    if not shows_unicode(sys.stdout):  # spelt out before the layout measures the cells
        title, columns = to_ascii(title), [to_ascii(c) for c in columns]
        rows = [[to_ascii(cell) for cell in row] for row in rows]
    cells = [list(columns), *rows]
    widest = [max(len(r[i]) for r in cells) for i in range(len(columns))]
    atomic = [
        max((len(r[i]) for r in rows if _atomic(r[i])), default=0) for i in range(len(columns))
    ]
    width = None
    if not sys.stdout.isatty():
        width = max(shutil.get_terminal_size((100, 24)).columns, sum(widest) + 3 * len(widest) + 4)
    console = Console(width=width)
    needed = sum(max(a, min(w, 6)) for a, w in zip(atomic, widest, strict=True))
    if needed + 3 * len(columns) + 1 > console.width:
        console.print(title, style="italic", markup=False)
        for row in rows:
            for name, cell in zip(columns, row, strict=True):
                console.print(f"  {name}: {cell}", markup=False, highlight=False, soft_wrap=True)
            console.print()
        return
    table = Table(title=title)
    for name, size in zip(columns, atomic, strict=True):
        table.add_column(name, overflow="fold", min_width=size or None)
    for row in rows:
        table.add_row(*row)
    console.print(table)


def print_footer(text: str) -> None:
    """A sentence under a table: in the table's notation, wrapped to the terminal."""
    from .notation import footer

    print(footer(text))


def fmt(value, digits: int = 10) -> str:
    """A number for people: significant digits, 'n/a' for None, NaN or infinity."""
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "n/a"
    if isinstance(value, float):
        return f"{value:.{digits}g}"
    return str(value)


EXIT_VIOLATION = 1
"""The command ran and found a violation, or failed to certify (the count is in the last
line)."""


def emit(result, as_json: bool, show) -> int:
    """Print ``result`` (its JSON, or ``show(result)`` for people) and return the exit code:
    0 when everything the command checked holds, else 1 with the verdict as the last line."""
    if as_json:
        print_json(result.to_dict())
    else:
        show(result)
    if result.ok:
        return 0
    if not as_json:
        print(result.verdict)
    return EXIT_VIOLATION
