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
import zipfile
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...errors import ReadError
from ..balls import checked_rows
from .balls import (
    PARQUET_SUFFIXES,
    RADIUS_NAMES,
    parquet_columns,
    pyarrow_available,
    read_ball_arrays,
)
from .tables import cells_of, delimiter_of, is_number

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
        chunks = _npz(path, chunk_rows)
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
    """Where the numbers of a ball CSV are, decided from its first line as read_balls does."""

    columns: list[int]
    """Columns of x, y, z and r."""
    skip: int
    """Lines before the first row of numbers (comments, blank lines and the header)."""
    delimiter: str | None
    """The delimiter (None: runs of spaces)."""
    rows: bool
    """Whether any line follows a header."""


def _header(path: Path) -> _CsvLayout:
    """The columns, delimiter and header of a ball CSV (as :func:`read_number_table` finds
    them: blank lines and lines starting with ``#`` are skipped)."""
    try:
        with open(path, encoding="utf-8-sig") as handle:
            lines = (
                (number, text)
                for number, text in enumerate(handle)
                if text.strip() and not text.lstrip().startswith("#")
            )
            number, line = next(lines, (0, None))
            more = next(lines, None) is not None
    except (OSError, UnicodeDecodeError) as exc:
        raise ReadError(
            f"cannot read balls {path}: {getattr(exc, 'strerror', None) or exc}"
        ) from None
    if line is None:
        raise ReadError(f"balls {path} is empty")
    delimiter = delimiter_of(line)
    cells = [cell.strip("\"'").strip().lower() for cell in cells_of(line, delimiter)]
    if all(is_number(cell) for cell in cells):
        return _CsvLayout([0, 1, 2, 3], number, delimiter, True)
    radius = next((name for name in RADIUS_NAMES if name in cells), None)
    if radius is None or not {"x", "y", "z"} <= set(cells):
        raise ReadError(f"balls {path}: the header must name x, y, z and r, got {line.strip()!r}")
    columns = [cells.index("x"), cells.index("y"), cells.index("z"), cells.index(radius)]
    return _CsvLayout(columns, number + 1, delimiter, more)


def _csv_arrow(path: Path, chunk_rows: int):
    import pyarrow as pa
    from pyarrow import csv

    layout = _header(path)
    if not layout.rows:
        return
    if layout.delimiter is None:  # runs of spaces: pyarrow reads one delimiter character
        yield from _csv_numpy(path, chunk_rows)
        return
    columns = layout.columns
    with open(path, "rb") as handle:
        start = handle.read(3)
    options = csv.ReadOptions(
        block_size=_CSV_BLOCK_BYTES,
        autogenerate_column_names=True,
        skip_rows=layout.skip,
        encoding="utf-8-sig" if start == b"\xef\xbb\xbf" else "utf8",
    )
    parse = csv.ParseOptions(delimiter=layout.delimiter)
    # No text stands for a missing value: "nan" and "inf" are numbers (then refused as balls
    # are), an empty cell is not a number.
    convert = csv.ConvertOptions(null_values=[], quoted_strings_can_be_null=False)
    try:
        reader = csv.open_csv(
            path, read_options=options, parse_options=parse, convert_options=convert
        )
        for batch in reader:
            if batch.num_columns <= max(columns):
                raise ReadError(f"balls {path}: need 4 columns x, y, z, r, got {batch.num_columns}")
            table = np.column_stack([_float_column(batch.column(c), path) for c in columns])
            for s in range(0, len(table), chunk_rows):
                yield table[s : s + chunk_rows, :3], table[s : s + chunk_rows, 3]
    except (pa.ArrowInvalid, pa.ArrowTypeError, OSError) as exc:
        message = " ".join(str(exc).split())
        raise ReadError(f"balls {path}: not a table of numbers ({message})") from None


def _float_column(column, path: Path) -> np.ndarray:
    import pyarrow as pa

    if not (pa.types.is_integer(column.type) or pa.types.is_floating(column.type)):
        if pa.types.is_null(column.type):  # an empty cell in every row of the block
            raise ReadError(f"balls {path}: not a table of numbers (empty cells)")
        raise ReadError(f"balls {path}: not a table of numbers (a column of {column.type})")
    if column.null_count:
        raise ReadError(f"balls {path}: not a table of numbers (empty cells)")
    return column.to_numpy(zero_copy_only=False).astype(float)


