"""σ-sparse ε-samples with a guarantee: a maximal sparse subset of a fine candidate lattice.

The candidates are visited in a random order (fixed by the seed; on a mesh with sharp features
its corners first, then its feature edges); each is accepted unless an
accepted sample lies within σε·min(L) of it. The result is the lexicographically first maximal
independent set of the conflict graph for that order, so it is σ-sparse by construction and,
by the choice of the lattice (:mod:`vorobound.sampling.sampler.lattice`), an ε-sample.

The visit runs in chunks of the order, each about ``CHUNK_GROWTH`` times the last: a chunk's
candidates that conflict with a sample accepted before it are dropped (one nearest-neighbour
query against the accepted samples), and conflicts inside the chunk are resolved in rounds (a
candidate joins once every earlier conflicting candidate of the chunk is decided), which gives
exactly the sequential result.

References
----------
The sampling conditions of Section 4.1 (ε-sample, σ-sparse).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...geometry.threads import thread_count
from ...progress import Counter, Progress
from .lattice import SPARSITY_SLACK, Candidates

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


@dataclass(frozen=True)
class Sample:
    """A sample of a surface: points, their local feature size and how they were made."""

    points: np.ndarray
    """(n, 3) sample points."""
    lfs: np.ndarray
    """(n,) local feature size L at each point."""
    eps: float
    sigma: float
    lipschitz: float
    """Lipschitz constant λ of L on the surface (1 for an exact local feature size)."""
    surface: str
    """Name of the sampled surface."""
    seed: int
    candidates: int
    """Size of the candidate lattice."""
    reach_ratio: float
    """Guaranteed: every surface point is within reach_ratio·ε·L of a candidate."""


def conflict_radius(eps: float, sigma: float, lfs_a, lfs_b):
    """Two points closer than this conflict: σε·min(L_a, L_b), widened by ``SPARSITY_SLACK``."""
    return sigma * (1 + SPARSITY_SLACK) * eps * np.minimum(lfs_a, lfs_b)


def maximal_sparse_subset(
    candidates: Candidates,
    eps: float,
    sigma: float,
    rng: np.random.Generator,
    progress: Progress | None = None,
) -> np.ndarray:
    """Indices of the maximal σ-sparse subset of ``candidates`` for a random visiting order.

    Parameters
    ----------
    candidates : Candidates
        Points and their L.
    eps, sigma : float
        Conflict when |p − q| < σε·min(L_p, L_q).
    rng : numpy.random.Generator
        Draws the visiting order.
    progress : Progress, optional
        Reports the candidates visited.

    Returns
    -------
    numpy.ndarray
        Accepted candidate indices, in visiting order.

    References
    ----------
    The σ-sparsity condition of Section 4.1.
    """
    from scipy.spatial import cKDTree

    points, lfs = candidates.points, candidates.lfs
    count = len(points)
    rank = rng.permutation(count)  # visiting position of each candidate
    if candidates.priority is not None:
        # Lower priority classes first (feature corners, then edges), random inside a class.
        order = np.lexsort((rank, candidates.priority))
        rank = np.empty(count, dtype=np.int64)
        rank[order] = np.arange(count)
    counter = Counter(progress, "sampling", count)
    accepted: list[np.ndarray] = []
    tree, members = None, np.empty(0, dtype=np.int64)
    for start, stop in _chunks(count):
        # Lattice order is spatially coherent: gathers and tree queries in it stay in cache.
        ids = np.flatnonzero((rank >= start) & (rank < stop))
        if tree is not None:
            ids = ids[~_conflicts_with(tree, lfs[members], points, lfs, ids, eps, sigma)]
        ids = ids[np.argsort(rank[ids])]
        if len(ids):
            accepted.append(ids[_first_independent(points[ids], lfs[ids], eps, sigma)])
            members = np.sort(np.concatenate(accepted))
            tree = cKDTree(points[members], balanced_tree=False)
        counter.step(stop - start)
    return np.concatenate(accepted) if accepted else np.empty(0, dtype=np.int64)


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


def sample_surface(
    shape, eps: float, sigma: float, seed: int = 0, progress: Progress | None = None
) -> Sample:
    """A σ-sparse ε-sample of ``shape`` (a surface of revolution or a mesh), fixed by ``seed``.

    Parameters
    ----------
    shape : RevolutionShape or MeshShape
        The surface and its local feature size L.
    eps : float
        ε: every surface point x gets a sample within ε·L(x) (guaranteed by construction).
    sigma : float
        σ < 1: samples are at least σε·min(L) apart (exact).
    seed : int
        Seeds the jitter of the lattice and the visiting order.
    progress : Progress, optional
        Reports the stages "lattice" and "sampling".

    References
    ----------
    The sampling conditions of Section 4.1.
    """
    from ..surfaces.analytic import RevolutionShape
    from .lattice import revolution_candidates
    from .slabs import slab_sample

    rng = np.random.default_rng(seed)
    if isinstance(shape, RevolutionShape):
        Counter(progress, "lattice", None)
        candidates = revolution_candidates(shape, eps, sigma, rng)
        chosen = np.sort(maximal_sparse_subset(candidates, eps, sigma, rng, progress))
        points, lfs = candidates.points[chosen], candidates.lfs[chosen]
        made, ratio = len(candidates.points), candidates.reach_ratio
    else:
        points, lfs, made, ratio = slab_sample(shape, eps, sigma, rng, progress)
    return Sample(
        points=points,
        lfs=lfs,
        eps=eps,
        sigma=sigma,
        lipschitz=shape.lipschitz,
        surface=shape.name,
        seed=seed,
        candidates=made,
        reach_ratio=ratio,
    )
