"""Tables of numbers in text files (ball and sizing CSVs), with the delimiter found from the
first line and every message naming a line of the file.

The delimiter is a semicolon, a tab or a comma (in that order of preference, since a file that
separates columns with semicolons may use commas as decimal marks), or runs of spaces when the
first line has none of them. A first line with no number in it is a header. Blank lines and
lines starting with ``#`` are skipped; line numbers count every line of the file from 1.
"""

from __future__ import annotations

import io
import os
from collections.abc import Iterator
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


def read_number_table(path: str | os.PathLike, what: str) -> NumberTable:
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
    numbered = list(numbered_lines(io.StringIO(text)))
    if not numbered:
        raise ReadError(f"{what} {path} is empty")
    delimiter = delimiter_of(numbered[0][1])
    header = None
    header_line, first = numbered[0][0], cells_of(numbered[0][1], delimiter)
    if is_header(first):
        header = tuple(cell.strip("\"'").strip().lower() for cell in first)
        numbered = numbered[1:]
    if not numbered:
        raise ReadError(
            f"{what} {path}: line {header_line} is not all numbers (a header?) and no rows "
            "follow; columns are separated by commas, semicolons, tabs or spaces"
        )
    lines = np.array([number for number, _ in numbered], dtype=np.int64)
    width = len(header) if header is not None else len(cells_of(numbered[0][1], delimiter))
    values = parse_rows(numbered, delimiter, f"{what} {path}", header_line, width, header)
    return NumberTable(values, lines, header, delimiter)


def parse_rows(
    numbered: list[tuple[int, str]],
    delimiter: str | None,
    what: str,
    source: int,
    width: int,
    header: tuple[str, ...] | None,
) -> np.ndarray:
    """The numbers of the ``numbered`` lines (file line, text) of a table: the one rule by which
    ball and sizing files are parsed, whole or a block at a time (:mod:`.stream`). Every row
    has ``width`` columns (the header's, else those of the first row of the file); ``source``
    is the line the delimiter was found on; ``what`` names the file in messages."""
    try:
        values = np.loadtxt(
            io.StringIO("\n".join(line for _, line in numbered)),
            delimiter=delimiter,
            comments=None,
            ndmin=2,
        )
    except ValueError:
        problem = _first_problem(numbered, delimiter, source, width)
        raise ReadError(f"{what}, {problem}") from None
    if values.shape[1] != width:
        if header is not None:
            raise ReadError(
                f"{what}: the header (line {source}) names {width} columns but the rows have "
                f"{values.shape[1]}"
            )
        raise ReadError(
            f"{what}, line {numbered[0][0]}: {values.shape[1]} columns where line {source} "
            f"has {width} (columns separated by {DELIMITER_NAMES[delimiter]})"
        )
    return values


def numbered_lines(lines) -> Iterator[tuple[int, str]]:
    """(file line from 1, text) of the lines that hold data: not blank, not a ``#`` comment
    (lines split at newlines only, as a file is read line by line)."""
    for number, line in enumerate(lines, start=1):
        if line.strip() and not line.lstrip().startswith("#"):
            yield number, line.rstrip("\r\n")


def delimiter_of(line: str) -> str | None:
    return next((d for d in DELIMITERS if d in line), None)


def cells_of(line: str, delimiter: str | None) -> list[str]:
    return [cell.strip() for cell in line.split(delimiter)]


def is_header(cells: list[str]) -> bool:
    """Whether a first line's cells are column names: none of them a number (a row of numbers
    with an empty cell or a decimal comma is a bad row, not a header)."""
    return not any(is_number(cell) for cell in cells)


def is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _first_problem(
    numbered: list[tuple[int, str]], delimiter: str | None, source: int, width: int
) -> str:
    """Where and why the rows are not a table of numbers (for the message after the path);
    ``source`` is the line the delimiter was taken from, ``width`` the columns every row has."""
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
                f"line {number}: {len(cells)} columns where line {source} has {width} "
                f"(columns separated by {DELIMITER_NAMES[delimiter]})"
            )
    return "not a table of numbers"
