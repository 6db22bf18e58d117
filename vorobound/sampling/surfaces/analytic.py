"""Surfaces for the sample-count estimates: area and ∫ dA / L² (L the local feature size)."""

from __future__ import annotations

import math
import warnings
from abc import ABC, abstractmethod
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ...errors import InputError, VoroboundWarning
from ..io.meshes import read_sizing, read_triangle_mesh

LIPSCHITZ_SLACK = 1e-6
"""A sizing may change by up to (1 + LIPSCHITZ_SLACK) per unit length before a warning."""


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
    feature_inv_lfs: float = 0.0
    """∫ ds / L along the sharp features (0 for a smooth surface): sets the feature balls."""
    mesh_lattice: bool = False
    """True when ``vorobound sample`` samples it with the mesh lattice
    (:mod:`vorobound.sampling.sampler.mesh_lattice`), whose size the advice then estimates."""


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
        vertex_lfs = read_sizing(sizing, len(mesh.points))
        _warn_if_steep(mesh, vertex_lfs, sizing)
        tri_lfs = vertex_lfs[mesh.triangles].mean(axis=1)
    else:
        _positive(lfs, "lfs")
        tri_lfs = np.full(len(mesh.triangles), float(lfs))
    return replace(surface_from_mesh_areas(mesh.name, areas, tri_lfs), mesh_lattice=True)


