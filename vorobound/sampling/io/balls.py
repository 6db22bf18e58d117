"""Reading someone else's balls (CSV, NPZ or a meshio point cloud) and writing samples.

Accepted inputs, each giving centers x, y, z and radii r:

* CSV: columns x, y, z, r (a header naming them is optional; ``radius`` is accepted for r;
  vc_mesh's x1coord, x2coord, x3coord, x4coord header is read as x, y, z, r),
  separated by commas, semicolons or tabs (:mod:`.tables`);
* NPZ: arrays ``x``, ``y``, ``z`` and ``r`` (or ``radius``), or ``points`` (n, 3) with ``radii``;
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
from .columns import columns_writer
from .meshes import quiet_meshio
from .tables import DELIMITER_NAMES, read_number_table

RADIUS_NAMES = ("r", "radius", "radii")
"""Names under which a radius column or array is recognised."""
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
    suffix = path.suffix.lower()
    if suffix == ".csv":
        return _read_csv(path)
    if suffix == ".npz":
        return (*_read_npz(path), None)
    if suffix in PARQUET_SUFFIXES:
        return (*_read_parquet(path), None)
    return (*_read_meshio(path), None)


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
    columns = [0, 1, 2, 3]
    if table.header is not None and table.header[:4] == VOROCRUST_HEADER:
        pass  # vc_mesh's sphere files: x1coord..x4coord are x, y, z, r
    elif table.header is not None:
        header = table.header
        radius = next((name for name in RADIUS_NAMES if name in header), None)
        if radius is None or not {"x", "y", "z"} <= set(header):
            raise ReadError(
                f"balls {path}: the header must name x, y, z and r, got {', '.join(header)!r}"
            )
        columns = [header.index("x"), header.index("y"), header.index("z"), header.index(radius)]
    values = table.values
    if values.shape[1] <= max(columns):
        found = values.shape[1]
        how = (
            f"separated by {DELIMITER_NAMES[table.delimiter]}"
            if found > 1
            else "no comma, semicolon, tab or space between the numbers"
        )
        raise ReadError(f"balls {path}: need 4 columns x, y, z, r, got {found} ({how})")
    return values[:, columns[:3]], values[:, columns[3]], table.lines


def _read_npz(path: Path):
    import zipfile
    import zlib

    if not zipfile.is_zipfile(path):
        raise ReadError(f"cannot read balls {path}: {_not_npz(path)}")
    try:
        with np.load(path, allow_pickle=False) as data:
            arrays = {name: np.asarray(data[name]) for name in data.files}
    except (OSError, ValueError, EOFError, zipfile.BadZipFile, zlib.error) as exc:
        broken = isinstance(exc, EOFError | zipfile.BadZipFile | zlib.error)
        reason = "a damaged NPZ archive" if broken else " ".join(str(exc).split())
        raise ReadError(f"cannot read balls {path}: {reason}") from None
    radius = next((arrays[n] for n in RADIUS_NAMES if n in arrays), None)
    if {"x", "y", "z"} <= arrays.keys():
        columns = [_numeric(np.ravel(arrays[name]), path) for name in "xyz"]
        if len({len(column) for column in columns}) != 1:
            raise ReadError(
                f"balls {path}: arrays x, y and z have different lengths "
                f"{[len(c) for c in columns]}"
            )
        centers = np.column_stack(columns)
    else:
        centers = arrays.get("points", arrays.get("centers"))
    if centers is None or radius is None:
        raise ReadError(
            f"balls {path}: need arrays x, y, z and r (or points and radii), got {sorted(arrays)}"
        )
    return _numeric(centers, path), _numeric(radius, path).ravel()


NPY_MAGIC = b"\x93NUMPY"
"""The first bytes of a single-array .npy file (what np.save writes)."""


def _not_npz(path: Path) -> str:
    """Why a file named .npz is not an NPZ archive, for the error message."""
    try:
        with open(path, "rb") as handle:
            head = handle.read(len(NPY_MAGIC))
    except OSError as exc:
        return exc.strerror or str(exc)
    if head == NPY_MAGIC:
        return (
            "it is a single NPY array (np.save), not an NPZ archive of named arrays "
            "(np.savez with x, y, z and r)"
        )
    return "not an NPZ archive (a zip file of named arrays, as np.savez writes)"


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
