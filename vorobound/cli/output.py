"""Formatting helpers shared by the commands: JSON for programs, rich tables for people."""

from __future__ import annotations

import json
import math
from collections.abc import Iterable, Sequence

from ..errors import VoroboundError


def jsonable(value):
    """Plain JSON types for numpy scalars/arrays and dataclass-like values; NaN becomes null."""
    if hasattr(value, "tolist"):
        value = value.tolist()
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [jsonable(v) for v in value]
    return value


def print_json(payload: dict) -> None:
    print(json.dumps(jsonable(payload), indent=2, allow_nan=False))


def print_table(title: str, columns: Sequence[str], rows: Iterable[Sequence[str]]) -> None:
    from rich.console import Console
    from rich.table import Table

    table = Table(title=title)
    for name in columns:
        table.add_column(name)
    for row in rows:
        table.add_row(*row)
    Console().print(table)


def fmt(value: float, digits: int = 10) -> str:
    """A number for people: significant digits, 'n/a' for NaN."""
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "n/a"
    return f"{value:.{digits}g}"


def parse_numbers(text: str, what: str, count: int | Sequence[int]) -> list[float]:
    """Parse ``"x,y[,z]"`` into finite floats, checking how many there are."""
    parts = [p.strip() for p in text.split(",")]
    allowed = (count,) if isinstance(count, int) else tuple(count)
    if len(parts) not in allowed:
        want = " or ".join(str(c) for c in allowed)
        raise VoroboundError(f"{what} needs {want} comma-separated numbers, got {text!r}")
    values = []
    for part in parts:
        try:
            value = float(part)
        except ValueError:
            raise VoroboundError(f"{what}: {part!r} is not a number") from None
        if not math.isfinite(value):
            raise VoroboundError(f"{what}: {part!r} is not a finite number")
        values.append(value)
    return values
