"""The surface M̂ is measured against: closest points, outward normals, L there, which side a
point is on, and its topology.

Spheres and tori are exact (closest point in closed form, L exact). A mesh is the
piecewise-linear surface of its triangles: closest points through libigl's AABB tree
(``point_mesh_squared_distance``), sides by the generalized winding number, normals of the
closest triangle (oriented so that the mesh encloses a positive volume), and L as the mesh's own
L there (per-vertex L interpolated, or the estimate of ``vorobound lfs``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...errors import InputError
from ..surfaces.analytic import SphereShape, TorusShape
from .topology import triangle_topology

WINDING_INSIDE = 0.5
"""A point is inside a mesh where its generalized winding number exceeds this."""


@dataclass(frozen=True)
class ClosestPoints:
    """Closest surface points of query points."""

    points: np.ndarray
    """(n, 3) closest points on the surface."""
    distance: np.ndarray
    """(n,) distance from the query point."""
    normal: np.ndarray
    """(n, 3) outward unit normal of the surface there."""
    lfs: np.ndarray
    """(n,) L at the closest point."""


@dataclass(frozen=True)
class ExpectedTopology:
    """The topology M̂ should have: the surface's."""

    euler_characteristic: int
    components: int
    source: str


class ReferenceSurface:
    """A sampled surface as the measurements need it (see :func:`reference_surface`)."""

    name: str
    expected: ExpectedTopology | None

    def closest(self, points: np.ndarray) -> ClosestPoints:
        raise NotImplementedError

    def inside(self, points: np.ndarray) -> np.ndarray:
        raise NotImplementedError

    def random_points(self, count: int, rng: np.random.Generator):
        return self.shape.random_points(count, rng)


class _Sphere(ReferenceSurface):
    def __init__(self, shape: SphereShape):
        self.shape, self.name = shape, shape.name
        self.expected = ExpectedTopology(2, 1, "a sphere")

    def closest(self, points):
        norm = np.linalg.norm(points, axis=1)
        with np.errstate(all="ignore"):
            normal = points / norm[:, None]
        radius = self.shape.radius
        return ClosestPoints(
            radius * normal, np.abs(norm - radius), normal, np.full(len(points), radius)
        )

    def inside(self, points):
        return np.linalg.norm(points, axis=1) < self.shape.radius


class _Torus(ReferenceSurface):
    def __init__(self, shape: TorusShape):
        self.shape, self.name = shape, shape.name
        self.expected = ExpectedTopology(0, 1, "a torus")

    def _tube(self, points):
        """Offset from the nearest point of the core circle, and its length."""
        angle = np.arctan2(points[:, 1], points[:, 0])
        core = self.shape.major * np.column_stack([np.cos(angle), np.sin(angle), 0 * angle])
        offset = points - core
        return core, offset, np.linalg.norm(offset, axis=1)

    def closest(self, points):
        core, offset, length = self._tube(points)
        with np.errstate(all="ignore"):
            normal = offset / length[:, None]
        closest = core + self.shape.minor * normal
        return ClosestPoints(
            closest, np.abs(length - self.shape.minor), normal, self.shape.lfs_at(closest)
        )

    def inside(self, points):
        return self._tube(points)[2] < self.shape.minor


class _Mesh(ReferenceSurface):
    def __init__(self, shape):
        corners = np.asarray(shape.corners, dtype=float)
        self.shape, self.name = shape, shape.name
        self.vertices, index = np.unique(corners.reshape(-1, 3), axis=0, return_inverse=True)
        self.triangles = index.reshape(-1, 3).astype(np.int64)
        p = self.vertices[self.triangles]
        normal = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
        volume = float(np.einsum("ij,ij->i", p[:, 0], normal).sum()) / 6
        self.normals = normal / np.linalg.norm(normal, axis=1, keepdims=True)
        if volume < 0:  # the mesh's triangles face inwards: measure against outward normals
            self.normals = -self.normals
        topology = triangle_topology(self.vertices, self.triangles)
        self.expected = (
            ExpectedTopology(topology.euler_characteristic, topology.components, "the mesh")
            if topology.closed_manifold
            else None
        )

    def closest(self, points):
        import igl

        query = np.ascontiguousarray(points, dtype=float)
        squared, triangle, closest = igl.point_mesh_squared_distance(
            query, self.vertices, self.triangles
        )
        return ClosestPoints(
            closest, np.sqrt(squared), self.normals[triangle], self._lfs(triangle, closest)
        )

    def _lfs(self, triangle, closest):
        if hasattr(self.shape, "corner_lfs"):  # L per vertex, linear on each triangle
            corners = self.shape.corners[triangle]
            bary = _barycentric(corners, closest)
            return self.shape.lfs_at(triangle, bary)
        return self.shape.lfs_of_points(closest)

    def inside(self, points):
        import igl

        query = np.ascontiguousarray(points, dtype=float)
        return igl.fast_winding_number(self.vertices, self.triangles, query) > WINDING_INSIDE


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


def reference_surface(shape) -> ReferenceSurface:
    """The measurement view of a shape of :mod:`vorobound.sampling.surfaces`."""
    if isinstance(shape, SphereShape):
        return _Sphere(shape)
    if isinstance(shape, TorusShape):
        return _Torus(shape)
    if hasattr(shape, "corners"):
        return _Mesh(shape)
    raise InputError(f"cannot measure against {type(shape).__name__}: not a sphere, torus or mesh")
