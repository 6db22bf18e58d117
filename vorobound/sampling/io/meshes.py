"""Reading the files users bring: surface meshes (through meshio; quads and polygons are split
into triangles, :mod:`.faces`) and per-vertex sizing CSVs.

meshio reports an unreadable file by printing to stdout and calling ``sys.exit(1)``; here its
output is captured and every failure becomes a :class:`~vorobound.errors.ReadError` with one
line of explanation, so a command's JSON on stdout stays clean.
"""

from __future__ import annotations

import contextlib
import io
import warnings
from pathlib import Path

import numpy as np

from ...checks import LFS_RANGE
from ...errors import ReadError, VoroboundWarning, warn_once
from ...mesh import MIN_AREA_RTOL, TriangleMesh, fingerprint, has_area, triangle_shapes

__all__ = [
    "MIN_AREA_RTOL",
    "TriangleMesh",
    "fingerprint",
    "format_by_content",
    "has_area",
    "read_sizing",
    "read_triangle_mesh",
    "triangle_shapes",
]


def quiet_meshio(call, path: Path, what: str):
    """Run a meshio ``call`` with its stdout/stderr chatter captured; failures raise ReadError."""
    sink = io.StringIO()
    try:
        with (
            contextlib.redirect_stdout(sink),
            contextlib.redirect_stderr(sink),
            warnings.catch_warnings(),
        ):
            warnings.simplefilter("ignore")
            return call()
    except SystemExit:
        said = " ".join(sink.getvalue().split())
        raise ReadError(
            f"cannot read {what} {path}: {said or 'meshio could not read it'}"
        ) from None
    except MemoryError:
        raise ReadError(f"cannot read {what} {path}: it does not fit in memory") from None
    except Exception as exc:  # meshio and its format readers raise many types
        message = " ".join(str(exc).split()) or type(exc).__name__
        raise ReadError(f"cannot read {what} {path}: {message}") from None


SUFFIX_FORMATS = {
    ".stl": "stl",
    ".obj": "obj",
    ".ply": "ply",
    ".off": "off",
    ".vtk": "vtk",
    ".vtu": "vtu",
    ".msh": "gmsh",
}
"""The meshio format of the suffixes whose content :func:`format_by_content` recognises."""
_OBJ_KEYWORDS = ("v", "vn", "vt", "f", "o", "g", "s", "l", "mtllib", "usemtl")


def format_by_content(path: Path) -> str | None:
    """The meshio format a mesh file holds, by its first bytes, where its suffix says another
    one (an OBJ named .stl was read as an STL of garbage, issue 34): None to let meshio go by
    the suffix. A one-line warning names the format read; a file named .stl that is neither
    ASCII nor binary STL is refused with the reason."""
    suffix_format = SUFFIX_FORMATS.get(path.suffix.lower())
    if suffix_format is None:
        return None
    try:
        with open(path, "rb") as handle:
            head = handle.read(4096)
        size = path.stat().st_size
    except OSError as exc:
        raise ReadError(f"cannot read mesh {path}: {exc.strerror or exc}") from None
    found = _sniff(head, size)
    if found is None or found == suffix_format:
        if suffix_format == "stl" and found is None:
            raise ReadError(
                f"cannot read mesh {path}: not an STL file (no 'solid' line, and its size is "
                "not that of a binary STL with the triangle count of its header)"
            )
        return None
    warnings.warn(
        f"mesh {path.name}: the file holds {found.upper()}, not what its suffix "
        f"{path.suffix} says; read as {found.upper()}",
        VoroboundWarning,
        stacklevel=3,
    )
    return found


def _sniff(head: bytes, size: int) -> str | None:
    """The format of a mesh file from its first bytes and size (None: not recognised)."""
    if len(head) >= 84 and size == 84 + 50 * int.from_bytes(head[80:84], "little"):
        return "stl"  # binary STL: 80-byte header, count, 50 bytes a triangle
    text = head.lstrip()
    if text.startswith(b"solid"):
        return "stl"
    if text.startswith(b"ply"):
        return "ply"
    if text[:4] in (b"OFF\n", b"OFF\r", b"OFF ") or text.startswith((b"COFF", b"NOFF")):
        return "off"
    if text.startswith(b"# vtk DataFile"):
        return "vtk"
    if text.startswith(b"<?xml") or text.startswith(b"<VTKFile"):
        return "vtu" if b"UnstructuredGrid" in head else None
    if text.startswith(b"$MeshFormat"):
        return "gmsh"
    try:
        lines = head.decode("utf-8").splitlines()[:-1] or head.decode("utf-8").splitlines()
    except UnicodeDecodeError:
        return None
    words = [line.split()[0] for line in lines if line.strip() and not line.startswith("#")]
    if words and all(word in _OBJ_KEYWORDS for word in words) and "v" in words:
        return "obj"
    return None


FACE_TYPES = ("triangle", "quad", "polygon")
"""meshio cell types read as surface faces; quads and polygons are split into triangles (with a
one-line warning). Other cells (vertices, lines, volumes) are ignored."""


