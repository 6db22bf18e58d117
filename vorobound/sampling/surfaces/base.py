"""What every surface of the package is: the protocol the sampler, the checks, the advisor and
the reconstruction use, and the values it returns.

A *shape* (a sphere, a torus, a mesh with its L; :mod:`.analytic`, :mod:`.mesh`) provides

* ``name``, ``lipschitz`` (λ of its L), ``lipschitz_exact`` (λ holds between any two points of
  space, not only along the surface) and ``equal_radii_on_sphere``;
* ``counts()``: :class:`SurfaceCounts`, what the sample-count estimates need (area, ∫ dA/L²);
* ``random_points(count, rng)``: points uniform by area and L there;
* ``closest(points)``: :class:`ClosestPoints` (nearest surface points, distance, outward
  normal, L there); ``project(points)`` gives just the points and L;
* ``inside(points)``: which points the closed surface encloses;
* ``expected_topology``: :class:`ExpectedTopology` (None when the surface is not closed).

A surface known only by its area and L (:func:`planar_area`) has counts and nothing else.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...errors import InputError

SPARSITY_SLACK = 1e-12
"""Two samples conflict when closer than σε·min(L)·(1 + SPARSITY_SLACK): the margin makes the
realized sparsity ≥ 1 survive the rounding of a distance computed again later (the sampler's,
:mod:`vorobound.sampling.sampler.lattice`; a surface's ``range_reach`` uses it too)."""


@dataclass(frozen=True)
class SurfaceCounts:
    """What the sample-count estimates need from a surface."""

    name: str
    area: float
    inv_lfs_sq_integral: float
    """∫ dA / L(x)²: dimensionless, the number of (L-sized) patches the surface holds."""
    lfs_min: float
    """Smallest local feature size on the surface (sets the smallest ball radius)."""
    exact: bool
    """True when the covering/packing counts are exact bounds (sphere), not estimates."""
    feature_inv_lfs: float = 0.0
    """∫ ds / L along the sharp features (0 for a smooth surface): sets the feature balls."""
    mesh_lattice: bool = False
    """True when ``vorobound sample`` samples it with the mesh lattice
    (:mod:`vorobound.sampling.sampler.mesh_lattice`), whose size the advice then estimates."""


@dataclass(frozen=True)
class ClosestPoints:
    """Nearest surface points of query points."""

    points: np.ndarray
    """(n, 3) nearest points on the surface."""
    distance: np.ndarray
    """(n,) distance from the query point."""
    normal: np.ndarray
    """(n, 3) outward unit normal of the surface there."""
    lfs: np.ndarray
    """(n,) L at the nearest point."""


@dataclass(frozen=True)
class ExpectedTopology:
    """The topology of a closed surface (what a reconstruction of it should have)."""

    euler_characteristic: int
    components: int
    source: str


def planar_area(area: float, lfs: float) -> SurfaceCounts:
    """A surface known only by its area, with constant local feature size."""
    positive(area, "area")
    positive(lfs, "lfs")
    return SurfaceCounts(f"area {area:g}, L={lfs:g}", area, area / lfs**2, lfs, False)


def mesh_counts(name: str, areas: np.ndarray, tri_lfs: np.ndarray) -> SurfaceCounts:
    """:class:`SurfaceCounts` of a mesh from triangle areas and one L per triangle (sampled
    with the mesh lattice), refusing nonsense."""
    with np.errstate(all="ignore"):
        area = float(areas.sum())
        integral = float((areas / tri_lfs**2).sum())
    if not (math.isfinite(area) and area > 0):
        raise InputError(f"mesh {name}: its triangles have no (finite) area")
    if not (math.isfinite(integral) and integral > 0):
        raise InputError(f"mesh {name}: the integral of 1/L² over the surface is not finite")
    return SurfaceCounts(
        f"mesh {name}", area, integral, float(tri_lfs.min()), False, mesh_lattice=True
    )


def positive(value, name: str) -> None:
    """Raise unless ``value`` is a positive finite number."""
    if value is None or not (math.isfinite(value) and value > 0):
        raise InputError(f"{name} must be positive and finite, got {value}")
