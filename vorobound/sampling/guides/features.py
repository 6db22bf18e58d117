"""Which guide triangles sit on a smooth patch and which within reach of a sharp feature.

VoroCrust's analysis (and the constraint set (33)–(36) with H3) is about smooth surfaces; on a
part with sharp edges and corners it protects the features with their own balls and the
smooth-surface guarantees hold away from them. The rule (docs/samples.md, "Sharp features"):

    a guide triangle is *at a feature* when one of its three balls comes within FEATURE_REACH
    ball radii of a sharp feature: min over its vertices v of d_F(v)/r_v ≤ FEATURE_REACH,

d_F the distance from the ball's center to the nearest feature curve or corner (the feature
edges that ``vorobound lfs`` finds: sharp, boundary or non-manifold edges) and r_v = δ·L(v)
its radius. With FEATURE_REACH = 2 the triangle's ball meets the ball of a sample on the
feature (radius δL there, about r_v: L is 1-Lipschitz, so it changes little over a ball),
i.e. the triangle shares a seed region with the balls that protect the feature.
Every other guide triangle is *on a smooth patch*: its balls contain no feature point and no
ball centred on one. The rule uses only the ball radii and the feature curves, both the same
for a coarse and a fine export of a part, so the classification is too.

References
----------
The sampling conditions of Section 4.1; docs/lfs.md (patches and features).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...geometry.threads import thread_count

FEATURE_REACH = 2.0
"""A guide triangle is at a feature when a vertex's ball center lies within this many of its
ball radii of a feature (module docstring)."""
FEATURE_RULE = (
    "a guide triangle is at a sharp feature when one of its balls' centers lies within "
    f"{FEATURE_REACH:g} ball radii of a feature edge or corner (min over its vertices of "
    "d_F/r <= 2), so its balls meet the balls that protect the feature; every other guide "
    "triangle is on a smooth patch (docs/samples.md, 'Sharp features')"
)
NO_FEATURES = "no sharp features known (no mesh, or none found): every guide triangle is smooth"
_BRUTE_SEGMENTS = 4096  # up to this many segments, every point is measured against every one
_CHUNK_PAIRS = 4_000_000  # point-segment pairs per chunk of the brute-force distance
_NEIGHBOURS = 8  # nearest pieces measured exactly per point before the certainty test
_MAX_PIECES = 2_000_000  # pieces the feature curves are cut into, at most


@dataclass(frozen=True)
class SharpFeatures:
    """The feature curves of a part as straight segments, and exact distances to them."""

    segments: np.ndarray
    """(k, 2, 3) end points of the feature edges (corners are their end points)."""

    @classmethod
    def of_shape(cls, shape) -> SharpFeatures | None:
        """The features a surface knows (a mesh with estimated L), or None."""
        segments = getattr(shape, "feature_segments", None)
        if segments is None or len(segments) == 0:
            return None
        return cls(np.asarray(segments, dtype=float).reshape(-1, 2, 3))

    def distance(self, points: np.ndarray) -> np.ndarray:
        """(n,) exact Euclidean distance from each point to the nearest feature segment.

        Up to a few thousand segments every pair is measured. Otherwise the segments are cut
        into pieces no longer than ``piece``; a k-d tree of the pieces' midpoints proposes the
        nearest ones, whose exact distances give an upper bound u; any piece closer than u has
        its midpoint within u + piece/2, so points whose k-th proposal is nearer than that are
        redone over every such piece.
        """
        points = np.asarray(points, dtype=float)
        if len(points) == 0:
            return np.zeros(0)
        if len(self.segments) <= _BRUTE_SEGMENTS:
            return self._brute(points)
        from scipy.spatial import cKDTree

        start, end, piece = _pieces(self.segments)
        tree = cKDTree(0.5 * (start + end))
        k = min(_NEIGHBOURS, len(start))
        near_d, near_i = tree.query(points, k=k, workers=thread_count())
        near_d, near_i = near_d.reshape(len(points), k), near_i.reshape(len(points), k)
        exact = _point_segment(points[:, None, :], start[near_i], end[near_i]).min(axis=1)
        unsure = np.zeros(0, np.int64)
        if k < len(start):
            unsure = np.flatnonzero(near_d[:, -1] <= exact + piece / 2)
        for row in unsure:
            ids = np.asarray(tree.query_ball_point(points[row], exact[row] + piece / 2))
            if len(ids):
                found = _point_segment(points[row][None, :], start[ids], end[ids]).min()
                exact[row] = min(exact[row], found)
        return exact

    def _brute(self, points: np.ndarray) -> np.ndarray:
        """Every point against every segment, in chunks of bounded memory."""
        a, b = self.segments[:, 0], self.segments[:, 1]
        rows = max(1, _CHUNK_PAIRS // len(a))
        out = np.empty(len(points))
        for first in range(0, len(points), rows):
            chunk = points[first : first + rows, None, :]
            out[first : first + rows] = _point_segment(chunk, a, b).min(axis=1)
        return out


def feature_reach(
    triples: np.ndarray, centers: np.ndarray, radii: np.ndarray, features: SharpFeatures | None
) -> np.ndarray:
    """(m,) min over each triangle's vertices of d_F/r (inf without features): the triangle
    is at a feature when this is at most :data:`FEATURE_REACH`.

    ``triples`` index ``centers`` and ``radii``; only the balls they use are measured.
    """
    triples = np.asarray(triples, dtype=np.int64).reshape(-1, 3)
    if features is None or len(triples) == 0:
        return np.full(len(triples), np.inf)
    used, local = np.unique(triples, return_inverse=True)
    ratio = features.distance(centers[used]) / radii[used]
    return ratio[local.reshape(-1, 3)].min(axis=1)


def at_features(reach: np.ndarray) -> np.ndarray:
    """Rows at a feature (the rule of the module docstring)."""
    return np.asarray(reach) <= FEATURE_REACH


def _pieces(segments: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """The segments cut into equal pieces of at most ``piece`` long (the same point set)."""
    a, b = segments[:, 0], segments[:, 1]
    length = np.linalg.norm(b - a, axis=1)
    total = float(length.sum())
    piece = max(float(np.median(length)), total / _MAX_PIECES)
    if piece <= 0:
        return a, b, 0.0
    cuts = np.maximum(1, np.ceil(length / piece)).astype(np.int64)
    owner = np.repeat(np.arange(len(segments)), cuts)
    first = np.concatenate([[0], np.cumsum(cuts)[:-1]])
    step = np.arange(len(owner)) - first[owner]
    t0 = (step / cuts[owner])[:, None]
    t1 = ((step + 1) / cuts[owner])[:, None]
    span = b[owner] - a[owner]
    start, end = a[owner] + t0 * span, a[owner] + t1 * span
    return start, end, float((np.linalg.norm(end - start, axis=1)).max())


def _point_segment(points: np.ndarray, start: np.ndarray, end: np.ndarray) -> np.ndarray:
    """Distance from points (broadcast) to the segments [start, end]."""
    span = end - start
    length_sq = (span * span).sum(axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.where(length_sq > 0, ((points - start) * span).sum(axis=-1) / length_sq, 0.0)
    t = np.clip(t, 0.0, 1.0)
    return np.linalg.norm(points - (start + t[..., None] * span), axis=-1)
