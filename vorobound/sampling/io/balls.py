"""Reading someone else's balls (CSV, NPZ or a meshio point cloud) and writing samples.

Accepted inputs, each giving centers x, y, z and radii r:

* CSV: columns x, y, z, r (a header naming them is optional; ``radius`` is accepted for r;
  vc_mesh's x1coord, x2coord, x3coord, x4coord header is read as x, y, z, r), separated by
  commas, semicolons, tabs or spaces (:mod:`.tables`); a file with another suffix (``.txt``,
  ``.dat``) is read as one when its content is such a table;
* NPZ: 1-D arrays ``x``, ``y``, ``z`` and ``r`` (or ``radius``), or ``points`` (n, 3) with
  ``radii``, each header checked against its data (:mod:`.npz`);
* Parquet (``.parquet``, ``.pq``; needs pyarrow): columns ``x``, ``y``, ``z`` and ``r`` (or
  ``radius``);
* any point set meshio reads (VTU, VTK, PLY, ...) with a point-data array named ``radius``,
  ``radii`` or ``r``.

Every problem is a :class:`~vorobound.errors.ReadError` with one line; the values are then
checked by :func:`vorobound.sampling.balls.make_balls`.
"""

from __future__ import annotations

import importlib.util
from functools import partial
from pathlib import Path

import numpy as np

from ...errors import InputError, ReadError
from ...files import checked_destination, write_set
from ..balls import Balls, make_balls
from .columns import columns_writer, fill_csv_chunks, fill_npz_chunks
from .meshes import quiet_meshio
from .npz import RADIUS_NAMES, npz_chunks
from .tables import DELIMITER_NAMES, read_number_table

PARQUET_SUFFIXES = (".parquet", ".pq")
VOROCRUST_HEADER = ("x1coord", "x2coord", "x3coord", "x4coord")
"""The first four columns of vc_mesh's sphere files (surface_spheres.csv, ...): x, y, z, r."""


def read_balls(path: str | Path) -> Balls:
    """Balls from a CSV, NPZ, Parquet or meshio file (module docstring).

    Raises
    ------
    ReadError
        The file is missing, unreadable, or not a point set with radii.
    InputError
        NaN, infinite or non-positive values, duplicate centers, fewer than four balls.
    """
    centers, radii, lines = read_ball_arrays(path)
    return make_balls(centers, radii, f"balls {Path(path).name}", lines=lines)


def read_ball_arrays(path: str | Path):
    """The centers (n, 3) and radii (n,) in a ball file, unchecked (see :func:`read_balls`),
    and the file line of each row for a CSV (None for other formats)."""
    path = Path(path)
    if not path.exists():
        raise ReadError(f"cannot read balls {path}: no such file")
    if not path.is_file():
        raise ReadError(f"cannot read balls {path}: not a regular file")
    kind = ball_format(path)
    if kind == "csv":
        return _read_csv(path)
    if kind == "npz":
        return (*_read_npz(path), None)
    if kind == "parquet":
        return (*_read_parquet(path), None)
    return (*_read_meshio(path), None)


SNIFF_BYTES = 1 << 16
"""How much of a file with an unknown suffix is read to tell a table of numbers."""


def ball_format(path: Path) -> str:
    """ "csv", "npz", "parquet" or "meshio": from the suffix, or for any other suffix (a
    ``.txt`` of whitespace-separated numbers, a ``.dat``) from the content: a zip archive is
    NPZ, ``PAR1`` Parquet, and text whose first row is four or more numbers (or names x, y, z
    and r) is a table, read as a CSV is."""
    suffix = path.suffix.lower()
    if suffix == ".csv":
        return "csv"
    if suffix == ".npz":
        return "npz"
    if suffix in PARQUET_SUFFIXES:
        return "parquet"
    try:
        with open(path, "rb") as handle:
            head = handle.read(SNIFF_BYTES)
    except OSError:
        return "meshio"  # its reader names the problem
    if head.startswith(b"PK\x03\x04"):
        return "npz"
    if head.startswith(b"PAR1"):
        return "parquet"
    return "csv" if _number_table_head(head) else "meshio"


