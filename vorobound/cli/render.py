"""The one renderer of the command line: JSON for programs, rich tables for people.

JSON never holds NaN or infinity: a value that cannot be computed is an error raised before
rendering, and a documented empty cell is ``null`` with its reason beside it.
"""

from __future__ import annotations

import dataclasses
import enum
import json
import math
from collections.abc import Iterable, Sequence


def jsonable(value):
    """Plain JSON types for numpy values, dataclasses, enums, tuples; NaN/inf become null."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        value = {f.name: getattr(value, f.name) for f in dataclasses.fields(value)}
    if isinstance(value, enum.Enum):
        value = value.value
    if hasattr(value, "tolist"):
        value = value.tolist()
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [jsonable(v) for v in value]
    return value


def json_text(payload, indent: int | None = 2) -> str:
    """``payload`` as JSON text (ASCII-safe)."""
    return json.dumps(jsonable(payload), indent=indent, allow_nan=False)


def print_json(payload) -> None:
    print(json_text(payload))


def print_table(title: str, columns: Sequence[str], rows: Iterable[Sequence[str]]) -> None:
    """A rich table that never cuts a cell short: narrow columns fold their text onto more
    lines (no "…"), and output that is not a terminal is laid out as wide as it needs."""
    import shutil
    import sys

    from rich.console import Console
    from rich.table import Table

    rows = [list(row) for row in rows]
    table = Table(title=title)
    for name in columns:
        table.add_column(name, overflow="fold")
    for row in rows:
        table.add_row(*row)
    width = None
    if not sys.stdout.isatty():
        cells = [list(columns), *rows]
        widest = [max(len(str(r[i])) for r in cells) for i in range(len(columns))]
        width = max(shutil.get_terminal_size((100, 24)).columns, sum(widest) + 3 * len(widest) + 4)
    Console(width=width).print(table)


def fmt(value, digits: int = 10) -> str:
    """A number for people: significant digits, 'n/a' for None, NaN or infinity."""
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "n/a"
    if isinstance(value, float):
        return f"{value:.{digits}g}"
    return str(value)
