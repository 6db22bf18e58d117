"""Extra surface samples at edge midpoints, placed on a smooth surface fitted to the vertices.

A point in the middle of a flat triangle lies off the smooth surface by about h²/(8L) (edge
length h), enough to shrink the empty balls of its neighbours by a fraction of order one
(docs/lfs.md). Here each vertex v gets a quartic height function z = f(x, y) over its tangent
plane, fitted by weighted least squares to the vertices two edges away or closer and passing
through v; its error is of order h⁵/L⁴ instead of the flat triangle's h²/L (measured in
docs/lfs.md: about 2·10⁻⁵ h at h ≈ L/5). The midpoint of an edge (a, b) is the mean of the
chord midpoint lifted onto the fits of a and of b along their normals. The fit uses vertex
positions only; the normal merely orients its frame, so first-order errors of vertex normals
on irregular meshes (which put PN-triangle points off the surface) do not matter.

A fit is used only where it can be trusted: its support (the two-ring) touches no sharp,
boundary or non-manifold edge, it has enough points, its least-squares problem is well
conditioned, and the normal lines of its support stay within :data:`GRAPH_ANGLE` of v's (the
surface is a graph over the tangent plane). An edge gets a midpoint only when both its ends
have such a fit and the two lifted points agree to :data:`AGREE_RTOL` of the edge length. So no
point is placed across or next to a sharp edge: the mesh there stays as it is.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .mesh_quality import PreparedMesh

FIT_DEGREE = 4
"""Total degree of each vertex's height function (terms of degree 1..FIT_DEGREE; the constant
is 0 because the fit passes through its vertex)."""
_TERMS = [(i, total - i) for total in range(1, FIT_DEGREE + 1) for i in range(total + 1)]
FIT_RINGS = 2
"""A vertex's fit uses the vertices at most FIT_RINGS edges away."""
FIT_WIDTH = 1.5
"""Width of the Gaussian weight exp(−(d/(FIT_WIDTH·h))²) of a support point at tangential
distance d; h is the vertex's longest edge."""
MAX_SUPPORT = 40
"""At most the MAX_SUPPORT nearest vertices of the two-ring enter a fit (bounds the memory of
very high valences)."""
MIN_SUPPORT = len(_TERMS) + 1
"""A fit needs this many support vertices besides its own."""
COND_MAX = 1e10
"""A fit whose normal matrix (in units of h) has a larger condition number is not used."""
GRAPH_ANGLE = 60.0
"""Degrees: a support vertex whose normal line is farther from v's makes v's fit unusable (the
surface does not look like a graph over v's tangent plane there)."""
AGREE_RTOL = 1e-2
"""The fits of an edge's two ends must lift its midpoint to within AGREE_RTOL·(edge length)."""
CHUNK = 4096
"""Vertices fitted together (bounds the memory to CHUNK·MAX_SUPPORT·14 numbers)."""


@dataclass(frozen=True)
class EdgeSamples:
    """Points added at edge midpoints on the fitted surface, in the prepared mesh's units."""

    points: np.ndarray
    """Added points (m, 3)."""
    normals: np.ndarray
    """A unit normal line per added point (sign arbitrary)."""
    edges: np.ndarray
    """The edge (m, 2) of each added point (indices into the prepared points)."""
    eligible: int
    """Edges that could get a midpoint (both fits usable, fits agree)."""


def edge_midpoints(
    prepared: PreparedMesh, normals: np.ndarray, excluded: np.ndarray, budget: int
) -> EdgeSamples:
    """Up to ``budget`` edge midpoints on the fitted surface, longest edges first.

    Parameters
    ----------
    prepared : PreparedMesh
        The mesh (vertices in units of its bounding-box diagonal).
    normals : ndarray (n, 3)
        Vertex normal lines (:func:`~vorobound.sampling.lfs.mesh_quality.vertex_normals`).
    excluded : ndarray of bool (e,)
        Edges near which nothing is fitted (sharp, boundary, non-manifold).
    budget : int
        Largest number of points to add (≤ 0: none).

    Returns
    -------
    EdgeSamples
    """
    edges = prepared.edges
    if budget <= 0 or len(edges) == 0:
        empty = np.zeros((0, 3))
        return EdgeSamples(empty, empty, np.zeros((0, 2), dtype=np.int64), 0)
    fits = _VertexFits(prepared, normals, excluded)
    usable = fits.usable[edges].all(axis=1)
    candidates = edges[usable]
    ends = prepared.points[candidates]
    middle = ends.mean(axis=1)
    lifted = [fits.lift(candidates[:, side], middle) for side in (0, 1)]
    length = np.linalg.norm(ends[:, 1] - ends[:, 0], axis=1)
    agree = np.linalg.norm(lifted[0] - lifted[1], axis=1) <= AGREE_RTOL * length
    order = np.argsort(-length[agree], kind="stable")[:budget]
    chosen = candidates[agree][order]
    points = 0.5 * (lifted[0] + lifted[1])[agree][order]
    first, second = normals[chosen[:, 0]], normals[chosen[:, 1]]
    flip = np.where((first * second).sum(axis=1) < 0, -1.0, 1.0)
    line = first + flip[:, None] * second
    line /= np.linalg.norm(line, axis=1)[:, None]
    return EdgeSamples(points, line, chosen, int(agree.sum()))


