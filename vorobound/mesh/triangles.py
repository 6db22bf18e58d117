"""A triangle mesh with cached derived data (as trimesh caches it): each table is computed
the first time it is asked for and kept on the object. The arrays of a mesh are never changed
in place (a changed mesh is a new object, ``dataclasses.replace``), so the cache stays valid.

Estimates that a higher layer computes from the mesh (its local feature size L,
:func:`vorobound.sampling.lfs.estimate.estimate_lfs`) are kept in the generic cache
(:meth:`TriangleMesh.cached`), keyed by what they depend on besides the mesh: a command that
is given the same mesh object again reuses them.
"""

from __future__ import annotations

from collections.abc import Callable, Hashable
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any, TypeVar

import numpy as np

from .rows import unique_rows

MIN_AREA_RTOL = 1e-14
"""Triangles with area below MIN_AREA_RTOL·(longest edge)² are slivers of no area."""

T = TypeVar("T")


def triangle_shapes(points: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(twice the area, longest edge) of each triangle ``faces`` (m, 3) of ``points``."""
    corners = points[faces]
    first, second = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    third = corners[:, 2] - corners[:, 1]
    double_area = np.linalg.norm(np.cross(first, second), axis=1)
    longest_sq = np.max([(e * e).sum(axis=1) for e in (first, second, third)], axis=0)
    return double_area, np.sqrt(longest_sq)


def has_area(points: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """True for triangles with three distinct vertices and an area above MIN_AREA_RTOL·(longest
    edge)²: the one definition of a degenerate triangle."""
    return _with_area(faces, *triangle_shapes(points, faces))


def _with_area(faces: np.ndarray, double_area: np.ndarray, longest: np.ndarray) -> np.ndarray:
    repeated = (faces[:, 0] == faces[:, 1]) | (faces[:, 1] == faces[:, 2])
    repeated |= faces[:, 0] == faces[:, 2]
    return ~repeated & (double_area > MIN_AREA_RTOL * longest**2)


def fingerprint(points: np.ndarray, triangles: np.ndarray | None = None) -> str:
    """A digest of a mesh's vertices (and triangles): what a warning about the mesh is given
    once per process for (:func:`vorobound.errors.warn_once`)."""
    import hashlib

    digest = hashlib.blake2b(np.ascontiguousarray(points).tobytes(), digest_size=16)
    if triangles is not None:
        digest.update(np.ascontiguousarray(triangles).tobytes())
    return digest.hexdigest()


@dataclass(frozen=True)
class TriangleMesh:
    """Vertices (n, 3) and triangles (m, 3) of a surface mesh, checked for basic sanity, with
    derived data cached on first use (module docstring)."""

    points: np.ndarray
    triangles: np.ndarray
    name: str
    _cache: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def cached(self, key: Hashable, compute: Callable[[], T]) -> T:
        """``compute()`` the first time ``key`` is asked for, the same object afterwards: the
        cache of what higher layers derive from the mesh (an L estimate and its options)."""
        if key not in self._cache:
            self._cache[key] = compute()
        return self._cache[key]

    def triangle_areas(self) -> np.ndarray:
        """Area of each triangle (cross product of two edges)."""
        return 0.5 * self.shapes[0]

    @cached_property
    def shapes(self) -> tuple[np.ndarray, np.ndarray]:
        """(twice the area, longest edge) of each triangle (:func:`triangle_shapes`)."""
        return triangle_shapes(self.points, self.triangles)

    @cached_property
    def with_area(self) -> np.ndarray:
        """(m,) True for the triangles with area (:func:`has_area`)."""
        return _with_area(self.triangles, *self.shapes)

    @cached_property
    def edges(self) -> np.ndarray:
        """Distinct edges (e, 2), smaller index first, in lexicographic order."""
        pairs = np.sort(self.triangles[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
        return unique_rows(pairs)

    @cached_property
    def face_lengths(self) -> np.ndarray:
        """(m, 3) lengths of each triangle's edges: corner k to corner k + 1 (cyclically)."""
        corners = self.points[self.triangles]
        return np.linalg.norm(corners - np.roll(corners, -1, axis=1), axis=2)

    @cached_property
    def longest_edges(self) -> np.ndarray:
        """(m,) longest edge of each triangle."""
        return self.face_lengths.max(axis=1)

    @cached_property
    def vertex_longest_edge(self) -> np.ndarray:
        """(n,) longest edge at each vertex (0 for a vertex of no triangle)."""
        longest = np.zeros(len(self.points))
        for k in range(3):
            length = self.face_lengths[:, k]
            np.maximum.at(longest, self.triangles[:, k], length)
            np.maximum.at(longest, self.triangles[:, (k + 1) % 3], length)
        return longest

    @cached_property
    def vertex_face(self) -> np.ndarray:
        """(n,) one triangle of each vertex (the last one listed), −1 for a vertex of none."""
        owner = np.full(len(self.points), -1)
        owner[self.triangles.reshape(-1)] = np.repeat(np.arange(len(self.triangles)), 3)
        return owner

    def vertex_labels(self, face_labels: np.ndarray) -> np.ndarray:
        """(n,) the label of one triangle of each vertex (that of :attr:`vertex_face`), −1
        for a vertex of none; ``face_labels`` (m,) one label per triangle."""
        labels = np.full(len(self.points), -1)
        labels[self.triangles.reshape(-1)] = np.repeat(face_labels, 3)
        return labels

    def vertex_label_table(self, face_labels: np.ndarray) -> np.ndarray:
        """(n, k) the distinct labels of each vertex's triangles in increasing order, −1
        padded; ``face_labels`` (m,) one label per triangle."""
        pairs = unique_rows(np.c_[self.triangles.reshape(-1), np.repeat(face_labels, 3)])
        counts = np.bincount(pairs[:, 0], minlength=len(self.points))
        width = max(1, int(counts.max()))
        table = np.full((len(self.points), width), -1)
        starts = np.r_[0, np.cumsum(counts)[:-1]]
        slot = np.arange(len(pairs)) - starts[pairs[:, 0]]
        table[pairs[:, 0], slot] = pairs[:, 1]
        return table

    @cached_property
    def kdtree(self) -> Any:
        """A k-d tree of the vertices (scipy's cKDTree)."""
        from scipy.spatial import cKDTree

        return cKDTree(self.points)
