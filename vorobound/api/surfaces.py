"""The surface a command is asked about, from the options every command spells alike:
``sphere`` (a radius), ``torus`` ((R, r)), ``mesh`` (a file) with optional ``lfs`` (a constant)
or ``sizing`` (a per-vertex file), and for the advisor ``area`` with ``lfs``.
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..checks import LFS_RANGE, checked_length, checked_number
from ..errors import InputError

if TYPE_CHECKING:
    from ..mesh import TriangleMesh

AREA_RANGE = (LFS_RANGE[0] ** 2, LFS_RANGE[1] ** 2)
"""Supported areas: squares of the supported lengths."""


def torus_radii(torus) -> tuple[float, float]:
    """``(R, r)`` as two checked lengths (a third entry, the axis, is :func:`torus_axis`'s)."""
    if isinstance(torus, str):
        torus = torus.split(",")
        torus = torus[:2] if len(torus) == 3 and torus[2].strip().lower() in "xyz" else torus
        try:
            torus = [float(x) for x in torus]
        except ValueError:
            raise InputError(f"torus needs two radii R,r, got {torus!r}") from None
    values = list(torus)
    if len(values) == 3 and isinstance(values[2], str):
        values = values[:2]
    if len(values) != 2:
        raise InputError(f"torus needs two radii (R, r), got {torus!r}")
    major, minor = (checked_length(v, "torus") for v in values)
    return major, minor


def torus_axis(torus) -> str:
    """The axis of ``torus`` = (R, r) or (R, r, axis): z unless a third entry names x or y."""
    from ..sampling.surfaces.axis import checked_axis

    values = torus.split(",") if isinstance(torus, str) else list(torus)
    return checked_axis(values[2]) if len(values) == 3 else "z"


def _one_surface(**given) -> None:
    named = [name for name, value in given.items() if value is not None]
    if len(named) > 1:
        raise InputError("give one surface: " + ", ".join(given) + f" (got {', '.join(named)})")


@dataclass(frozen=True)
class Surface:
    """The surface a command is asked about, as every command and API function takes it: one
    of ``sphere``, ``torus``, ``mesh``, with ``lfs`` or ``sizing`` for a mesh (the advisor also
    takes ``lfs`` with an area). Checked where it is turned into a shape."""

    sphere: float | None = None
    torus: Sequence[float] | str | None = None
    mesh: str | os.PathLike | TriangleMesh | None = None
    lfs: float | None = None
    sizing: str | os.PathLike | None = None

    def shape(self, *, required: bool = True, instead: tuple[str, ...] = (), progress=None):
        """This surface as a shape (:func:`sample_shape`)."""
        return sample_shape(self, required=required, instead=instead, progress=progress)


SURFACE_FIELDS = tuple(f.name for f in dataclasses.fields(Surface))
"""sphere, torus, mesh, lfs, sizing: the surface keywords every command takes."""


def sample_shape(
    surface: Surface, *, required: bool = True, instead: tuple[str, ...] = (), progress=None
):
    """The surface to sample or measure against (None if none is given and none is
    required): a sphere, a torus, or a mesh with L constant (``lfs``), per vertex
    (``sizing``) or estimated from the mesh as by ``vorobound lfs``. A shape of the protocol
    in :mod:`vorobound.sampling.surfaces.base`. ``instead`` names the inputs that may replace a
    surface, for the message when none is given. ``torus`` may name its axis, (R, r, "y"),
    where the surface only measures (not ``required``, the sampling commands' case)."""
    sphere, torus, mesh, lfs, sizing = (getattr(surface, k) for k in SURFACE_FIELDS)
    from ..sampling.surfaces.analytic import SphereShape, TorusShape

    _one_surface(sphere=sphere, torus=torus, mesh=mesh)
    if mesh is None and (lfs is not None or sizing is not None):
        raise InputError("lfs and sizing describe a mesh: use them with mesh")
    if sphere is not None:
        return SphereShape(checked_length(sphere, "sphere"))
    if torus is not None:
        shape = TorusShape(*torus_radii(torus))
        axis = torus_axis(torus)
        if axis == "z":
            return shape
        if required:
            raise InputError(
                f"a torus about the {axis} axis is for measuring balls or seeds; samples are "
                "made about z (permute the columns), or give the part as --mesh"
            )
        from ..sampling.surfaces.axis import AxisShape

        return AxisShape(shape, axis)
    if mesh is not None:
        if lfs is not None and sizing is not None:
            raise InputError("give lfs or sizing for the mesh, not both")
        given = None if lfs is None else checked_length(lfs, "lfs")
        return _mesh_shape(mesh, given, sizing, progress)
    if required:
        others = "".join(f" or {name}" for name in instead)
        raise InputError(f"give a surface (sphere R, torus (R, r) or mesh FILE){others}")
    return None


def _mesh_shape(path, lfs: float | None, sizing, progress):
    """The mesh with L constant, per vertex (a sizing file, warned about when it is steeper
    than a local feature size can be) or estimated from the mesh."""
    import numpy as np

    from ..sampling.io.meshes import read_sizing, read_triangle_mesh
    from ..sampling.surfaces.mesh import FieldMeshShape, MeshShape, warn_if_steep

    mesh = read_triangle_mesh(path)
    if sizing is not None:
        name = os.path.basename(os.fspath(sizing))
        vertex_lfs = read_sizing(sizing, len(mesh.points))
        warn_if_steep(mesh, vertex_lfs, f"sizing file {name}")
        return MeshShape(mesh, vertex_lfs, f"sizing {name}")
    if lfs is not None:
        return MeshShape(mesh, np.full(len(mesh.points), lfs), f"constant {lfs:g}")
    from ..sampling.lfs.estimate import estimate_lfs

    estimate = estimate_lfs(mesh, progress=progress)
    return FieldMeshShape(estimate, f"estimated, {estimate.lipschitz:g}-Lipschitz (docs/lfs.md)")


ESTIMATED = (
    "estimated from the mesh ({method}); numerical, the L that `vorobound lfs` reports and "
    "`vorobound sample --mesh` uses (accuracy on the test meshes: docs/lfs.md)"
)


def count_surface(
    surface: Surface | None = None, *, area: float | None = None, progress=None, **fields
):
    """The advisor's view of the surface (a :class:`Surface`, or its ``fields`` as keywords),
    its :class:`~vorobound.sampling.surfaces.base.SurfaceCounts` (area and ∫ dA/L²), and where
    its L comes from ("exact", "given", "sizing file", "estimated ..."); (None, None) when no
    surface is given."""
    from ..sampling.surfaces.base import planar_area

    surface = Surface(**fields) if surface is None else surface
    sphere, torus, mesh, lfs, sizing = (getattr(surface, k) for k in SURFACE_FIELDS)
    _one_surface(area=area, sphere=sphere, torus=torus, mesh=mesh)
    if sizing is not None and mesh is None:
        raise InputError("sizing goes with mesh")
    if area is not None:
        if lfs is None:
            raise InputError("area needs lfs (the local feature size)")
        counts = planar_area(checked_number(area, "area", *AREA_RANGE), checked_length(lfs, "lfs"))
        return counts, "given (lfs)"
    if lfs is not None and mesh is None:
        raise InputError("lfs describes a surface: use it with area or mesh")
    shape = surface.shape(required=False, progress=progress)
    if shape is None:
        return None, None
    if mesh is None:
        source = "exact"
    elif sizing is not None:
        source = f"sizing file {os.path.basename(os.fspath(sizing))}"
    elif lfs is not None:
        source = "given (lfs)"
    else:
        source = ESTIMATED.format(method=shape.estimate.method)
    return shape.counts(), source
