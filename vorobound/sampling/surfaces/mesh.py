"""A triangle mesh as a surface to sample: L given per vertex, linear on each triangle."""

from __future__ import annotations

import numpy as np

from ...errors import InputError
from ..io.meshes import TriangleMesh
from ..sampler.lattice import SPARSITY_SLACK

MIN_AREA_RTOL = 1e-14
"""Triangles with area below MIN_AREA_RTOL·(longest edge)² are slivers of no area: skipped."""


class MeshShape:
    """The piecewise-linear surface of a triangle mesh with a local feature size per vertex.

    L is interpolated linearly on each triangle; ``lipschitz`` is the largest gradient of that
    interpolation (0 for a constant L), the λ the sampler's covering argument uses. It bounds
    changes of L along the mesh, not across it (``lipschitz_exact`` is False): a check
    measures the λ its sample has instead.
    """

    equal_radii_on_sphere = False
    lipschitz_exact = False

    def __init__(self, mesh: TriangleMesh, vertex_lfs: np.ndarray, lfs_source: str):
        vertex_lfs = np.asarray(vertex_lfs, dtype=float)
        if vertex_lfs.shape != (len(mesh.points),):
            raise InputError(f"mesh {mesh.name}: need one L per vertex, got {vertex_lfs.shape}")
        if not (np.isfinite(vertex_lfs).all() and (vertex_lfs > 0).all()):
            raise InputError(f"mesh {mesh.name}: L must be positive and finite at every vertex")
        corners, area2, longest, keep = _triangles_with_area(mesh)
        self.name = f"mesh {mesh.name} (L: {lfs_source})"
        self.lfs_source = lfs_source
        self.corners = corners[keep]
        self.corner_lfs = vertex_lfs[mesh.triangles[keep]]
        self.areas = 0.5 * area2[keep]
        self.longest = longest[keep]
        self.triangle_lipschitz = _gradient_norm(self.corners, self.corner_lfs)
        self.lipschitz = float(self.triangle_lipschitz.max())

    def counts(self):
        """Area and ∫ dA/L² (each triangle with the mean L of its corners), for the advice and
        the sampler's size check."""
        from dataclasses import replace

        from .analytic import surface_from_mesh_areas

        counts = surface_from_mesh_areas(self.name, self.areas, self.corner_lfs.mean(axis=1))
        return replace(counts, mesh_lattice=True)

    def lfs_at(self, triangle: np.ndarray, bary: np.ndarray, points=None) -> np.ndarray:
        """L at barycentric coordinates ``bary`` (n, 3) of the given triangles."""
        return (self.corner_lfs[triangle] * bary).sum(axis=1)

    def range_reach(self, eps: float, sigma: float) -> np.ndarray:
        """The lattice's alternative bound ε(L_min − σ'L_max) per triangle (may be ≤ 0)."""
        lo, hi = self.corner_lfs.min(axis=1), self.corner_lfs.max(axis=1)
        return eps * (lo - sigma * (1 + SPARSITY_SLACK) * hi)

    def at(self, triangle: np.ndarray, u: np.ndarray, v: np.ndarray):
        """Points and L at barycentric (1 − u − v, u, v) of the given triangles."""
        c, f = self.corners[triangle], self.corner_lfs[triangle]
        points = c[:, 0] + u[:, None] * (c[:, 1] - c[:, 0]) + v[:, None] * (c[:, 2] - c[:, 0])
        return points, f[:, 0] + u * (f[:, 1] - f[:, 0]) + v * (f[:, 2] - f[:, 0])

    def random_points(self, count: int, rng: np.random.Generator):
        """``count`` points uniform by area, and L there."""
        cumulative = np.cumsum(self.areas)
        triangle = np.searchsorted(cumulative, rng.uniform(0, cumulative[-1], count))
        triangle = np.minimum(triangle, len(self.areas) - 1)
        u, v = uniform_in_triangle(rng, count)
        return self.at(triangle, u, v)

    def project(self, points):
        """Not available for meshes (coverage then uses random probes only)."""
        return None


