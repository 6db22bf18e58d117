"""The feature terms of the estimate of L (:mod:`.estimate`): the feature curves' own size
L_F (radius of curvature, half the distance to non-adjacent curves), the cap it puts on every
site, the limit of the patches' values at a feature, and ∫ ds/L along the features.
"""

from __future__ import annotations

import numpy as np

from ...mesh.nearest import nearest_allowed
from .lipschitz import DistanceCap
from .medial import compiled_poles
from .patches import Patches


def edge_patches(prepared, patches: Patches) -> np.ndarray:
    """(e, 2) the patches on either side of each feature edge (−1 where none)."""
    edges = np.sort(patches.feature_edges, axis=1)
    out = np.full((len(edges), 2), -1)
    if not len(edges):
        return out
    faces = prepared.triangles
    pairs = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), 1)
    face = np.tile(np.arange(len(faces)), 3)
    order = np.lexsort((pairs[:, 1], pairs[:, 0]))
    pairs, face = pairs[order], face[order]
    key = edges[:, 0] * (len(prepared.points) + 1) + edges[:, 1]
    all_keys = pairs[:, 0] * (len(prepared.points) + 1) + pairs[:, 1]
    first = np.searchsorted(all_keys, key)
    for column in range(2):
        at = np.minimum(first + column, len(all_keys) - 1)
        hit = all_keys[at] == key
        out[hit, column] = patches.face_patch[face[at[hit]]]
    return out


def vertex_curves(patches: Patches, vertices: np.ndarray) -> np.ndarray:
    """(n, k) the curves of each feature vertex's edges, −1 padded."""
    edges = patches.feature_edges
    if not len(edges) or not len(vertices):
        return np.full((len(vertices), 1), -1)
    ends = np.concatenate([edges[:, 0], edges[:, 1]])
    curve = np.concatenate([patches.edge_curve, patches.edge_curve])
    pairs = np.unique(np.c_[ends, curve], axis=0)
    index = {v: k for k, v in enumerate(vertices.tolist())}
    width = max(1, int(np.bincount(pairs[:, 0]).max()))
    table = np.full((len(vertices), width), -1)
    fill = np.zeros(len(vertices), dtype=np.int64)
    for v, c in pairs.tolist():
        row = index.get(v)
        if row is not None:
            table[row, fill[row]] = c
            fill[row] += 1
    return table


def edge_radius(patches: Patches, edge: np.ndarray) -> np.ndarray:
    """Radius of curvature of the curve at a point of a feature edge: the smaller one of the
    edge's two end vertices."""
    ends = patches.feature_edges[edge]
    radius = patches.vertex_curvature_radius
    return np.minimum(radius[ends[:, 0]], radius[ends[:, 1]])


def patch_limit(site_points, site_patches, raw, kind, queries) -> np.ndarray:
    """For each query (feature) site, min over its patches of raw at that patch's nearest site
    inside the patch (a vertex or a face site among the 16 nearest)."""
    from scipy.spatial import cKDTree

    inner = np.flatnonzero(kind < 2)
    out = np.full(len(queries), np.inf)
    if not len(inner) or not len(queries):
        return out
    tree = cKDTree(site_points[inner])
    for column in range(site_patches.shape[1]):
        wanted = site_patches[queries, column]

        def of_patch(rows, index, wanted=wanted):
            mine = wanted[rows, None]
            return (site_patches[inner[index], 0] == mine) & (mine >= 0)

        _, index = nearest_allowed(tree, site_points[queries], of_patch, (16,))
        found = index >= 0
        out[found] = np.minimum(out[found], raw[inner[index[found]]])
    return out


FEATURE_PAIRS = 4_000_000
"""(site, feature point) pairs looked at together by :func:`feature_lfs` (its memory bound)."""