def _number_table_head(head: bytes) -> bool:
    """True when ``head`` starts a text table of balls: its first row (after blank and ``#``
    lines) is four or more numbers, or a header naming x, y, z and a radius."""
    from .tables import cells_of, delimiter_of, is_number

    try:
        text = head.decode("utf-8-sig")
    except UnicodeDecodeError:
        text = head[: head.rfind(b"\n") + 1].decode("utf-8-sig", errors="replace")
    rows = [
        line for line in text.splitlines() if line.strip() and not line.lstrip().startswith("#")
    ]
    if not rows:
        return False
    cells = cells_of(rows[0], delimiter_of(rows[0]))
    if len(cells) >= 4 and all(is_number(cell) for cell in cells):
        return True
    names = {cell.strip("\"'").lower() for cell in cells}
    return {"x", "y", "z"} <= names and bool(names & set(RADIUS_NAMES))


def pyarrow_available() -> bool:
    """True when pyarrow can be imported (Parquet files, fast CSV)."""
    return importlib.util.find_spec("pyarrow") is not None


def parquet_columns(path: Path):
    """The open Parquet file and its columns x, y, z, r (names in any case; r may be radius or
    radii)."""
    if not pyarrow_available():
        raise ReadError(
            f"cannot read balls {path}: Parquet files need pyarrow "
            "(pip install 'vorobound[parquet]')"
        )
    import pyarrow as pa
    import pyarrow.parquet as pq

    try:
        # Without pre-buffering, streaming a file holds about one column chunk at a time.
        handle = pq.ParquetFile(path, pre_buffer=False, buffer_size=1 << 22)
    except (pa.ArrowException, OSError) as exc:
        raise ReadError(f"cannot read balls {path}: {' '.join(str(exc).split())}") from None
    names = {name.lower(): name for name in handle.schema_arrow.names}
    radius = next((names[n] for n in RADIUS_NAMES if n in names), None)
    if radius is None or not {"x", "y", "z"} <= names.keys():
        raise ReadError(
            f"balls {path}: need columns x, y, z and r (or radius), got "
            f"{sorted(handle.schema_arrow.names)}"
        )
    return handle, [names["x"], names["y"], names["z"], radius]


def _read_parquet(path: Path):
    handle, columns = parquet_columns(path)  # refuses first when pyarrow is missing
    import pyarrow as pa

    try:
        table = handle.read(columns=columns)
        values = [table.column(name).to_numpy() for name in columns]
    except (pa.ArrowException, OSError) as exc:
        raise ReadError(f"cannot read balls {path}: {' '.join(str(exc).split())}") from None
    values = [_numeric(value, path) for value in values]  # before stacking: dates, bools
    return np.column_stack(values[:3]), values[3]


def _read_csv(path: Path):
    """Centers, radii and the file line of each ball (for messages about a row)."""
    table = read_number_table(path, "balls")
    columns = csv_columns(path, table.header, table.values.shape[1], table.delimiter)
    values = table.values
    return values[:, columns[:3]], values[:, columns[3]], table.lines


def csv_columns(path: Path, header, width: int, delimiter: str | None) -> list[int]:
    """The columns of x, y, z and r in a ball CSV of ``width`` columns with ``header`` (None:
    the first four): the one rule of the whole and the streamed reader."""
    columns = [0, 1, 2, 3]
    if header is not None and tuple(header[:4]) == VOROCRUST_HEADER:
        pass  # vc_mesh's sphere files: x1coord..x4coord are x, y, z, r
    elif header is not None:
        radius = next((name for name in RADIUS_NAMES if name in header), None)
        if radius is None or not {"x", "y", "z"} <= set(header):
            raise ReadError(
                f"balls {path}: the header must name x, y, z and r, got {', '.join(header)!r}"
            )
        columns = [header.index("x"), header.index("y"), header.index("z"), header.index(radius)]
    if width <= max(columns):
        how = (
            f"separated by {DELIMITER_NAMES[delimiter]}"
            if width > 1
            else "no comma, semicolon, tab or space between the numbers"
        )
        raise ReadError(f"balls {path}: need 4 columns x, y, z, r, got {width} ({how})")
    return columns