class FieldMeshShape:
    """The piecewise-linear surface of a triangle mesh with L a λ-Lipschitz function of space
    (the estimate of :func:`vorobound.sampling.lfs.estimate.estimate_lfs`, evaluated where needed).

    λ holds between any two points of space, so the sampler's covering argument and a check's
    Lipschitz condition use the same λ (``lipschitz_exact``). The estimate's feature corners
    and edges are sampled first.
    """

    equal_radii_on_sphere = False
    lipschitz_exact = True

    def __init__(self, estimate, lfs_source: str):
        mesh = estimate.mesh
        corners, area2, longest, keep = _triangles_with_area(mesh)
        self.estimate = estimate
        self.name = f"mesh {mesh.name} (L: {lfs_source})"
        self.lfs_source = lfs_source
        self.corners = corners[keep]
        self.areas = 0.5 * area2[keep]
        self.longest = longest[keep]
        self.lipschitz = float(estimate.lipschitz)
        self.triangle_lipschitz = np.full(len(self.areas), self.lipschitz)
        self.feature_segments = mesh.points[estimate.feature_segments]
        self.corner_points = mesh.points[estimate.feature_corners]

    def counts(self):
        """Area and ∫ dA/L² of the estimate (its face sites), for the advice and the sampler's
        size check."""
        from dataclasses import replace

        return replace(self.estimate.surface(), mesh_lattice=True)

    def lfs_of_points(self, points: np.ndarray) -> np.ndarray:
        return self.estimate.at(points)

    def lfs_at(self, triangle, bary, points) -> np.ndarray:
        return self.estimate.at(points)

    def range_reach(self, eps: float, sigma: float) -> np.ndarray:
        return np.zeros(len(self.areas))

    def random_points(self, count: int, rng: np.random.Generator):
        """``count`` points uniform by area, and L there."""
        cumulative = np.cumsum(self.areas)
        triangle = np.searchsorted(cumulative, rng.uniform(0, cumulative[-1], count))
        triangle = np.minimum(triangle, len(self.areas) - 1)
        u, v = uniform_in_triangle(rng, count)
        c = self.corners[triangle]
        points = c[:, 0] + u[:, None] * (c[:, 1] - c[:, 0]) + v[:, None] * (c[:, 2] - c[:, 0])
        return points, self.estimate.at(points)

    def project(self, points):
        """Not available for meshes (coverage then uses random probes only)."""
        return None


def _triangles_with_area(mesh: TriangleMesh):
    """(corners, twice the areas, longest edges, mask of triangles with area) of a mesh;
    refuses a mesh whose every triangle is degenerate."""
    corners = mesh.points[mesh.triangles]
    edge1, edge2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    area2 = np.linalg.norm(np.cross(edge1, edge2), axis=1)
    third = ((corners[:, 2] - corners[:, 1]) ** 2).sum(1)
    longest = np.sqrt(np.max([(edge1**2).sum(1), (edge2**2).sum(1), third], axis=0))
    keep = area2 > MIN_AREA_RTOL * longest**2
    if not keep.any():
        raise InputError(f"mesh {mesh.name}: every triangle is degenerate (no area)")
    return corners, area2, longest, keep


def points_on_mesh(mesh: TriangleMesh, count: int, rng: np.random.Generator) -> np.ndarray:
    """``count`` points uniform by area on a mesh's triangles."""
    areas = mesh.triangle_areas()
    triangle = rng.choice(len(areas), count, p=areas / areas.sum())
    u, v = uniform_in_triangle(rng, count)
    p = mesh.points[mesh.triangles[triangle]]
    return p[:, 0] + u[:, None] * (p[:, 1] - p[:, 0]) + v[:, None] * (p[:, 2] - p[:, 0])


def uniform_in_triangle(rng: np.random.Generator, count: int):
    """Barycentric (u, v), uniform over the triangle u, v ≥ 0, u + v ≤ 1."""
    u, v = rng.random(count), rng.random(count)
    flip = u + v > 1
    return np.where(flip, 1 - u, u), np.where(flip, 1 - v, v)


def _gradient_norm(corners: np.ndarray, values: np.ndarray) -> np.ndarray:
    """|∇f| of the linear interpolation of ``values`` on each triangle."""
    e1, e2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    d1, d2 = values[:, 1] - values[:, 0], values[:, 2] - values[:, 0]
    g11, g12, g22 = (e1 * e1).sum(1), (e1 * e2).sum(1), (e2 * e2).sum(1)
    det = g11 * g22 - g12 * g12
    # ∇f = α e1 + β e2 with the Gram system [g11 g12; g12 g22][α; β] = [d1; d2].
    alpha = (g22 * d1 - g12 * d2) / det
    beta = (g11 * d2 - g12 * d1) / det
    return np.sqrt(np.maximum(alpha * d1 + beta * d2, 0.0))