def feature_lfs(query_points, query_curves, radius, patches: Patches, feature) -> np.ndarray:
    """L_F at feature sites: min(the curve's radius of curvature, half the distance to the
    nearest point of a non-adjacent curve: neither one of the site's curves nor sharing a
    corner with one)."""
    from scipy.spatial import cKDTree

    n = len(query_points)
    if n == 0 or len(feature.points) == 0:
        return np.minimum(radius, np.inf)
    target_curve = patches.edge_curve[feature.edge]
    related = patches.curve_adjacent | np.eye(patches.curves, dtype=bool)

    def far(rows, index):
        near = np.zeros(index.shape, dtype=bool)
        for column in range(query_curves.shape[1]):
            mine = query_curves[rows, column]
            valid = mine >= 0
            hit = related[np.maximum(mine, 0)[:, None], target_curve[index]]
            near |= hit & valid[:, None]
        return ~near

    compiled = compiled_poles()
    if compiled is not None:
        # One walk of the poles' box tree with the curves as labels, each site's label its
        # set of curves (the same distances as the k-d tree's, without the k nearest points
        # of its own curves, thousands where the curves are finely cut).
        groups, group = np.unique(query_curves, axis=0, return_inverse=True)
        allowed = np.ones((len(groups), patches.curves), dtype=bool)
        for column in range(groups.shape[1]):
            valid = groups[:, column] >= 0
            allowed[valid] &= ~related[groups[valid, column]]
        tree = compiled.PoleTree(feature.points, target_curve)
        gap = tree.nearest_allowed(query_points, group.reshape(-1), allowed)[0]
        return np.minimum(radius, gap / 2)
    tree = cKDTree(feature.points)
    gap, found = nearest_allowed(tree, query_points, far, (16, 64, 256), FEATURE_PAIRS)
    # The rest: among the k nearest points, k one more than the points on the site's own and
    # related curves, one is on a curve that counts (exact, and bounded by the curves' sizes,
    # not by all feature points at once).
    todo = np.flatnonzero(found < 0)
    if len(todo):
        per_curve = np.bincount(target_curve, minlength=patches.curves)
        related_points = related.astype(np.int64) @ per_curve
        curves = query_curves[todo]
        need = np.where(curves >= 0, related_points[np.maximum(curves, 0)], 0).sum(axis=1) + 1
        need = np.minimum(need, len(feature.points))
        width = 2 ** np.ceil(np.log2(need)).astype(np.int64)
        for k in np.unique(width):
            rows = todo[width == k]

            def far_rows(sub, index, rows=rows):
                return far(rows[sub], index)

            gap[rows], _ = nearest_allowed(
                tree, query_points[rows], far_rows, (int(k),), FEATURE_PAIRS
            )
    return np.minimum(radius, gap / 2)


def feature_cap(site_points, raw, feature_points, feature_lfs, half) -> np.ndarray:
    """min(raw, min over feature pieces P of max(dist(x, P), L_F(P))), with dist(x, P) taken
    as |x − p| − (half the piece's length), p its centre (never above the distance)."""
    finite = np.isfinite(feature_lfs)  # an infinite L_F caps nothing
    if not finite.any():
        return raw
    cap = DistanceCap(feature_points[finite], feature_lfs[finite], half[finite])
    return cap(site_points, upper=raw)


def feature_integrals(points, edges, field) -> tuple[float, float]:
    """Length of the feature edges and ∫ ds/L along them (midpoint rule on pieces no longer
    than L/4 at the edge's midpoint)."""
    if not len(edges):
        return 0.0, 0.0
    a, b = points[edges[:, 0]], points[edges[:, 1]]
    length = np.linalg.norm(b - a, axis=1)
    pieces = np.clip(np.ceil(4 * length / field(0.5 * (a + b))), 1, 4096).astype(np.int64)
    owner = np.repeat(np.arange(len(edges)), pieces)
    index = np.arange(len(owner)) - np.repeat(np.cumsum(pieces) - pieces, pieces)
    f = (index + 0.5) / pieces[owner]
    values = field(a[owner] + f[:, None] * (b - a)[owner])
    return float(length.sum()), float((length[owner] / pieces[owner] / values).sum())
