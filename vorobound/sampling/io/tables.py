"""Tables of numbers in text files (ball and sizing CSVs), with the delimiter found from the
first line and every message naming a line of the file.

The delimiter is a semicolon, a tab or a comma (in that order of preference, since a file that
separates columns with semicolons may use commas as decimal marks), or runs of spaces when the
first line has none of them. A first line that is not all numbers is a header. Blank lines and
lines starting with ``#`` are skipped; line numbers count every line of the file from 1.
"""

from __future__ import annotations

import io
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...errors import ReadError

DELIMITERS = (";", "\t", ",")
"""Column delimiters recognised, in order of preference (module docstring)."""
DELIMITER_NAMES = {";": "semicolons", "\t": "tabs", ",": "commas", None: "spaces"}


@dataclass(frozen=True)
class NumberTable:
    """The numbers of a text table, its header (if any) and where each row is in the file."""

    values: np.ndarray
    """(rows, columns) float64."""
    lines: np.ndarray
    """File line number of each row, counted from 1 (header, blank and comment lines count)."""
    header: tuple[str, ...] | None
    """Column names of the first line, lower-cased and unquoted, or None without a header."""
    delimiter: str | None
    """The delimiter found (None: runs of spaces)."""


def read_number_table(path: str | Path, what: str) -> NumberTable:
    """Read a table of numbers; ``what`` names the file in messages ("balls", "sizing file").

    Raises
    ------
    ReadError
        Missing or unreadable file, no rows, a row with a different number of columns than the
        first, or a cell that is not a number (a decimal comma is named as the likely cause).
    """
    path = Path(path)
    if path.exists() and not path.is_file():
        raise ReadError(f"cannot read {what} {path}: not a regular file")
    try:
        text = path.read_text(encoding="utf-8-sig")
    except UnicodeDecodeError:
        raise ReadError(f"{what} {path} is not UTF-8 text") from None
    except OSError as exc:
        raise ReadError(f"cannot read {what} {path}: {exc.strerror or exc}") from None
    numbered = [
        (number, line)
        for number, line in enumerate(text.splitlines(), start=1)
        if line.strip() and not line.lstrip().startswith("#")
    ]
    if not numbered:
        raise ReadError(f"{what} {path} is empty")
    delimiter = delimiter_of(numbered[0][1])
    header = None
    header_line, first = numbered[0][0], cells_of(numbered[0][1], delimiter)
    if not all(is_number(cell) for cell in first):
        header = tuple(cell.strip("\"'").strip().lower() for cell in first)
        numbered = numbered[1:]
    if not numbered:
        raise ReadError(
            f"{what} {path}: line {header_line} is not all numbers (a header?) and no rows "
            "follow; columns are separated by commas, semicolons, tabs or spaces"
        )
    lines = np.array([number for number, _ in numbered], dtype=np.int64)
    try:
        values = np.loadtxt(
            io.StringIO("\n".join(line for _, line in numbered)),
            delimiter=delimiter,
            comments=None,
            ndmin=2,
        )
    except ValueError:
        problem = _first_problem(numbered, delimiter, header_line)
        raise ReadError(f"{what} {path}, {problem}") from None
    if header is not None and values.shape[1] != len(header):
        raise ReadError(
            f"{what} {path}: the header (line {header_line}) names {len(header)} columns but "
            f"the rows have {values.shape[1]}"
        )
    return NumberTable(values, lines, header, delimiter)


def delimiter_of(line: str) -> str | None:
    return next((d for d in DELIMITERS if d in line), None)


def cells_of(line: str, delimiter: str | None) -> list[str]:
    return [cell.strip() for cell in line.split(delimiter)]


def is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _first_problem(numbered: list[tuple[int, str]], delimiter: str | None, source: int) -> str:
    """Where and why the rows are not a table of numbers (for the message after the path);
    ``source`` is the line the delimiter was taken from."""
    width = len(cells_of(numbered[0][1], delimiter))
    for number, line in numbered:
        cells = cells_of(line, delimiter)
        bad = next((cell for cell in cells if not is_number(cell)), None)
        if bad is not None:
            hint = ""
            other = next((d for d in DELIMITERS if d != delimiter and d in bad), None)
            if other == "," and is_number(bad.replace(",", ".")):
                hint = " (a decimal comma? write numbers with a decimal point)"
            elif other is not None:
                hint = (
                    f" (columns separated by {DELIMITER_NAMES[other]}? line {source} "
                    f"separates them by {DELIMITER_NAMES[delimiter]})"
                )
            elif bad == "":
                hint = " (an empty cell)"
            return f"line {number}: {bad[:40]!r} is not a number{hint}"
        if len(cells) != width:
            return (
                f"line {number}: {len(cells)} columns where line {numbered[0][0]} has {width} "
                f"(columns separated by {DELIMITER_NAMES[delimiter]})"
            )
    return "not a table of numbers"
