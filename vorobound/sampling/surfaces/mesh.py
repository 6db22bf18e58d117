"""Triangle meshes as surfaces to sample and to measure against: L given per vertex (linear on
each triangle) or estimated from the mesh; shapes of the protocol in :mod:`.base`.

Closest points come from libigl's AABB tree (``point_mesh_squared_distance``), the inside test
from the generalized winding number, normals from the closest triangle (oriented so that the
mesh encloses a positive volume).
"""

from __future__ import annotations

import numpy as np

from ...errors import InputError, warn_once
from ...mesh import TriangleMesh, fingerprint
from .base import SPARSITY_SLACK, ClosestPoints, ExpectedTopology, SurfaceCounts, mesh_counts

WINDING_INSIDE = 0.5
"""A point is inside a mesh where its generalized winding number exceeds this."""
EXACT_WINDING_TRIANGLES = 64
"""Meshes of up to this many triangles get the exact winding number (a sum over every
triangle: for the 12 triangles of a cube, 10 times faster than the fast approximation on 10⁶
points); larger ones libigl's fast winding number (a tree of expansions)."""
LIPSCHITZ_SLACK = 1e-6
"""A sizing may change by up to (1 + LIPSCHITZ_SLACK) per unit length before a warning."""


class _TriangleSurface:
    """What both mesh shapes share: the triangles with area, random points, closest points,
    the inside test and the topology. Subclasses give ``lfs_on(triangle, points)`` (L at
    points of the given triangles) and ``counts()``."""

    equal_radii_on_sphere = False

    def lfs_on(self, triangle: np.ndarray, points: np.ndarray) -> np.ndarray:
        """L at points of the given triangles (each subclass says how)."""
        raise NotImplementedError

    def _set_triangles(self, mesh: TriangleMesh) -> np.ndarray:
        """Keep the triangles with area; return which ones were kept."""
        corners, area2, longest, keep = _triangles_with_area(mesh)
        self.mesh_name = mesh.name
        self.corners = corners[keep]
        self.areas = 0.5 * area2[keep]
        self.longest = longest[keep]
        self.vertices, index = np.unique(self.corners.reshape(-1, 3), axis=0, return_inverse=True)
        self.triangles = index.reshape(-1, 3).astype(np.int64)
        c = self.corners
        normal = np.cross(c[:, 1] - c[:, 0], c[:, 2] - c[:, 0])
        volume = float(np.einsum("ij,ij->i", c[:, 0], normal).sum()) / 6
        self.normals = normal / np.linalg.norm(normal, axis=1, keepdims=True)
        if volume < 0:  # the triangles face inwards: outward normals point the other way
            self.normals = -self.normals
        return keep

    @property
    def expected_topology(self) -> ExpectedTopology | None:
        """The mesh's own topology, if it is a closed 2-manifold (else None)."""
        from ...mesh.topology import triangle_topology

        top = triangle_topology(self.vertices, self.triangles)
        if not top.closed_manifold:
            return None
        return ExpectedTopology(top.euler_characteristic, top.components, "the mesh")

    def random_points(self, count: int, rng: np.random.Generator):
        """``count`` points uniform by area, and L there."""
        points, triangle = self.random_points_on(count, rng)
        return points, self.lfs_on(triangle, points)

    def random_points_on(self, count: int, rng: np.random.Generator):
        """``count`` points uniform by area and their triangles (:meth:`random_points`
        without L; the same draws)."""
        cumulative = np.cumsum(self.areas)
        triangle = np.searchsorted(cumulative, rng.uniform(0, cumulative[-1], count))
        triangle = np.minimum(triangle, len(self.areas) - 1)
        u, v = uniform_in_triangle(rng, count)
        c = self.corners[triangle]
        points = c[:, 0] + u[:, None] * (c[:, 1] - c[:, 0]) + v[:, None] * (c[:, 2] - c[:, 0])
        return points, triangle

    def closest(self, points: np.ndarray) -> ClosestPoints:
        """Nearest points of the mesh (libigl's AABB tree), distance, normal and L there."""
        nearest, distance, triangle = self.nearest(points)
        return ClosestPoints(
            nearest, distance, self.normals[triangle], self.lfs_on(triangle, nearest)
        )

    def nearest(self, points: np.ndarray):
        """Nearest points of the mesh, their distance and triangle (:meth:`closest` without
        L)."""
        import igl

        query = np.ascontiguousarray(points, dtype=float)
        squared, triangle, nearest = igl.point_mesh_squared_distance(
            query, self.vertices, self.triangles
        )
        return nearest, np.sqrt(squared), triangle

    def project(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Nearest mesh points of ``points`` and L there."""
        found = self.closest(points)
        return found.points, found.lfs

    def inside(self, points: np.ndarray) -> np.ndarray:
        """True where the generalized winding number of the mesh exceeds 1/2."""
        import igl

        query = np.ascontiguousarray(points, dtype=float)
        if len(self.triangles) <= EXACT_WINDING_TRIANGLES:
            winding = igl.winding_number(self.vertices, self.triangles, query)
        else:
            winding = igl.fast_winding_number(self.vertices, self.triangles, query)
        return winding > WINDING_INSIDE


class MeshShape(_TriangleSurface):
    """The piecewise-linear surface of a triangle mesh with a local feature size per vertex.

    L is interpolated linearly on each triangle; ``lipschitz`` is the largest gradient of that
    interpolation (0 for a constant L), the λ the sampler's covering argument uses. It bounds
    changes of L along the mesh, not across it (``lipschitz_exact`` is False): a check
    measures the λ its sample has instead.
    """

    lipschitz_exact = False

    def __init__(self, mesh: TriangleMesh, vertex_lfs: np.ndarray, lfs_source: str):
        vertex_lfs = np.asarray(vertex_lfs, dtype=float)
        if vertex_lfs.shape != (len(mesh.points),):
            raise InputError(f"mesh {mesh.name}: need one L per vertex, got {vertex_lfs.shape}")
        if not (np.isfinite(vertex_lfs).all() and (vertex_lfs > 0).all()):
            raise InputError(f"mesh {mesh.name}: L must be positive and finite at every vertex")
        keep = self._set_triangles(mesh)
        self.name = f"mesh {mesh.name} (L: {lfs_source})"
        self.lfs_source = lfs_source
        self.corner_lfs = vertex_lfs[mesh.triangles[keep]]
        self.triangle_lipschitz = _gradient_norm(self.corners, self.corner_lfs)
        self.lipschitz = float(self.triangle_lipschitz.max())

    def counts(self) -> SurfaceCounts:
        """Area and ∫ dA/L² (each triangle with the mean L of its corners), for the advice and
        the sampler's size check."""
        return mesh_counts(self.mesh_name, self.areas, self.corner_lfs.mean(axis=1))

    def lfs_at(self, triangle: np.ndarray, bary: np.ndarray, points=None) -> np.ndarray:
        """L at barycentric coordinates ``bary`` (n, 3) of the given triangles."""
        return (self.corner_lfs[triangle] * bary).sum(axis=1)

    def lfs_on(self, triangle: np.ndarray, points: np.ndarray) -> np.ndarray:
        """L at points of the given triangles (linear interpolation of the corners)."""
        return self.lfs_at(triangle, _barycentric(self.corners[triangle], points))

    def range_reach(self, eps: float, sigma: float) -> np.ndarray:
        """The lattice's alternative bound ε(L_min − σ'L_max) per triangle (may be ≤ 0)."""
        lo, hi = self.corner_lfs.min(axis=1), self.corner_lfs.max(axis=1)
        return eps * (lo - sigma * (1 + SPARSITY_SLACK) * hi)


class FieldMeshShape(_TriangleSurface):
    """The piecewise-linear surface of a triangle mesh with L a λ-Lipschitz function of space
    (the estimate of :func:`vorobound.sampling.lfs.estimate.estimate_lfs`, evaluated where
    needed).

    λ holds between any two points of space, so the sampler's covering argument and a check's
    Lipschitz condition use the same λ (``lipschitz_exact``). The estimate's feature corners
    and edges are sampled first.
    """

    lipschitz_exact = True

    def __init__(self, estimate, lfs_source: str):
        mesh = estimate.mesh
        self._set_triangles(mesh)
        self.estimate = estimate
        self.name = f"mesh {mesh.name} (L: {lfs_source})"
        self.lfs_source = lfs_source
        self.lipschitz = float(estimate.lipschitz)
        self.triangle_lipschitz = np.full(len(self.areas), self.lipschitz)
        self.feature_segments = mesh.points[estimate.feature_segments]
        self.corner_points = mesh.points[estimate.feature_corners]

    def counts(self) -> SurfaceCounts:
        """Area and ∫ dA/L² of the estimate (its face sites), for the advice and the sampler's
        size check."""
        from dataclasses import replace

        return replace(self.estimate.surface(), mesh_lattice=True)

    def lfs_of_points(self, points: np.ndarray) -> np.ndarray:
        return self.estimate.at(points)

    def lfs_at(self, triangle, bary, points) -> np.ndarray:
        return self.estimate.at(points)

    def lfs_on(self, triangle: np.ndarray, points: np.ndarray) -> np.ndarray:
        """L at points (the estimate is a function of space)."""
        return self.estimate.at(points)

    def range_reach(self, eps: float, sigma: float) -> np.ndarray:
        return np.zeros(len(self.areas))


def _triangles_with_area(mesh: TriangleMesh):
    """(corners, twice the areas, longest edges, mask of triangles with area) of a mesh;
    refuses a mesh whose every triangle is degenerate."""
    area2, longest = mesh.shapes
    keep = mesh.with_area
    corners = mesh.points[mesh.triangles]
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


def _barycentric(corners: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Barycentric coordinates of points in their triangles (clipped to the triangle)."""
    e1, e2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    d = points - corners[:, 0]
    g11, g12, g22 = (e1 * e1).sum(1), (e1 * e2).sum(1), (e2 * e2).sum(1)
    r1, r2 = (d * e1).sum(1), (d * e2).sum(1)
    det = g11 * g22 - g12 * g12
    u = (g22 * r1 - g12 * r2) / det
    v = (g11 * r2 - g12 * r1) / det
    bary = np.clip(np.column_stack([1 - u - v, u, v]), 0, 1)
    return bary / bary.sum(axis=1, keepdims=True)


def warn_if_steep(mesh: TriangleMesh, vertex_lfs: np.ndarray, source: str) -> None:
    """Warn when a per-vertex L changes faster than 1 per unit length along an edge: a local
    feature size is 1-Lipschitz, and the bounds assume it."""
    ends = mesh.triangles[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    length = np.linalg.norm(mesh.points[ends[:, 0]] - mesh.points[ends[:, 1]], axis=1)
    change = np.abs(vertex_lfs[ends[:, 0]] - vertex_lfs[ends[:, 1]])
    with np.errstate(divide="ignore", invalid="ignore"):
        slope = np.where(length > 0, change / length, np.where(change > 0, np.inf, 0.0))
    steepest = float(slope.max())
    if steepest > 1 + LIPSCHITZ_SLACK:
        warn_once(
            f"{source}: L changes by up to {steepest:.3g} per unit length along a mesh edge; a "
            "local feature size is 1-Lipschitz and the bounds assume it (`vorobound lfs "
            "--lipschitz` gives such a sizing)",
            fingerprint(mesh.points, mesh.triangles),
            stacklevel=3,
        )