def read_triangle_mesh(path: str | Path | TriangleMesh) -> TriangleMesh:
    """Read the faces of any mesh meshio understands (STL, OBJ, PLY, OFF, VTK, VTU, ...) as
    triangles: quadrilateral and polygonal faces are split (:mod:`.faces`) with a warning.
    A :class:`~vorobound.mesh.TriangleMesh` is returned as it is (the same object, with what
    is cached on it, such as its L estimate).

    Raises
    ------
    ReadError
        Unreadable file, no faces, points that are not 2-D or 3-D, non-finite coordinates,
        or faces that refer to missing vertices.
    """
    if isinstance(path, TriangleMesh):
        return path
    path = Path(path)
    if not path.exists():
        raise ReadError(f"cannot read mesh {path}: no such file")
    if not path.is_file():
        raise ReadError(f"cannot read mesh {path}: not a regular file")
    import meshio

    file_format = format_by_content(path)
    mesh = quiet_meshio(lambda: meshio.read(path, file_format=file_format), path, "mesh")
    points = np.asarray(mesh.points)
    if points.size == 0:
        raise ReadError(f"mesh {path} has no vertices (is it a mesh file?)")
    if points.ndim != 2 or points.shape[1] not in (2, 3) or points.shape[0] == 0:
        raise ReadError(f"mesh {path}: points must be 2-D or 3-D, got shape {points.shape}")
    if not np.issubdtype(points.dtype, np.number) or np.iscomplexobj(points):
        raise ReadError(f"mesh {path}: point coordinates are not real numbers")
    points = points.astype(float)
    if not np.isfinite(points).all():
        raise ReadError(f"mesh {path}: some point coordinates are NaN or infinite")
    if points.shape[1] == 2:
        points = np.column_stack([points, np.zeros(len(points))])
    low, high = LFS_RANGE
    size = float(np.ptp(points, axis=0).max())
    if float(np.abs(points).max()) > high or not size >= low:
        raise ReadError(
            f"mesh {path}: coordinates must lie within ±{high:g} and the mesh must be at least "
            f"{low:g} across (the supported range of lengths), got size {size:g}"
        )
    blocks = [np.asarray(block.data) for block in mesh.cells if block.type in FACE_TYPES]
    if not blocks or sum(len(b) for b in blocks) == 0:
        raise ReadError(f"mesh {path} has no triangles (nor quads or polygons to split)")
    from .faces import triangulate

    split = triangulate(points, [_face_indices(block, len(points), path) for block in blocks])
    note = split.note(path.name)
    if note is not None:
        warn_once(note, fingerprint(points))
    if len(split.triangles) == 0:
        raise ReadError(f"mesh {path} has no triangles (every face repeats a vertex)")
    return TriangleMesh(points, _without_repeats(points, split.triangles, path), path.name)


def _without_repeats(points: np.ndarray, triangles: np.ndarray, path: Path) -> np.ndarray:
    """The triangles with each set of three vertex positions once (a face listed twice, in
    either orientation, would count its area twice); a warning says how many were dropped."""
    _, position = np.unique(points, axis=0, return_inverse=True)
    key = np.sort(position.reshape(-1)[triangles], axis=1)
    _, first = np.unique(key, axis=0, return_index=True)
    repeats = len(triangles) - len(first)
    if repeats == 0:
        return triangles
    warn_once(
        f"mesh {path.name}: {repeats} triangles repeat another one (the same three vertex "
        "positions); each is counted once",
        fingerprint(points, triangles),
        stacklevel=3,
    )
    return triangles[np.sort(first)]


def _face_indices(block: np.ndarray, count: int, path: Path) -> np.ndarray:
    """The vertex indices of a block of faces as int64, each checked to name one of the
    ``count`` vertices before any conversion (indices beyond int64 arrive as floats or
    Python integers)."""
    if block.ndim != 2 or block.shape[1] < 3:
        raise ReadError(f"mesh {path}: faces must have at least 3 vertex indices each")
    if block.dtype.kind in "iu" and block.size:
        low, high = block.min(), block.max()
        if 0 <= low and high < count:
            return block.astype(np.int64)
    try:
        values = [int(value) for value in block.reshape(-1).tolist()]
    except (TypeError, ValueError, OverflowError):
        raise ReadError(
            f"mesh {path}: a face has a vertex index that is not a whole number"
        ) from None
    if block.dtype.kind == "f" and not np.array_equal(block, np.floor(block)):
        raise ReadError(f"mesh {path}: a face has a vertex index that is not a whole number")
    bad = next((value for value in values if not 0 <= value < count), None)
    if bad is not None:
        raise ReadError(
            f"mesh {path}: a face refers to vertex index {bad} (0-based) but the mesh has "
            f"{count} vertices"
        )
    return np.array(values, dtype=np.int64).reshape(-1, block.shape[1])


def read_sizing(path: str | Path, count: int) -> np.ndarray:
    """One positive, finite local feature size per vertex from a CSV (last column; a header
    line is allowed; commas, semicolons or tabs between columns, :mod:`.tables`)."""
    from .tables import read_number_table

    table = read_number_table(path, "sizing file")
    data = table.values[:, -1]
    if len(data) != count:
        raise ReadError(f"sizing file {path} has {len(data)} values for {count} vertices")
    low, high = LFS_RANGE
    bad = np.flatnonzero(~(np.isfinite(data) & (data >= low) & (data <= high)))
    if len(bad):
        raise ReadError(
            f"sizing file {path}, line {table.lines[bad[0]]}: {float(data[bad[0]])!r} is not a "
            f"local feature size in [{low:g}, {high:g}] (positive, finite, supported range; "
            f"{len(bad)} such rows)"
        )
    return data