def _warn_if_steep(mesh, vertex_lfs: np.ndarray, sizing: Path) -> None:
    """Warn when the sizing changes faster than 1 per unit length along an edge: a local
    feature size is 1-Lipschitz, and the sampling bounds assume it."""
    ends = mesh.triangles[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    length = np.linalg.norm(mesh.points[ends[:, 0]] - mesh.points[ends[:, 1]], axis=1)
    change = np.abs(vertex_lfs[ends[:, 0]] - vertex_lfs[ends[:, 1]])
    with np.errstate(divide="ignore", invalid="ignore"):
        slope = np.where(length > 0, change / length, np.where(change > 0, np.inf, 0.0))
    steepest = float(slope.max())
    if steepest > 1 + LIPSCHITZ_SLACK:
        warnings.warn(
            f"sizing file {sizing.name}: L changes by up to {steepest:.3g} per unit length "
            "along a mesh edge; a local feature size is 1-Lipschitz and the bounds assume it "
            "(`vorobound lfs --lipschitz` gives such a sizing)",
            VoroboundWarning,
            stacklevel=3,
        )


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


# --- Surfaces of revolution with their exact local feature size, for the sampler -------------


class RevolutionShape(ABC):
    """A closed surface of revolution about the z axis, traced by a profile curve (ρ(t), z(t)).

    ``t`` runs over ``t_range`` at constant speed ``profile_speed`` (arc length per unit t);
    ρ is the distance to the axis. Subclasses give the profile and the exact local feature
    size L, which is 1-Lipschitz like every distance to a set.
    """

    lipschitz = 1.0
    """Lipschitz constant λ of L: |L(x) − L(y)| ≤ λ|x − y|."""
    lipschitz_exact = True
    """λ holds for every pair of points in space (L is a distance to a set)."""
    equal_radii_on_sphere = False
    """True for a sphere with constant L: its balls are cospherical with equal radii."""
    name: str
    t_range: tuple[float, float]
    profile_speed: float

    @abstractmethod
    def profile(self, t):
        """(ρ(t), z(t)): distance to the axis and height."""

    @abstractmethod
    def profile_lfs(self, t):
        """L on the circle of parameter t."""

    @abstractmethod
    def rho_max(self, t0, t1):
        """Largest ρ over each parameter interval [t0, t1]."""

    @abstractmethod
    def lfs_min(self, t0, t1):
        """Smallest L over each parameter interval [t0, t1]."""

    @abstractmethod
    def lfs_at(self, points: np.ndarray) -> np.ndarray:
        """The exact L at points (n, 3) of the surface."""

    @abstractmethod
    def project(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Nearest surface points of ``points`` (n, 3) and L there."""

    @abstractmethod
    def surface(self) -> Surface:
        """The advisor's description (area, ∫ dA/L²)."""

    def embed(self, t, angle) -> np.ndarray:
        """Points (n, 3) at profile parameter ``t`` and rotation angle ``angle``."""
        rho, z = self.profile(t)
        return np.stack([rho * np.cos(angle), rho * np.sin(angle), z], axis=-1)

    def random_points(self, count: int, rng: np.random.Generator):
        """``count`` points uniform by area (rejection on dA ∝ ρ(t) dt dα) and L there."""
        t_lo, t_hi = self.t_range
        top = float(self.rho_max(t_lo, t_hi))
        kept = []
        while sum(len(k) for k in kept) < count:
            t = rng.uniform(t_lo, t_hi, 2 * count)
            kept.append(t[rng.uniform(0, top, len(t)) < self.profile(t)[0]])
        t = np.concatenate(kept)[:count]
        points = self.embed(t, rng.uniform(0, 2 * math.pi, count))
        return points, self.profile_lfs(t)


def _interval_max_cos(t0, t1):
    """max cos over [t0, t1] ⊂ [0, 2π]: 1 when the interval holds 0 or 2π."""
    ends = np.maximum(np.cos(t0), np.cos(t1))
    return np.where((t0 <= 0) | (t1 >= 2 * math.pi), 1.0, ends)


def _interval_min_cos(t0, t1):
    """min cos over [t0, t1] ⊂ [0, 2π]: −1 when the interval holds π."""
    ends = np.minimum(np.cos(t0), np.cos(t1))
    return np.where((t0 <= math.pi) & (t1 >= math.pi), -1.0, ends)


class SphereShape(RevolutionShape):
    """Sphere of radius R about the origin: L = R (the medial axis is the center).

    Profile: t ∈ [0, π] the polar angle, ρ = R sin t, z = R cos t.
    """

    equal_radii_on_sphere = True
    t_range = (0.0, math.pi)

    def __init__(self, radius: float):
        _positive(radius, "sphere radius")
        self.radius = float(radius)
        self.name = f"sphere R={radius:g}"
        self.profile_speed = self.radius

    def profile(self, t):
        return self.radius * np.sin(t), self.radius * np.cos(t)

    def profile_lfs(self, t):
        return np.full(np.shape(t), self.radius)

    def rho_max(self, t0, t1):
        ends = np.maximum(np.sin(t0), np.sin(t1))
        return self.radius * np.where((t0 <= math.pi / 2) & (t1 >= math.pi / 2), 1.0, ends)

    def lfs_min(self, t0, t1):
        return np.full(np.shape(t0), self.radius)

    def lfs_at(self, points):
        return np.full(len(points), self.radius)

    def project(self, points):
        norm = np.linalg.norm(points, axis=1, keepdims=True)
        return self.radius * points / norm, np.full(len(points), self.radius)

    def surface(self) -> Surface:
        return sphere(self.radius)


class TorusShape(RevolutionShape):
    """Ring torus with radii R > r about the z axis: L = min(r, ρ), ρ the distance to the axis.

    The medial axis is the core circle (at distance r from every surface point) and the z axis
    (at distance ρ = R + r cos φ). Profile: t = φ ∈ [0, 2π), ρ = R + r cos φ, z = r sin φ.
    """

    t_range = (0.0, 2 * math.pi)

    def __init__(self, major: float, minor: float):
        _positive(minor, "torus minor radius")
        if not (math.isfinite(major) and major > minor):
            raise InputError(f"a ring torus needs R > r, got R={major:g}, r={minor:g}")
        self.major, self.minor = float(major), float(minor)
        self.name = f"torus R={major:g}, r={minor:g}"
        self.profile_speed = self.minor

    def profile(self, t):
        return self.major + self.minor * np.cos(t), self.minor * np.sin(t)

    def profile_lfs(self, t):
        return np.minimum(self.minor, self.major + self.minor * np.cos(t))

    def rho_max(self, t0, t1):
        return self.major + self.minor * _interval_max_cos(t0, t1)

    def lfs_min(self, t0, t1):
        return np.minimum(self.minor, self.major + self.minor * _interval_min_cos(t0, t1))

    def lfs_at(self, points):
        return np.minimum(self.minor, np.hypot(points[:, 0], points[:, 1]))

    def project(self, points):
        rho = np.hypot(points[:, 0], points[:, 1])
        tube = np.arctan2(points[:, 2], rho - self.major)
        return self.embed(tube, np.arctan2(points[:, 1], points[:, 0])), self.profile_lfs(tube)

    def surface(self) -> Surface:
        return torus(self.major, self.minor)
