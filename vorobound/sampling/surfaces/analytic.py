"""Surfaces of revolution with their exact local feature size: the sphere and the ring torus.

Each is a shape of the protocol in :mod:`.base`: counts, random points, closest points,
inside test and topology, with L written once per shape (as a function of the distance to
the axis for the torus).
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod

import numpy as np

from ...errors import InputError
from .base import ClosestPoints, ExpectedTopology, SurfaceCounts, positive


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
    def closest(self, points: np.ndarray) -> ClosestPoints:
        """Nearest surface points of ``points`` (n, 3), distance, outward normal and L."""

    @abstractmethod
    def inside(self, points: np.ndarray) -> np.ndarray:
        """True for points (n, 3) the surface encloses."""

    @abstractmethod
    def counts(self) -> SurfaceCounts:
        """Area and ∫ dA/L² (the advisor's and the sampler's size estimates)."""

    expected_topology: ExpectedTopology

    def project(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Nearest surface points of ``points`` (n, 3) and L there."""
        found = self.closest(points)
        return found.points, found.lfs

    def embed(self, t, angle) -> np.ndarray:
        """Points (n, 3) at profile parameter ``t`` and rotation angle ``angle``."""
        rho, z = self.profile(t)
        return np.stack([rho * np.cos(angle), rho * np.sin(angle), z], axis=-1)

    def random_points(self, count: int, rng: np.random.Generator):
        """``count`` points uniform by area (rejection on dA ∝ ρ(t) dt dα) and L there."""
        t_lo, t_hi = self.t_range
        top = float(self.rho_max(t_lo, t_hi))
        kept: list[np.ndarray] = []
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
        positive(radius, "sphere radius")
        self.radius = float(radius)
        self.name = f"sphere R={radius:g}"
        self.profile_speed = self.radius
        self.expected_topology = ExpectedTopology(2, 1, "a sphere")

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

    def closest(self, points):
        norm = np.linalg.norm(points, axis=1)
        with np.errstate(all="ignore"):
            normal = points / norm[:, None]
        radius = self.radius
        return ClosestPoints(
            radius * normal, np.abs(norm - radius), normal, np.full(len(points), radius)
        )

    def inside(self, points):
        return np.linalg.norm(points, axis=1) < self.radius

    def counts(self) -> SurfaceCounts:
        """L = R everywhere: area 4πR², ∫ dA/L² = 4π (the counts are exact bounds)."""
        return SurfaceCounts(
            self.name, 4 * math.pi * self.radius**2, 4 * math.pi, self.radius, True
        )


class TorusShape(RevolutionShape):
    """Ring torus with radii R > r about the z axis: L = min(r, ρ), ρ the distance to the axis.

    The medial axis is the core circle (at distance r from every surface point) and the z axis
    (at distance ρ = R + r cos φ). Profile: t = φ ∈ [0, 2π), ρ = R + r cos φ, z = r sin φ.
    """

    t_range = (0.0, 2 * math.pi)

    def __init__(self, major: float, minor: float):
        positive(minor, "torus minor radius")
        if not (math.isfinite(major) and major > minor):
            raise InputError(f"a ring torus needs R > r, got R={major:g}, r={minor:g}")
        self.major, self.minor = float(major), float(minor)
        self.name = f"torus R={major:g}, r={minor:g}"
        self.profile_speed = self.minor
        self.expected_topology = ExpectedTopology(0, 1, "a torus")

    def lfs_of_rho(self, rho):
        """L at distance ρ from the axis: min(r, ρ), the distance to the nearer part of the
        medial axis (the core circle, at r, or the z axis, at ρ). The one formula of L."""
        return np.minimum(self.minor, rho)

    def profile(self, t):
        return self.major + self.minor * np.cos(t), self.minor * np.sin(t)

    def profile_lfs(self, t):
        return self.lfs_of_rho(self.profile(t)[0])

    def rho_max(self, t0, t1):
        return self.major + self.minor * _interval_max_cos(t0, t1)

    def lfs_min(self, t0, t1):
        return self.lfs_of_rho(self.major + self.minor * _interval_min_cos(t0, t1))

    def lfs_at(self, points):
        return self.lfs_of_rho(np.hypot(points[:, 0], points[:, 1]))

    def _tube(self, points):
        """Nearest point of the core circle, the offset from it, and its length."""
        angle = np.arctan2(points[:, 1], points[:, 0])
        core = self.major * np.column_stack([np.cos(angle), np.sin(angle), 0 * angle])
        offset = points - core
        return core, offset, np.linalg.norm(offset, axis=1)

    def closest(self, points):
        core, offset, length = self._tube(points)
        with np.errstate(all="ignore"):
            normal = offset / length[:, None]
        nearest = core + self.minor * normal
        return ClosestPoints(nearest, np.abs(length - self.minor), normal, self.lfs_at(nearest))

    def inside(self, points):
        return self._tube(points)[2] < self.minor

    def counts(self) -> SurfaceCounts:
        """Area 4π²Rr and ∫ dA/L² = 2π ∫ r·ρ(φ)/L(φ)² dφ (quadrature, split where L switches
        from r to the axis distance, R + r cos φ = r)."""
        from scipy.integrate import quad

        major, minor = self.major, self.minor

        def integrand(phi):
            rho = major + minor * math.cos(phi)
            return minor * rho / float(self.lfs_of_rho(rho)) ** 2

        c = (minor - major) / minor
        breaks = [math.acos(c), 2 * math.pi - math.acos(c)] if c > -1 else []
        total, _ = quad(
            integrand, 0, 2 * math.pi, points=breaks or None, limit=200, epsabs=0, epsrel=1e-12
        )
        return SurfaceCounts(
            self.name,
            4 * math.pi**2 * major * minor,
            2 * math.pi * total,
            float(self.lfs_min(0.0, 2 * math.pi)),
            False,
        )
