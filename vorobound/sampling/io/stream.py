"""Ball files read in chunks: CSV, NPZ and Parquet without loading the whole file.

:func:`ball_chunks` yields (centers, radii) of at most ``chunk_rows`` balls at a time, checked
row by row as :func:`vorobound.sampling.balls.make_balls` checks a whole set (the checks that
need every ball, duplicates and the count, are left to the caller). The formats and column
names are those of :func:`vorobound.sampling.io.balls.read_balls`:

* CSV: columns x, y, z, r (header optional; ``radius`` or ``radii`` for r), separated by
  semicolons, tabs, commas or runs of spaces as :mod:`.tables` decides from the first line;
  blank lines and lines starting with ``#`` are skipped. Parsed by pyarrow's streaming CSV
  reader when pyarrow is installed (``pip install 'vorobound[parquet]'``), else by numpy, block
  by block (several times slower); by numpy for spaces, and pyarrow refuses a ``#`` line after
  the first row of numbers.
* NPZ: arrays x, y, z, r (or radius/radii), or points (n, 3) with radii; each array is read
  from its member of the archive a block at a time (compressed or not).
* Parquet (``.parquet``, ``.pq``): columns x, y, z and r/radius/radii, by record batches
  (needs pyarrow).
* anything else: a meshio point set, read whole (meshio has no streaming reader) and handed
  out in chunks.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...errors import ReadError
from ..balls import checked_rows
from .balls import (
    PARQUET_SUFFIXES,
    csv_columns,
    parquet_columns,
    pyarrow_available,
    read_ball_arrays,
)
from .npz import npz_chunks
from .tables import cells_of, delimiter_of, is_header, numbered_lines, parse_rows

CHUNK_ROWS = 1 << 18
"""Balls per chunk (8 MB of float64 centers and radii; larger chunks were slower, not faster,
in the passes of a tiled check)."""
_CSV_BLOCK_BYTES = 1 << 23  # pyarrow's CSV block (about 2.5·10⁵ rows of x, y, z, r)


def ball_chunks(path: str | Path, chunk_rows: int = CHUNK_ROWS) -> Iterator[tuple]:
    """(centers (m, 3), radii (m,)) of consecutive balls of the file, m ≤ ``chunk_rows``.

    Raises
    ------
    ReadError
        The file is missing, unreadable, or not a table of balls.
    InputError
        A row with NaN, infinite or non-positive values, or outside the supported range (the
        message gives its row number in the file).
    """
    path = Path(path)
    if not path.exists():
        raise ReadError(f"cannot read balls {path}: no such file")
    if not path.is_file():
        raise ReadError(f"cannot read balls {path}: not a regular file")
    suffix = path.suffix.lower()
    if suffix == ".csv":
        chunks = (
            _csv_arrow(path, chunk_rows) if pyarrow_available() else _csv_numpy(path, chunk_rows)
        )
    elif suffix == ".npz":
        chunks = npz_chunks(path, chunk_rows)
    elif suffix in PARQUET_SUFFIXES:
        chunks = _parquet(path, chunk_rows)
    else:
        centers, radii, _ = read_ball_arrays(path)
        chunks = (
            (centers[s : s + chunk_rows], radii[s : s + chunk_rows])
            for s in range(0, len(radii), chunk_rows)
        )
    what = f"balls {path.name}"
    first = 0
    for centers, radii in chunks:
        centers, radii = checked_rows(centers, radii, what, first)
        first += len(radii)
        if len(radii):
            yield centers, radii


@dataclass(frozen=True)
class _CsvLayout:
    """Where the numbers of a ball CSV are, found as :func:`read_number_table` finds them."""

    columns: list[int]
    """Columns of x, y, z and r."""
    skip: int
    """Lines before the first row of numbers (comments, blank lines and the header)."""
    delimiter: str | None
    """The delimiter (None: runs of spaces)."""
    source: int
    """The line (from 1) the delimiter was found on: the header's, else the first row's."""
    width: int
    """Columns of every row."""
    header: tuple[str, ...] | None


def _layout(path: Path) -> _CsvLayout:
    """The columns, delimiter and header of a ball CSV (blank lines and lines starting with
    ``#`` are skipped)."""
    try:
        with open(path, encoding="utf-8-sig") as handle:
            lines = numbered_lines(handle)
            number, line = next(lines, (0, None))
            more = next(lines, None) is not None
    except (OSError, UnicodeDecodeError) as exc:
        raise ReadError(
            f"cannot read balls {path}: {getattr(exc, 'strerror', None) or exc}"
        ) from None
    if line is None:
        raise ReadError(f"balls {path} is empty")
    delimiter = delimiter_of(line)
    cells = cells_of(line, delimiter)
    header = None
    if is_header(cells):
        header = tuple(cell.strip("\"'").strip().lower() for cell in cells)
        if not more:
            raise ReadError(
                f"balls {path}: line {number} is not all numbers (a header?) and no rows "
                "follow; columns are separated by commas, semicolons, tabs or spaces"
            )
    columns = csv_columns(path, header, len(cells), delimiter)
    skip = number if header is not None else number - 1
    return _CsvLayout(columns, skip, delimiter, number, len(cells), header)


def _csv_arrow(path: Path, chunk_rows: int):
    """pyarrow's streaming reader, strict: every column float64, no quotes, every row as wide
    as the first. Where it refuses a block, the rows from there on are read by
    :func:`_csv_numpy`, whose verdict (and message) is the whole reader's."""
    import pyarrow as pa
    from pyarrow import csv

    layout = _layout(path)
    if layout.delimiter is None:  # runs of spaces: pyarrow reads one delimiter character
        yield from _csv_numpy(path, chunk_rows)
        return
    columns = layout.columns
    with open(path, "rb") as handle:
        start = handle.read(3)
    options = csv.ReadOptions(
        block_size=_CSV_BLOCK_BYTES,
        column_names=[f"f{i}" for i in range(layout.width)],
        skip_rows=layout.skip,
        encoding="utf-8-sig" if start == b"\xef\xbb\xbf" else "utf8",
    )
    parse = csv.ParseOptions(delimiter=layout.delimiter, quote_char=False)
    # Every column float64 (a first block of integers made int64 columns that a later "0.5"
    # broke); no text stands for a missing value: "nan" and "inf" are numbers (then refused
    # as balls are), an empty cell is not a number.
    convert = csv.ConvertOptions(
        column_types={f"f{i}": pa.float64() for i in range(layout.width)},
        null_values=[],
        quoted_strings_can_be_null=False,
    )
    done = 0
    try:
        reader = csv.open_csv(
            path, read_options=options, parse_options=parse, convert_options=convert
        )
        for batch in reader:
            if batch.num_columns != layout.width or any(c.null_count for c in batch.columns):
                break
            table = np.column_stack(
                [batch.column(c).to_numpy(zero_copy_only=False) for c in columns]
            )
            for s in range(0, len(table), chunk_rows):
                yield table[s : s + chunk_rows, :3], table[s : s + chunk_rows, 3]
            done += len(table)
        else:
            return
    except (pa.ArrowInvalid, pa.ArrowTypeError, pa.ArrowNotImplementedError, OSError):
        pass
    yield from _csv_numpy(path, chunk_rows, done)


def _csv_numpy(path: Path, chunk_rows: int, done: int = 0):
    """The rows after the first ``done`` (parsed by :func:`parse_rows`, as the whole file is)."""
    layout = _layout(path)
    columns, what = layout.columns, f"balls {path}"
    try:
        with open(path, encoding="utf-8-sig") as handle:
            rows = itertools.islice(numbered_lines(handle), int(layout.header is not None), None)
            rows = itertools.islice(rows, done, None)
            while block := list(itertools.islice(rows, chunk_rows)):
                table = parse_rows(
                    block, layout.delimiter, what, layout.source, layout.width, layout.header
                )
                yield table[:, columns[:3]], table[:, columns[3]]
    except (OSError, UnicodeDecodeError) as exc:
        raise ReadError(
            f"cannot read balls {path}: {getattr(exc, 'strerror', None) or exc}"
        ) from None


def _float_column(column, path: Path) -> np.ndarray:
    import pyarrow as pa

    if not (pa.types.is_integer(column.type) or pa.types.is_floating(column.type)):
        if pa.types.is_null(column.type):  # an empty cell in every row of the block
            raise ReadError(f"balls {path}: not a table of numbers (empty cells)")
        raise ReadError(f"balls {path}: not a table of numbers (a column of {column.type})")
    if column.null_count:
        raise ReadError(f"balls {path}: not a table of numbers (empty cells)")
    return column.to_numpy(zero_copy_only=False).astype(float)


def _parquet(path: Path, chunk_rows: int):
    handle, columns = parquet_columns(path)  # refuses first when pyarrow is missing
    import pyarrow as pa

    try:
        for batch in handle.iter_batches(batch_size=chunk_rows, columns=columns):
            table = np.column_stack([_float_column(batch.column(i), path) for i in range(4)])
            yield table[:, :3], table[:, 3]
    except (pa.ArrowException, OSError) as exc:
        message = " ".join(str(exc).split())
        raise ReadError(f"cannot read balls {path}: {message}") from None
