"""The surface a command is asked about, from the options every command spells alike:
``sphere`` (a radius), ``torus`` ((R, r)), ``mesh`` (a file) with optional ``lfs`` (a constant)
or ``sizing`` (a per-vertex file), and for the advisor ``area`` with ``lfs``.
"""

from __future__ import annotations

import os
from collections.abc import Sequence

from ..checks import LFS_RANGE, checked_length, checked_number
from ..errors import InputError

AREA_RANGE = (LFS_RANGE[0] ** 2, LFS_RANGE[1] ** 2)
"""Supported areas: squares of the supported lengths."""


def torus_radii(torus) -> tuple[float, float]:
    """``(R, r)`` as two checked lengths."""
    if isinstance(torus, str):
        torus = torus.split(",")
        try:
            torus = [float(x) for x in torus]
        except ValueError:
            raise InputError(f"torus needs two radii R,r, got {torus!r}") from None
    values = list(torus)
    if len(values) != 2:
        raise InputError(f"torus needs two radii (R, r), got {torus!r}")
    major, minor = (checked_length(v, "torus") for v in values)
    return major, minor


def _one_surface(**given) -> None:
    named = [name for name, value in given.items() if value is not None]
    if len(named) > 1:
        raise InputError("give one surface: " + ", ".join(given) + f" (got {', '.join(named)})")


def sample_shape(
    *,
    sphere: float | None = None,
    torus: Sequence[float] | None = None,
    mesh: str | os.PathLike | None = None,
    lfs: float | None = None,
    sizing: str | os.PathLike | None = None,
    required: bool = True,
    progress=None,
):
    """The surface to sample or measure against (None if none is given and none is
    required): a sphere, a torus, or a mesh with L constant (``lfs``), per vertex
    (``sizing``) or estimated from the mesh as by ``vorobound lfs``."""
    from ..sampling.surfaces.analytic import SphereShape, TorusShape

    _one_surface(sphere=sphere, torus=torus, mesh=mesh)
    if mesh is None and (lfs is not None or sizing is not None):
        raise InputError("lfs and sizing describe a mesh: use them with mesh")
    if sphere is not None:
        return SphereShape(checked_length(sphere, "sphere"))
    if torus is not None:
        return TorusShape(*torus_radii(torus))
    if mesh is not None:
        if lfs is not None and sizing is not None:
            raise InputError("give lfs or sizing for the mesh, not both")
        return _mesh_shape(
            mesh, None if lfs is None else checked_length(lfs, "lfs"), sizing, progress
        )
    if required:
        raise InputError("give a surface: sphere R, torus (R, r) or mesh FILE")
    return None


def _mesh_shape(path, lfs: float | None, sizing, progress):
    """The mesh with L constant, per vertex or estimated from the mesh."""
    import numpy as np

    from ..sampling.io.meshes import read_sizing, read_triangle_mesh
    from ..sampling.surfaces.mesh import FieldMeshShape, MeshShape

    mesh = read_triangle_mesh(path)
    if sizing is not None:
        name = os.path.basename(os.fspath(sizing))
        return MeshShape(mesh, read_sizing(sizing, len(mesh.points)), f"sizing {name}")
    if lfs is not None:
        return MeshShape(mesh, np.full(len(mesh.points), lfs), f"constant {lfs:g}")
    from ..sampling.lfs.estimate import estimate_lfs

    estimate = estimate_lfs(mesh, progress=progress)
    return FieldMeshShape(estimate, f"estimated, {estimate.lipschitz:g}-Lipschitz (docs/lfs.md)")


def count_surface(
    *,
    area: float | None = None,
    lfs: float | None = None,
    sphere: float | None = None,
    torus: Sequence[float] | None = None,
    mesh: str | os.PathLike | None = None,
    sizing: str | os.PathLike | None = None,
    progress=None,
):
    """The advisor's surface (area and ∫ dA/L²) and where its L comes from ("exact", "given",
    "sizing file", "estimated ..."); (None, None) when no surface is given."""
    from ..sampling.surfaces import analytic as surfaces

    _one_surface(area=area, sphere=sphere, torus=torus, mesh=mesh)
    if sizing is not None and mesh is None:
        raise InputError("sizing goes with mesh")
    if area is not None:
        if lfs is None:
            raise InputError("area needs lfs (the local feature size)")
        surface = surfaces.planar_area(
            checked_number(area, "area", *AREA_RANGE), checked_length(lfs, "lfs")
        )
        return surface, "given (lfs)"
    if sphere is not None:
        return surfaces.sphere(checked_length(sphere, "sphere")), "exact"
    if torus is not None:
        return surfaces.torus(*torus_radii(torus)), "exact"
    if mesh is not None and lfs is None and sizing is None:
        return _estimated_surface(mesh, progress)
    if mesh is not None:
        given = None if lfs is None else checked_length(lfs, "lfs")
        name = None if sizing is None else os.path.basename(os.fspath(sizing))
        source = "given (lfs)" if sizing is None else f"sizing file {name}"
        return surfaces.mesh_surface(mesh, given, sizing), source
    if lfs is not None:
        raise InputError("lfs describes a surface: use it with area or mesh")
    return None, None


def _estimated_surface(mesh, progress):
    """A mesh whose L nobody gave: estimate it (its warnings, e.g. about sharp edges, are
    issued as warnings), and say so in the output."""
    from ..sampling.io.meshes import read_triangle_mesh
    from ..sampling.lfs.estimate import estimate_lfs

    estimate = estimate_lfs(read_triangle_mesh(mesh), progress=progress)
    return estimate.surface(), (
        f"estimated from the mesh ({estimate.method}); numerical, the L that `vorobound lfs` "
        "reports and `vorobound sample --mesh` uses (accuracy on the test meshes: docs/lfs.md)"
    )
