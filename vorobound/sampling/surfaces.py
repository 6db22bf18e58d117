"""Surfaces for the sample-count estimates: area and ∫ dA / L² (L the local feature size)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError
from .mesh_io import read_sizing, read_triangle_mesh


@dataclass(frozen=True)
class Surface:
    """What the sample-count estimates need from a surface."""

    name: str
    area: float
    inv_lfs_sq_integral: float
    """∫ dA / L(x)²: dimensionless, the number of (L-sized) patches the surface holds."""
    lfs_min: float
    """Smallest local feature size on the surface (sets the smallest ball radius)."""
    exact: bool
    """True when the covering/packing counts are exact bounds (sphere), not estimates."""


def sphere(radius: float) -> Surface:
    """Sphere: L = R everywhere (the medial axis is the center)."""
    _positive(radius, "sphere radius")
    return Surface(f"sphere R={radius:g}", 4 * math.pi * radius**2, 4 * math.pi, radius, True)


def torus(major: float, minor: float) -> Surface:
    """Ring torus (R > r): L(φ) = min(r, R + r cos φ).

    The medial axis is the core circle (distance r) and the symmetry axis (distance
    R + r cos φ, the distance of the point from the axis); φ is the angle around the tube.
    """
    _positive(minor, "torus minor radius")
    if not major > minor:
        raise InputError(f"a ring torus needs R > r, got R={major:g}, r={minor:g}")
    from scipy.integrate import quad

    def integrand(phi):
        rho = major + minor * math.cos(phi)
        return minor * rho / min(minor, rho) ** 2

    # L switches from r to the axis distance where R + r cos φ = r.
    c = (minor - major) / minor
    breaks = [math.acos(c), 2 * math.pi - math.acos(c)] if c > -1 else []
    total, _ = quad(
        integrand, 0, 2 * math.pi, points=breaks or None, limit=200, epsabs=0, epsrel=1e-12
    )
    return Surface(
        f"torus R={major:g}, r={minor:g}",
        4 * math.pi**2 * major * minor,
        2 * math.pi * total,
        min(minor, major - minor),
        False,
    )


def planar_area(area: float, lfs: float) -> Surface:
    """A surface known only by its area, with constant local feature size."""
    _positive(area, "area")
    _positive(lfs, "lfs")
    return Surface(f"area {area:g}, L={lfs:g}", area, area / lfs**2, lfs, False)


def mesh_surface(path: Path, lfs: float | None = None, sizing: Path | None = None) -> Surface:
    """A triangle mesh read with meshio; L constant (``lfs``) or per vertex (``sizing`` CSV).

    With a sizing file each triangle uses the mean L of its vertices.
    """
    if (lfs is None) == (sizing is None):
        raise InputError("a mesh needs either a constant L or a sizing file (one L per vertex)")
    mesh = read_triangle_mesh(path)
    areas = mesh.triangle_areas()
    if sizing is not None:
        tri_lfs = read_sizing(sizing, len(mesh.points))[mesh.triangles].mean(axis=1)
    else:
        _positive(lfs, "lfs")
        tri_lfs = np.full(len(mesh.triangles), float(lfs))
    return surface_from_mesh_areas(mesh.name, areas, tri_lfs)


def surface_from_mesh_areas(name: str, areas: np.ndarray, tri_lfs: np.ndarray) -> Surface:
    """A :class:`Surface` from triangle areas and one L per triangle, refusing nonsense."""
    with np.errstate(all="ignore"):
        area = float(areas.sum())
        integral = float((areas / tri_lfs**2).sum())
    if not (math.isfinite(area) and area > 0):
        raise InputError(f"mesh {name}: its triangles have no (finite) area")
    if not (math.isfinite(integral) and integral > 0):
        raise InputError(f"mesh {name}: the integral of 1/L² over the surface is not finite")
    return Surface(f"mesh {name}", area, integral, float(tri_lfs.min()), False)


def _positive(value, name: str) -> None:
    if value is None or not (math.isfinite(value) and value > 0):
        raise InputError(f"{name} must be positive and finite, got {value}")
