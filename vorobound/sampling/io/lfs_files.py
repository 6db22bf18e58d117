"""Writing an L estimate: a sizing CSV (what ``--sizing`` reads) or a VTU for ParaView."""

from __future__ import annotations

from collections.abc import Callable
from functools import partial
from pathlib import Path

import numpy as np

from ...errors import InputError
from ...files import checked_destination, write_set
from ..lfs.result import LfsEstimate
from .balls import fill_vtu
from .columns import fill_csv

FORMATS = (".csv", ".vtu")
"""Output suffixes understood by :func:`write_lfs`."""


def checked_lfs_output(path: str | Path) -> Path:
    """``path`` if its suffix is one of :data:`FORMATS` (checked before any work is done)."""
    path = Path(path)
    if path.suffix.lower() not in FORMATS:
        raise InputError(f"cannot write {path}: the L file must end in .csv or .vtu")
    return checked_destination(path)


def lfs_writers(paths, estimate: LfsEstimate) -> dict[Path, Callable[[Path], None]]:
    """Writers for :func:`~vorobound.files.write_set`, one per output path (suffix checked)."""
    writers: dict[Path, Callable[[Path], None]] = {}
    for path in paths:
        path = checked_lfs_output(path)
        csv = path.suffix.lower() == ".csv"
        writers[path] = partial(_write_csv if csv else _write_vtu, estimate=estimate)
    return writers


def write_lfs(path: str | Path, estimate: LfsEstimate) -> Path:
    """Write the per-vertex L: CSV ``x,y,z,lfs`` (one row per vertex, in vertex order; its last
    column is what :func:`~vorobound.sampling.io.meshes.read_sizing` reads) or VTU (the mesh with
    point data ``lfs`` and ``sharp``, 1 on vertices of sharp edges). Written atomically."""
    return write_set(lfs_writers([path], estimate))[0]


def _write_csv(path: Path, estimate: LfsEstimate) -> None:
    x, y, z = estimate.mesh.points.T
    fill_csv(path, {"x": x, "y": y, "z": z, "lfs": estimate.lfs})


def _write_vtu(path: Path, estimate: LfsEstimate) -> None:
    mesh = estimate.mesh
    sharp = np.zeros(len(mesh.points), dtype=np.int8)
    sharp[estimate.sharp_edges.reshape(-1)] = 1
    cells = [("triangle", np.asarray(mesh.triangles))]
    fill_vtu(path, mesh.points, cells, {"lfs": estimate.lfs, "sharp": sharp})
