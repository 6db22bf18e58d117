"""Columns of numbers written to a file whose suffix says the format: the one path by which
vorobound writes tables (balls, L per vertex, per-triangle rows).

``.csv`` (a header row; integers as integers, floats with ``precision`` significant digits),
``.npz`` (one named array per column, ``np.savez_compressed``) and ``.parquet`` (one column
each, snappy-compressed; needs pyarrow). Each ``fill_*`` fills the path it is given, so
:func:`vorobound.files.write_set` makes it atomic.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np

from ...errors import InputError, MissingDependency

FULL_PRECISION = 17
"""Significant digits that round-trip every float64 (inputs such as ball files)."""
READABLE_PRECISION = 10
"""Significant digits of measured results written as text (per-triangle rows)."""


def fill_csv(path: Path, columns: dict[str, np.ndarray], precision: int = FULL_PRECISION) -> None:
    """A CSV with a header row; integer and boolean columns as integers."""
    names = list(columns)
    arrays = [np.asarray(columns[n]) for n in names]
    formats = ["%d" if a.dtype.kind in "iub" else f"%.{precision}g" for a in arrays]
    with open(path, "w", encoding="utf-8", newline="") as handle:
        handle.write(",".join(names) + "\n")
        if arrays and len(arrays[0]):
            table = np.column_stack([a.astype(float) for a in arrays])
            np.savetxt(handle, table, fmt=formats, delimiter=",")


def fill_npz(path: Path, columns: dict[str, np.ndarray], precision: int | None = None) -> None:
    """One named array per column (compressed); ``precision`` does not apply."""
    with open(path, "wb") as handle:
        arrays: dict[str, Any] = {name: np.asarray(a) for name, a in columns.items()}
        np.savez_compressed(handle, **arrays)


def fill_parquet(path: Path, columns: dict[str, np.ndarray], precision: int | None = None) -> None:
    """A Parquet file, one column each (needs pyarrow)."""
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        raise MissingDependency(
            f"cannot write {path}: Parquet needs pyarrow (pip install 'vorobound[parquet]')"
        ) from None
    table = pa.table({name: np.asarray(a) for name, a in columns.items()})
    pq.write_table(table, path, compression="snappy")


def fill_csv_chunks(
    path: Path, chunks: Callable[[], Iterator[dict[str, np.ndarray]]], precision=FULL_PRECISION
) -> None:
    """:func:`fill_csv` of the columns that ``chunks()`` yields block by block (float columns;
    the same text as the whole columns would give)."""
    with open(path, "w", encoding="utf-8", newline="") as handle:
        for number, block in enumerate(chunks()):
            if not number:
                handle.write(",".join(block) + "\n")
            if len(next(iter(block.values()))):
                table = np.column_stack([np.asarray(a, dtype=float) for a in block.values()])
                np.savetxt(handle, table, fmt=f"%.{precision}g", delimiter=",")


def fill_npz_chunks(
    path: Path, names: list[str], count: int, chunks: Callable[[], Iterator[dict]]
) -> None:
    """:func:`fill_npz` of float columns ``names`` of ``count`` rows that ``chunks()`` yields
    block by block: each member is written as the blocks come (one pass per column), so
    memory holds a block, and ``np.load`` reads the arrays :func:`fill_npz` would write."""
    import zipfile

    header = {"descr": np.lib.format.dtype_to_descr(np.dtype("<f8")), "fortran_order": False}
    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_DEFLATED, allowZip64=True) as archive:
        for name in names:
            with archive.open(f"{name}.npy", "w", force_zip64=True) as member:
                np.lib.format.write_array_header_1_0(member, {**header, "shape": (count,)})
                for block in chunks():
                    member.write(np.ascontiguousarray(block[name], dtype="<f8").tobytes())


FILLERS: dict[str, Callable] = {".csv": fill_csv, ".npz": fill_npz, ".parquet": fill_parquet}
"""The writer of each suffix."""


def table_format(path: str | Path, allowed: tuple[str, ...] = tuple(FILLERS)) -> str:
    """The suffix of ``path`` if it names a table format in ``allowed``; else InputError."""
    suffix = Path(path).suffix.lower()
    if suffix not in allowed:
        raise InputError(f"cannot write {path}: a table file must end in {', '.join(allowed)}")
    return suffix


def columns_writer(
    path: str | Path, columns: dict[str, np.ndarray], precision: int = FULL_PRECISION
) -> Callable[[Path], None]:
    """A writer for :func:`vorobound.files.write_set` of ``columns`` in ``path``'s format."""
    return partial(FILLERS[table_format(path)], columns=columns, precision=precision)
