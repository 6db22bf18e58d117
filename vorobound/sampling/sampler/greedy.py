"""The greedy rule of the sampler, shared by the whole-lattice visit (:mod:`.maximal`) and the
slab sampler (:mod:`.slabs`): a candidate is accepted unless an accepted sample lies within
σε·min(L) of it; visits run in chunks of the order, each resolved exactly (:mod:`.maximal`'s
docstring).

References
----------
The σ-sparsity condition of Section 4.1.
"""

from __future__ import annotations

import numpy as np

from ...geometry.threads import thread_count
from .lattice import SPARSITY_SLACK

FIRST_CHUNK_SHARE = 1 / 64
"""The first chunk visits this share of the candidates (at least ``MIN_CHUNK``)."""
CHUNK_GROWTH = 1.5
"""Each later chunk is this much larger: few chunks, so few rebuilds of the accepted samples'
search tree, while late chunks, whose candidates are mostly in conflict already, stay cheap."""
MIN_CHUNK = 1 << 12
"""Smallest first chunk. A chunk's conflict pairs grow like its size times its share of all
candidates, so a large first chunk of a small lattice holds hundreds of pairs per candidate:
1 << 16 took 1.6 GB for a 93 000-candidate mesh lattice that 1 << 12 samples in 0.1 GB, with
the same result (the visiting order alone decides it)."""


def conflict_radius(eps: float, sigma: float, lfs_a, lfs_b):
    """Two points closer than this conflict: σε·min(L_a, L_b), widened by ``SPARSITY_SLACK``."""
    return sigma * (1 + SPARSITY_SLACK) * eps * np.minimum(lfs_a, lfs_b)


def _chunks(count: int) -> list[tuple[int, int]]:
    """(start, stop) of the visiting chunks: geometric growth from ``FIRST_CHUNK_SHARE``."""
    bounds, start, size = [], 0, max(MIN_CHUNK, count * FIRST_CHUNK_SHARE)
    while start < count:
        stop = min(count, start + int(size))
        bounds.append((start, stop))
        start, size = stop, size * CHUNK_GROWTH
    return bounds


def _conflicts_with(tree, tree_lfs, points, lfs, ids, eps, sigma) -> np.ndarray:
    """Mask over ``ids``: True where the candidate conflicts with a point of ``tree``.

    The nearest tree point decides unless it is farther than its own conflict radius but
    nearer than the candidate's (possible only where L varies); those candidates are checked
    against every tree point within the candidate's radius.
    """
    own = conflict_radius(eps, sigma, lfs[ids], lfs[ids])
    dist, near = tree.query(
        points[ids], k=1, distance_upper_bound=float(own.max()), workers=thread_count()
    )
    hit = near < tree.n
    conflict = np.zeros(len(ids), dtype=bool)
    conflict[hit] = dist[hit] < conflict_radius(eps, sigma, lfs[ids][hit], tree_lfs[near[hit]])
    unsure = np.flatnonzero(hit & ~conflict & (dist < own))
    candidates = tree.query_ball_point(points[ids[unsure]], own[unsure])
    for row, found in zip(unsure, candidates, strict=True):
        found = np.asarray(found, dtype=np.int64)
        gap = np.linalg.norm(tree.data[found] - points[ids[row]], axis=1)
        conflict[row] = bool(
            (gap < conflict_radius(eps, sigma, lfs[ids[row]], tree_lfs[found])).any()
        )
    return conflict


def _conflict_pairs(points: np.ndarray, lfs: np.ndarray, eps: float, sigma: float) -> np.ndarray:
    """Pairs (i, j), i < j, of rows of ``points`` that conflict."""
    from scipy.spatial import cKDTree

    reach = float(conflict_radius(eps, sigma, lfs.max(), lfs.max()))
    pairs = cKDTree(points).query_pairs(reach, output_type="ndarray")
    i, j = pairs[:, 0], pairs[:, 1]
    gap = points[i] - points[j]
    close = np.einsum("ij,ij->i", gap, gap) < conflict_radius(eps, sigma, lfs[i], lfs[j]) ** 2
    return np.sort(pairs[close], axis=1)


def _first_independent(points, lfs, eps, sigma) -> np.ndarray:
    """Mask of the sequential greedy independent set of rows visited in row order.

    Rounds: a row joins when no earlier conflicting row is undecided; rows conflicting with a
    joined row leave. Every round decides at least the earliest undecided row.
    """
    pairs = _conflict_pairs(points, lfs, eps, sigma)
    undecided, joined = np.ones(len(points), dtype=bool), np.zeros(len(points), dtype=bool)
    while undecided.any():
        early, late = pairs[:, 0], pairs[:, 1]
        waiting = np.zeros(len(points), dtype=bool)
        waiting[late[undecided[early]]] = True
        joins = undecided & ~waiting
        joined |= joins
        undecided &= ~joins
        undecided[late[joins[early]]] = False
        keep = undecided[early] & undecided[late]
        pairs = pairs[keep]
    return joined