def _read_npz(path: Path):
    """Every ball of an NPZ file, by the reader the streamed check uses (:mod:`.npz`)."""
    parts = list(npz_chunks(path, 1 << 20))
    if not parts:
        return np.empty((0, 3)), np.empty(0)
    return np.concatenate([c for c, _ in parts]), np.concatenate([r for _, r in parts])


def _read_meshio(path: Path):
    import meshio

    mesh = quiet_meshio(lambda: meshio.read(path), path, "balls")
    radius = next((mesh.point_data[n] for n in RADIUS_NAMES if n in mesh.point_data), None)
    if radius is None:
        raise ReadError(
            f"balls {path}: a point set needs a point-data array named r, radius or radii "
            f"(found {sorted(mesh.point_data) or 'none'})"
        )
    return _numeric(mesh.points, path), _numeric(radius, path).ravel()


def _numeric(array, path: Path) -> np.ndarray:
    array = np.asarray(array)
    if array.dtype.kind not in "iuf":  # not bool, complex, text or objects
        raise ReadError(f"balls {path}: values are not real numbers")
    return array.astype(float)


def write_balls(path: str | Path, balls: Balls, point_data: dict[str, np.ndarray]) -> Path:
    """Write balls (centers, radii, extra per-ball arrays) as NPZ, VTU or CSV (columns x, y,
    z, r and one per extra array, full precision), atomically.

    All three formats read back with :func:`read_balls`.
    """
    path = checked_output(path)
    if path.suffix.lower() == ".vtu":
        cells = [("vertex", np.arange(len(balls)).reshape(-1, 1))]
        arrays = {"radius": balls.radii, **point_data}
        fill = partial(fill_vtu, points=balls.centers, cells=cells, point_data=arrays)
        return write_set({path: fill})[0]
    x, y, z = balls.centers.T
    radius = "r" if path.suffix.lower() == ".csv" else "radius"
    columns = {"x": x, "y": y, "z": z, radius: balls.radii, **point_data}
    return write_set({path: columns_writer(path, columns)})[0]


def write_balls_streamed(path: str | Path, count: int, blocks) -> Path:
    """:func:`write_balls` of ``count`` balls that ``blocks()`` yields block by block as
    (centers, radii, extra per-ball arrays), atomically. NPZ and CSV are written as the blocks
    come (memory: a block); a VTU is gathered whole first (meshio writes whole meshes)."""
    path = checked_output(path)
    suffix = path.suffix.lower()
    radius = "r" if suffix == ".csv" else "radius"

    def columns():
        for centers, radii, extra in blocks():
            x, y, z = np.asarray(centers, dtype=float).T
            yield {"x": x, "y": y, "z": z, radius: radii, **extra}

    if suffix == ".vtu":
        parts = list(blocks())
        extra = {name: np.concatenate([p[2][name] for p in parts]) for name in parts[0][2]}
        centers = np.concatenate([p[0] for p in parts])
        balls = Balls(centers, np.concatenate([p[1] for p in parts]))
        return write_balls(path, balls, extra)
    if suffix == ".csv":
        return write_set({path: partial(fill_csv_chunks, chunks=columns)})[0]
    names = list(next(columns()))
    return write_set({path: partial(fill_npz_chunks, names=names, count=count, chunks=columns)})[0]


def checked_output(path: str | Path) -> Path:
    """``path`` if it names a .npz, .vtu or .csv file (checked before any work is done)."""
    path = Path(path)
    if path.suffix.lower() not in (".npz", ".vtu", ".csv"):
        raise InputError(f"cannot write {path}: the sample file must end in .npz, .vtu or .csv")
    return checked_destination(path)


def fill_vtu(path: Path, points, cells, point_data: dict, cell_data: dict | None = None) -> None:
    """Write a VTU (XML, readable by ParaView and meshio) at ``path`` as it is: a writer for
    :func:`~vorobound.files.write_set`, which makes it atomic."""
    import meshio

    mesh = meshio.Mesh(points, cells, point_data=point_data, cell_data=cell_data or {})
    meshio.write(path, mesh, file_format="vtu")
