"""NPZ ball files read a block at a time: the one NPZ reader of both the whole-file reader
(:func:`vorobound.sampling.io.balls.read_balls`) and the streamed one
(:func:`vorobound.sampling.io.stream.ball_chunks`).

Arrays ``x``, ``y``, ``z`` and ``r`` (or ``radius``/``radii``), each 1-D, or ``points`` (n, 3)
with ``radii`` (n,). Each ``.npy`` header is checked against its data: an array whose data is
shorter or longer than its header says is refused (a file with a lying header gave two
different ball sets whole and streamed, issue 34).
"""

from __future__ import annotations

import zipfile
import zlib
from collections.abc import Iterator
from pathlib import Path

import numpy as np

from ...errors import ReadError

RADIUS_NAMES = ("r", "radius", "radii")
"""Names under which a radius column or array is recognised."""
NPY_MAGIC = b"\x93NUMPY"
"""The first bytes of a single-array .npy file (what np.save writes)."""
_BROKEN = (OSError, EOFError, zipfile.BadZipFile, zlib.error)


def npz_chunks(path: Path, chunk_rows: int) -> Iterator[tuple[np.ndarray, np.ndarray]]:
    """(centers (m, 3), radii (m,)) of consecutive balls of an NPZ file, m ≤ ``chunk_rows``
    (unchecked values; float64)."""
    if not zipfile.is_zipfile(path):
        raise ReadError(f"cannot read balls {path}: {_not_npz(path)}")
    try:
        archive = zipfile.ZipFile(path)
    except (OSError, zipfile.BadZipFile):
        raise ReadError(f"cannot read balls {path}: {_not_npz(path)}") from None
    with archive:
        members = {name[:-4]: name for name in archive.namelist() if name.endswith(".npy")}
        radius = next((n for n in RADIUS_NAMES if n in members), None)
        if {"x", "y", "z"} <= members.keys() and radius is not None:
            streams = [_NpyStream(archive, members[n], path, 1) for n in ("x", "y", "z", radius)]
            if len({s.rows for s in streams}) != 1:
                raise ReadError(
                    f"balls {path}: arrays x, y, z and r have different lengths "
                    f"{[s.rows for s in streams]}"
                )
        else:
            points = members.get("points", members.get("centers"))
            if points is None or radius is None:
                raise ReadError(
                    f"balls {path}: need arrays x, y, z and r (or points and radii), got "
                    f"{sorted(members)}"
                )
            streams = [_NpyStream(archive, points, path, 3)]
            if streams[0].fortran:  # column after column: read each column as an array
                streams = [_NpyStream(archive, points, path, 3, column) for column in range(3)]
            streams.append(_NpyStream(archive, members[radius], path, 1))
            if streams[0].rows != streams[-1].rows:
                raise ReadError(
                    f"balls {path}: {streams[0].rows} points but {streams[-1].rows} radii"
                )
        for _ in range(0, streams[0].rows, chunk_rows):
            parts = [s.read(chunk_rows) for s in streams]
            if len(parts) == 4:
                yield np.column_stack(parts[:3]), parts[3]
            else:
                yield parts[0], parts[1]
        for stream in streams:
            stream.finish()


class _NpyStream:
    """Rows of one .npy member of a zip archive, read a block at a time; ``width`` is 1 for a
    1-D array, 3 for points (n, 3). ``column`` reads one column of Fortran-ordered points
    (stored column after column) as a 1-D array."""

    def __init__(
        self,
        archive: zipfile.ZipFile,
        member: str,
        path: Path,
        width: int,
        column: int | None = None,
    ):
        self.path, self.member = path, member
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
        except (*_BROKEN, ValueError) as exc:
            raise ReadError(f"cannot read balls {path}: {member}: {_why(exc)}") from None
        if dtype.kind not in "iuf" or dtype.hasobject:
            raise ReadError(f"balls {path}: values are not real numbers")
        expected = (shape[0],) if width == 1 else (shape[0], width) if shape else None
        if shape != expected:
            want = "1-D" if width == 1 else f"of shape (n, {width})"
            raise ReadError(
                f"balls {path}: {member[:-4]} has shape {tuple(shape)}; it must be {want} "
                "(one value per ball)"
            )
        self.rows, self.width, self.dtype, self.done = int(shape[0]), width, dtype, 0
        self.fortran, self.last = bool(fortran and width > 1 and shape[0] > 1), True
        if column is not None:
            self.width, self.last = 1, column == width - 1
            try:
                self.handle.seek(column * self.rows * dtype.itemsize, 1)
            except (*_BROKEN, ValueError) as exc:
                raise ReadError(f"cannot read balls {path}: {member}: {_why(exc)}") from None

    def read(self, rows: int) -> np.ndarray:
        rows = min(rows, self.rows - self.done)
        size = rows * self.width * self.dtype.itemsize
        try:
            data = self.handle.read(size)
        except _BROKEN as exc:
            raise ReadError(f"cannot read balls {self.path}: {_why(exc)}") from None
        if len(data) != size:
            held = self.done + len(data) // (self.width * self.dtype.itemsize)
            raise ReadError(
                f"balls {self.path}: the header of {self.member} says {self.rows:,} rows but "
                f"its data holds {held:,}"
            )
        self.done += rows
        values = np.frombuffer(data, dtype=self.dtype).astype(float)
        return values.reshape(-1, self.width) if self.width > 1 else values

    def finish(self) -> None:
        """Refuse data beyond what the header says."""
        if not self.last:  # a column of Fortran-ordered points: the next column follows
            self.handle.close()
            return
        try:
            extra = self.handle.read(1)
        except _BROKEN as exc:
            raise ReadError(f"cannot read balls {self.path}: {_why(exc)}") from None
        if extra:
            raise ReadError(
                f"balls {self.path}: the header of {self.member} says {self.rows:,} rows but "
                "its data holds more"
            )
        self.handle.close()


def _why(exc: BaseException) -> str:
    if isinstance(exc, EOFError | zipfile.BadZipFile | zlib.error):
        return "a damaged NPZ archive"
    return " ".join(str(exc).split()) or type(exc).__name__


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