class _VertexFits:
    """The quartic height function of every vertex over its tangent plane (where usable)."""

    def __init__(self, prepared: PreparedMesh, normals: np.ndarray, excluded: np.ndarray):
        import scipy.sparse as sparse

        points, edges = prepared.points, prepared.edges
        count = len(points)
        adjacency = sparse.coo_matrix(
            (np.ones(2 * len(edges)), (edges.T.reshape(-1), edges[:, ::-1].T.reshape(-1))),
            shape=(count, count),
        ).tocsr() + sparse.identity(count, format="csr")
        support = adjacency
        for _ in range(FIT_RINGS - 1):
            support = support @ adjacency
        support = support.tocsr()
        feature = np.zeros(count)
        feature[edges[excluded].reshape(-1)] = 1.0
        near_feature = support @ feature > 0
        length = np.linalg.norm(points[edges[:, 0]] - points[edges[:, 1]], axis=1)
        unit = np.zeros(count)
        np.maximum.at(unit, edges[:, 0], length)
        np.maximum.at(unit, edges[:, 1], length)
        first, second = tangent_basis(normals)
        self.frame = np.stack([first, second, normals], axis=1)
        self.points, self.unit = points, np.where(unit > 0, unit, 1.0)
        self.coefficients = np.zeros((count, len(_TERMS)))
        self.usable = np.zeros(count, dtype=bool)
        candidates = np.flatnonzero(~near_feature & (unit > 0))
        for start in range(0, len(candidates), CHUNK):
            self._fit(support, normals, candidates[start : start + CHUNK])

    def _fit(self, support, normals, vertices: np.ndarray) -> None:
        neighbours, valid = _nearest_rows(support, self.points, vertices)
        local = self._local(vertices[:, None], self.points[np.where(valid, neighbours, 0)])
        x, y, z = local[..., 0], local[..., 1], local[..., 2]
        basis = _monomials(x, y)
        weight = valid * np.exp(-(x * x + y * y) / FIT_WIDTH**2)
        weighted = basis * weight[..., None]
        normal_matrix = np.einsum("vki,vkj->vij", weighted, basis)
        right = np.einsum("vki,vk->vi", weighted, z)
        eigen = np.linalg.eigvalsh(normal_matrix)
        well_posed = eigen[:, 0] > eigen[:, -1] / COND_MAX
        cosine = np.abs(
            np.einsum("vkd,vd->vk", normals[np.where(valid, neighbours, 0)], normals[vertices])
        )
        graph = np.where(valid, cosine >= np.cos(np.radians(GRAPH_ANGLE)), True).all(axis=1)
        enough = valid.sum(axis=1) - 1 >= MIN_SUPPORT
        good = well_posed & graph & enough
        solved = np.linalg.solve(normal_matrix[good], right[good][..., None])[..., 0]
        self.coefficients[vertices[good]] = solved
        self.usable[vertices[good]] = True

    def _local(self, vertex: np.ndarray, points: np.ndarray) -> np.ndarray:
        """Coordinates of ``points`` in the frame of ``vertex``, in units of its edge length."""
        offset = points - self.points[vertex]
        return (
            np.einsum("...jd,...d->...j", self.frame[vertex], offset) / self.unit[vertex][..., None]
        )

    def lift(self, vertex: np.ndarray, points: np.ndarray) -> np.ndarray:
        """``points`` (m, 3) moved along the normal of ``vertex`` (m,) onto its fit."""
        local = self._local(vertex, points)
        height = (self.coefficients[vertex] * _monomials(local[:, 0], local[:, 1])).sum(axis=1)
        step = (height - local[:, 2]) * self.unit[vertex]
        return points + step[:, None] * self.frame[vertex, 2]


def _monomials(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    return np.stack([x**i * y**j for i, j in _TERMS], axis=-1)


def _nearest_rows(support, points: np.ndarray, vertices: np.ndarray):
    """Padded support of each vertex (rows of the sparse ``support``), nearest first, at most
    MAX_SUPPORT; −1 marks padding."""
    starts, stops = support.indptr[vertices], support.indptr[vertices + 1]
    sizes = stops - starts
    row = np.repeat(np.arange(len(vertices)), sizes)
    flat = support.indices[
        np.repeat(starts - np.cumsum(np.r_[0, sizes[:-1]]), sizes) + np.arange(sizes.sum())
    ]
    distance = np.linalg.norm(points[flat] - points[vertices[row]], axis=1)
    order = np.lexsort((distance, row))
    row, flat = row[order], flat[order]
    rank = np.arange(len(row)) - np.repeat(np.cumsum(np.r_[0, sizes[:-1]]), sizes)
    keep = rank < MAX_SUPPORT
    width = int(min(sizes.max(), MAX_SUPPORT))
    neighbours = np.full((len(vertices), width), -1)
    neighbours[row[keep], rank[keep]] = flat[keep]
    return neighbours, neighbours >= 0


def tangent_basis(normals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors spanning the plane normal to each of ``normals`` (unit, (n, 3)), with
    the normal a right-handed frame."""
    helper = np.eye(3)[np.argmin(np.abs(normals), axis=1)]
    first = np.cross(normals, helper)
    first /= np.linalg.norm(first, axis=1)[:, None]
    return first, np.cross(normals, first)