def _csv_numpy(path: Path, chunk_rows: int):
    layout = _header(path)
    columns = layout.columns
    try:
        with open(path, encoding="utf-8-sig") as handle:
            lines = (
                line
                for line in itertools.islice(handle, layout.skip, None)
                if line.strip() and not line.lstrip().startswith("#")
            )
            while True:
                block = list(itertools.islice(lines, chunk_rows))
                if not block:
                    return
                try:
                    table = np.loadtxt(block, delimiter=layout.delimiter, comments=None, ndmin=2)
                except ValueError as exc:
                    raise ReadError(f"balls {path}: not a table of numbers ({exc})") from None
                if table.shape[1] <= max(columns):
                    raise ReadError(
                        f"balls {path}: need 4 columns x, y, z, r, got {table.shape[1]}"
                    )
                yield table[:, columns[:3]], table[:, columns[3]]
    except (OSError, UnicodeDecodeError) as exc:
        raise ReadError(
            f"cannot read balls {path}: {getattr(exc, 'strerror', None) or exc}"
        ) from None


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


def _npz(path: Path, chunk_rows: int):
    try:
        archive = zipfile.ZipFile(path)
    except (OSError, zipfile.BadZipFile):
        raise ReadError(f"cannot read balls {path}: not an NPZ archive") from None
    with archive:
        members = {name[:-4]: name for name in archive.namelist() if name.endswith(".npy")}
        radius = next((n for n in RADIUS_NAMES if n in members), None)
        if {"x", "y", "z"} <= members.keys() and radius is not None:
            streams = [_NpyStream(archive, members[n], path) for n in ("x", "y", "z", radius)]
            if len({s.rows for s in streams}) != 1:
                raise ReadError(
                    f"balls {path}: arrays x, y, z and r have different lengths "
                    f"{[s.rows for s in streams]}"
                )
            for _ in range(0, streams[0].rows, chunk_rows):
                parts = [s.read(chunk_rows) for s in streams]
                yield np.column_stack(parts[:3]), parts[3]
            return
        points = members.get("points", members.get("centers"))
        radii = members.get(radius) if radius is not None else None
        if points is None or radii is None:
            raise ReadError(
                f"balls {path}: need arrays x, y, z and r (or points and radii), got "
                f"{sorted(members)}"
            )
        centers, radius_stream = _NpyStream(archive, points, path), _NpyStream(archive, radii, path)
        for _ in range(0, centers.rows, chunk_rows):
            yield centers.read(chunk_rows), radius_stream.read(chunk_rows)


class _NpyStream:
    """Rows of one .npy member of a zip archive, read a block at a time."""

    def __init__(self, archive: zipfile.ZipFile, member: str, path: Path):
        self.path = path
        try:
            self.handle = archive.open(member)
            version = np.lib.format.read_magic(self.handle)
            reader = {
                (1, 0): np.lib.format.read_array_header_1_0,
                (2, 0): np.lib.format.read_array_header_2_0,
            }.get(version)
            if reader is None:
                raise ValueError(f"unsupported .npy version {version}")
            shape, fortran, dtype = reader(self.handle)
        except (OSError, ValueError, zipfile.BadZipFile, EOFError) as exc:
            raise ReadError(f"cannot read balls {path}: {member}: {exc}") from None
        if dtype.kind not in "iuf" or dtype.hasobject:
            raise ReadError(f"balls {path}: values are not real numbers")
        self.width = int(np.prod(shape[1:])) if len(shape) > 1 else 1
        if fortran and len(shape) > 1 and shape[0] > 1:
            raise ReadError(
                f"balls {path}: {member} is stored in Fortran order; save it C-ordered "
                "(numpy.ascontiguousarray) to stream it"
            )
        self.rows = int(shape[0]) if shape else 1
        self.dtype, self.shape = dtype, shape

    def read(self, rows: int) -> np.ndarray:
        count = rows * self.width
        data = self.handle.read(count * self.dtype.itemsize)
        values = np.frombuffer(data, dtype=self.dtype)
        if len(values) % self.width:
            raise ReadError(f"cannot read balls {self.path}: an array ends early")
        values = values.astype(float)
        return values.reshape(-1, self.width) if len(self.shape) > 1 else values
