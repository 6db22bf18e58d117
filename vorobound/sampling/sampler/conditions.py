"""What a sample achieves: coverage, sparsity and the Lipschitz property of its L.

* coverage: max over probe points x of the surface of (distance to the nearest sample)/(εL(x));
  an ε-sample has it < 1. Probes are random points, uniform by area (``PROBES_PER_SAMPLE`` per
  sample, between ``MIN_PROBES`` and ``MAX_PROBES``), plus any points the
  caller adds (the checker adds the circumcenters of the guide triangles projected onto the
  surface, near which the distance to the sample peaks). A measurement, not a proof.
* sparsity: min over all pairs of |p_i − p_j|/(σε·min(L_i, L_j)); σ-sparse means ≥ 1. Exact.
* Lipschitz: max of |L_i − L_j|/|p_i − p_j| over each sample and its nearest samples (where a
  guide triangle's vertices are), and the pairs above a given λ.

References
----------
The sampling conditions of Section 4.1.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ...geometry.threads import thread_count

PROBES_PER_SAMPLE = 4
"""Random probe points per sample for the coverage measurement."""
MIN_PROBES = 100_000
"""At least this many random probe points."""
MAX_PROBES = 2_000_000
"""At most this many random probe points (a sample of 10⁷ points would otherwise need 4·10⁷
evaluations of L, as many as the sampler itself)."""
BLOCK_SAMPLES = 500_000
"""Samples beyond this many are measured for sparsity in blocks of this size along their
longest axis (:func:`sparsity_in_blocks`), which bounds the memory of the neighbour lists."""
HALO_RATIO = 2.0
"""A block is measured with the samples within HALO_RATIO·σε·max L of it along the axis: every
pair whose sparsity ratio is below HALO_RATIO lies in one block and its halo."""
NEIGHBOURS = 16
"""Sparsity and Lipschitz ratios are evaluated between each sample and this many nearest
samples (sparsity then completes the search where that could miss a pair)."""
LIPSCHITZ_RTOL = 1e-9
"""A pair breaks λ-Lipschitz when |L_i − L_j| > λ|p_i − p_j| + LIPSCHITZ_RTOL·(λ|p_i − p_j| +
max(L_i, L_j)): differences at the rounding level of L do not count."""
_SEARCH_BLOCK = 1 << 14  # points searched in full at a time
WORST_LISTED = 10
"""How many of the worst offending pairs a report lists."""


@dataclass(frozen=True)
class PairReport:
    """A condition on pairs of samples: its extreme value and the pairs that break it."""

    extreme: float
    """min sparsity ratio, or max realized Lipschitz ratio."""
    extreme_pair: tuple[int, int]
    violations: int
    """Pairs breaking the condition."""
    worst: np.ndarray
    """(k, 2) indices of up to ``WORST_LISTED`` breaking pairs, worst first."""
    worst_values: np.ndarray
    """Their ratios."""


@dataclass(frozen=True)
class Neighbours:
    """Each sample's ``NEIGHBOURS`` nearest samples, as distinct pairs (shared by the checks)."""

    pairs: np.ndarray
    """(m, 2) pairs (i, j), each pair of the set once."""
    gap: np.ndarray
    """|p_i − p_j| per pair."""
    tree: Any
    """The points' cKDTree."""
    farthest: np.ndarray
    """Distance from each point to the last of its neighbours."""
    owned: np.ndarray | None = None
    """The points whose pairs these are (None: all; see :func:`neighbours`)."""


def neighbours(points: np.ndarray, owned: np.ndarray | None = None) -> Neighbours:
    """Pairs of each point with its ``NEIGHBOURS`` nearest points.

    With ``owned`` (a mask), only the pairs that the owned points answer for: i → j for owned
    i and j among its neighbours, unless j < i and i is among j's neighbours too (then j
    answers for the pair). Over a partition of the points into owned sets, each pair of the
    whole set is then answered for exactly once, provided every owned point's neighbours, and
    their neighbours up to the distance of the owned point, are among ``points`` (the tiles'
    halo rule, :mod:`vorobound.tiling.plan`).
    """
    from scipy.spatial import cKDTree

    tree = cKDTree(points)
    count = min(NEIGHBOURS + 1, len(points))
    dist, near = tree.query(points, k=count, workers=thread_count())
    if owned is None:
        first = np.repeat(np.arange(len(points)), count - 1)
        pairs = _unique_pairs(first, near[:, 1:].ravel(), len(points))
    else:
        sources = np.flatnonzero(owned)
        # (sources, count - 1) tables: the first point of each pair broadcast along its row.
        first = np.broadcast_to(sources[:, None], (len(sources), count - 1))
        second, apart = near[sources, 1:], dist[sources, 1:]
        # i is among j's neighbours when closer than j's last one (the lists decide ties).
        last = dist[second, -1]
        mutual = apart < last
        tied = np.nonzero(apart == last)
        mutual[tied] = (near[second[tied], 1:] == sources[tied[0], None]).any(axis=1)
        keep = (first < second) | ~mutual
        pairs = np.column_stack([first[keep], second[keep]])
        # The tree's distances are these pairs' gaps: the same sum of squares in the same order
        # as the norm below (tests/sampling/test_conditions_neighbours.py holds them to it).
        return Neighbours(pairs, apart[keep], tree, dist[:, -1], owned)
    gap = np.linalg.norm(points[pairs[:, 0]] - points[pairs[:, 1]], axis=1)
    return Neighbours(pairs, gap, tree, dist[:, -1], owned)


def sparsity(
    points: np.ndarray, lfs: np.ndarray, eps: float, sigma: float, near: Neighbours | None = None
) -> PairReport:
    """min over all pairs of |p_i − p_j|/(σε·min(L_i, L_j)) and the pairs below 1 (exact).

    With U the smallest ratio among nearest neighbours (an upper bound on the minimum, made at
    least 1), a pair below U is closer than U·σε·L to either endpoint, so it is among that
    endpoint's ``NEIGHBOURS`` nearest points unless even the farthest of them is that close;
    such points are searched in full. With ``near.owned``, pairs are searched from the owned
    points only, the minimum is over the pairs found, and a pair below 1 counts when its
    smaller index is owned (its other owner does not count it).

    References
    ----------
    The σ-sparsity condition of Section 4.1.
    """
    unit = sigma * eps
    near = near or neighbours(points)
    pairs, gap = near.pairs, near.gap
    ratio = gap / (unit * np.minimum(lfs[pairs[:, 0]], lfs[pairs[:, 1]]))
    reach = max(float(ratio.min()) if len(ratio) else 1.0, 1.0) * unit * lfs

    def measure(i, j, gap):
        return gap / (unit * np.minimum(lfs[i], lfs[j]))

    pairs, ratio = _complete(points, near, reach, pairs, ratio, measure)
    broken = ratio < 1
    if near.owned is not None:
        broken &= near.owned[np.minimum(pairs[:, 0], pairs[:, 1])]
    return _report(pairs, ratio, broken, smallest=True)


def sparsity_in_blocks(points: np.ndarray, lfs: np.ndarray, eps: float, sigma: float) -> PairReport:
    """:func:`sparsity` of a large sample, block by block along its longest axis: blocks of
    ``BLOCK_SAMPLES`` consecutive samples in the order of the axis, measured by
    :func:`sparsity_of_blocks` (exact when the minimum is below HALO_RATIO).

    References
    ----------
    The σ-sparsity condition of Section 4.1.
    """
    if len(points) <= BLOCK_SAMPLES:
        return sparsity(points, lfs, eps, sigma)
    axis = int(np.argmax(np.ptp(points, axis=0)))
    order = np.argsort(points[:, axis], kind="stable")
    blocks = [order[start : start + BLOCK_SAMPLES] for start in range(0, len(order), BLOCK_SAMPLES)]

    def read(ids):
        return points[ids], lfs[ids]

    return sparsity_of_blocks(blocks, read, axis, eps, sigma, float(lfs.max()))


def sparsity_of_blocks(blocks, read, axis: int, eps: float, sigma: float, lfs_max: float):
    """:func:`sparsity` of a sample given as blocks of row indices (any order, any overlap of
    their extents), ``read(ids)`` giving (points, L) of rows; memory holds a block and the
    samples near it.

    Each block is measured with the samples of the earlier blocks within
    h = HALO_RATIO·σε·``lfs_max`` of its extent along ``axis``. A pair with ratio r <
    HALO_RATIO is closer than h along the axis, so it is measured in the block of whichever of
    its points comes later: the minimum is exact when below HALO_RATIO (else it is the ratio of
    a pair, at least HALO_RATIO), and pairs below 1 are counted once, in that block. Pair
    indices are rows.

    References
    ----------
    The σ-sparsity condition of Section 4.1.
    """
    halo = HALO_RATIO * sigma * eps * lfs_max
    seen: list[tuple[np.ndarray, float, float]] = []
    best: tuple[float, tuple[int, int]] | None = None
    violations = 0
    worst: list[np.ndarray] = []
    worst_values: list[np.ndarray] = []
    for ids in blocks:
        if not len(ids):
            continue
        points, lfs = read(ids)
        coord = points[:, axis]
        low, high = float(coord.min()), float(coord.max())
        near = [e for e, e_low, e_high in seen if e_high >= low - halo and e_low <= high + halo]
        rows = np.asarray(ids)
        earlier = 0
        if near:
            near_ids = np.concatenate(near)
            near_points, near_lfs = read(near_ids)
            keep = np.abs(near_points[:, axis] - (low + high) / 2) <= (high - low) / 2 + halo
            earlier = int(keep.sum())
            rows = np.concatenate([near_ids[keep], rows])
            points = np.concatenate([near_points[keep], points])
            lfs = np.concatenate([near_lfs[keep], lfs])
        seen.append((np.asarray(ids), low, high))
        report = sparsity(points, lfs, eps, sigma)
        if best is None or report.extreme < best[0]:
            first, second = report.extreme_pair
            best = (report.extreme, (int(rows[first]), int(rows[second])))
        if report.violations:
            pairs, ratio = _pairs_below_one(points, lfs, eps, sigma)
            own = pairs.max(axis=1) >= earlier
            violations += int(own.sum())
            worst.append(rows[pairs[own]])
            worst_values.append(ratio[own])
    if best is None:
        return sparsity(np.zeros((0, 3)), np.zeros(0), eps, sigma)
    pairs_found = np.concatenate([np.empty((0, 2), dtype=np.int64), *worst])
    values = np.concatenate([np.empty(0), *worst_values])
    listed = np.argsort(values)[:WORST_LISTED]
    return PairReport(best[0], best[1], violations, pairs_found[listed], values[listed])


def _pairs_below_one(points, lfs, eps, sigma):
    """All pairs (i, j), i < j, closer than σε·min(L_i, L_j), and their ratios."""
    from scipy.spatial import cKDTree

    unit = sigma * eps
    pairs = cKDTree(points).query_pairs(unit * float(lfs.max()), output_type="ndarray")
    pairs = np.sort(pairs, axis=1)
    gap = np.linalg.norm(points[pairs[:, 0]] - points[pairs[:, 1]], axis=1)
    ratio = gap / (unit * np.minimum(lfs[pairs[:, 0]], lfs[pairs[:, 1]]))
    return pairs[ratio < 1], ratio[ratio < 1]


def lipschitz(
    points: np.ndarray, lfs: np.ndarray, bound: float | None, near: Neighbours | None = None
) -> PairReport:
    """max of |L_i − L_j|/|p_i − p_j| over each point's ``NEIGHBOURS`` nearest points, and the
    pairs above ``bound`` (λ)."""
    near = near or neighbours(points)
    pairs, gap = near.pairs, near.gap
    change = np.abs(lfs[pairs[:, 0]] - lfs[pairs[:, 1]])
    ratio = change / gap
    if bound is None:
        broken = np.zeros(len(ratio), dtype=bool)
    else:
        slack = LIPSCHITZ_RTOL * (bound * gap + np.maximum(lfs[pairs[:, 0]], lfs[pairs[:, 1]]))
        broken = change > bound * gap + slack
    return _report(pairs, ratio, broken, smallest=False)


def measured_lipschitz(points, lfs, triples, near: Neighbours) -> float:
    """The λ a sample has: the largest |L_a − L_b|/|p_a − p_b| over neighbouring samples and
    over the edges of the guide triangles ``triples``, so every guide triangle meets the
    Lipschitz conditions with it; 0 only for a constant L."""
    from ...checks import LIPSCHITZ_RANGE

    edges = np.concatenate([triples[:, [0, 1]], triples[:, [1, 2]], triples[:, [2, 0]]])
    change = np.abs(lfs[edges[:, 0]] - lfs[edges[:, 1]])
    length = np.linalg.norm(points[edges[:, 0]] - points[edges[:, 1]], axis=1)
    ratios = [lipschitz(points, lfs, None, near).extreme]
    if len(edges):
        ratios.append(float((change / length).max()))
    value = max(ratios)
    return 0.0 if value == 0 else max(value, LIPSCHITZ_RANGE[0])


def _unique_pairs(first: np.ndarray, second: np.ndarray, count: int) -> np.ndarray:
    """Distinct unordered pairs as rows (i, j), i < j (one integer key per pair)."""
    low, high = np.minimum(first, second), np.maximum(first, second)
    keys = np.sort(low.astype(np.int64) * count + high)
    keys = keys[np.concatenate([[True], keys[1:] != keys[:-1]])]
    return np.column_stack([keys // count, keys % count])


def _complete(points, near: Neighbours, reach, pairs, ratio, measure):
    """Add the pairs within ``reach[i]`` of (owned) points whose neighbour list ends inside it."""
    tree = near.tree
    short = near.farthest < reach
    if near.owned is not None:
        short &= near.owned
    short = np.flatnonzero(short)
    extra = []
    for start in range(0, len(short), _SEARCH_BLOCK):
        rows = short[start : start + _SEARCH_BLOCK]
        for i, found in zip(rows, tree.query_ball_point(points[rows], reach[rows]), strict=True):
            found = np.asarray([j for j in found if j != i], dtype=np.int64)
            extra.append(np.column_stack([np.full(len(found), i), found]))
    if not extra:
        return pairs, ratio
    more = np.concatenate([pairs, *extra])
    pairs = _unique_pairs(more[:, 0], more[:, 1], len(points))
    gap = np.linalg.norm(points[pairs[:, 0]] - points[pairs[:, 1]], axis=1)
    return pairs, measure(pairs[:, 0], pairs[:, 1], gap)


def _report(pairs: np.ndarray, ratio: np.ndarray, broken: np.ndarray, smallest: bool):
    if len(ratio) == 0:
        empty = np.empty((0, 2), dtype=np.int64)
        return PairReport(np.inf if smallest else 0.0, (-1, -1), 0, empty, np.empty(0))
    at = int(np.argmin(ratio) if smallest else np.argmax(ratio))
    bad = np.flatnonzero(broken)
    bad = bad[np.argsort(ratio[bad] if smallest else -ratio[bad])][:WORST_LISTED]
    return PairReport(
        float(ratio[at]),
        (int(pairs[at, 0]), int(pairs[at, 1])),
        int(broken.sum()),
        pairs[bad],
        ratio[bad],
    )


def coverage(
    points: np.ndarray,
    eps: float,
    probes: np.ndarray,
    probe_lfs: np.ndarray,
) -> tuple[float, np.ndarray]:
    """max over ``probes`` of (distance to the nearest sample)/(εL) and the worst probe.

    References
    ----------
    The ε-sample condition of Section 4.1.
    """
    from scipy.spatial import cKDTree

    dist, _ = cKDTree(points).query(probes, workers=thread_count())
    ratio = dist / (eps * probe_lfs)
    at = int(np.argmax(ratio))
    return float(ratio[at]), probes[at]


def coverage_probes(shape, samples: int, seed: int | None, extra=None):
    """The probes of :func:`surface_coverage` for a sample of ``samples`` points: random
    surface points (``PROBES_PER_SAMPLE`` per sample, at least ``MIN_PROBES``, at most
    ``MAX_PROBES``, fixed by ``seed``) and the projections of ``extra`` onto the surface.
    Returns (probes, L there)."""
    rng = np.random.default_rng([0 if seed is None else seed, 1])
    count = max(MIN_PROBES, min(MAX_PROBES, PROBES_PER_SAMPLE * samples))
    probes, probe_lfs = shape.random_points(count, rng)
    projected = shape.project(extra) if extra is not None and len(extra) else None
    if projected is not None:  # (shapes without a projection return None)
        probes = np.concatenate([probes, projected[0]])
        probe_lfs = np.concatenate([probe_lfs, projected[1]])
    return probes, probe_lfs


def surface_coverage(
    shape, points: np.ndarray, eps: float, seed: int | None, extra=None
) -> tuple[float, np.ndarray, int]:
    """Coverage of ``shape`` by samples at ``points``: :func:`coverage` over the probes of
    :func:`coverage_probes` (random surface points and the projections of ``extra`` points,
    e.g. circumcenters, near which the largest gaps lie). Returns (max ratio, worst probe,
    probes used).

    References
    ----------
    The ε-sample condition of Section 4.1.
    """
    probes, probe_lfs = coverage_probes(shape, len(points), seed, extra)
    ratio, where = coverage(points, eps, probes, probe_lfs)
    return ratio, where, len(probes)


def coverage_of_blocks(blocks, read, axis: int, eps: float, probes, probe_lfs):
    """:func:`coverage` of a sample given as blocks of row indices, ``read(ids)`` giving
    (points, L) of rows; memory holds the probes and the samples near a group of them.

    The probes are taken in groups along ``axis`` (as many as the blocks); a group spanning
    [a, b] with largest L_max is measured against the samples within [a − εL_max, b + εL_max]
    along the axis. A probe x whose nearest sample is within εL(x) finds it there, so its
    ratio is exact when below 1, and at least 1 otherwise: the maximum is exact when below 1
    and at least 1 when the sample does not cover a probe.

    References
    ----------
    The ε-sample condition of Section 4.1.
    """
    extents = []
    for ids in blocks:
        if len(ids):
            coord = read(ids)[0][:, axis]
            extents.append((np.asarray(ids), float(coord.min()), float(coord.max())))
    order = np.argsort(probes[:, axis], kind="stable")
    best, where = -np.inf, probes[0]
    for group in np.array_split(order, max(1, len(extents))):
        if not len(group):
            continue
        coord = probes[group, axis]
        reach = eps * float(probe_lfs[group].max())
        low, high = float(coord.min()) - reach, float(coord.max()) + reach
        near = [ids for ids, e_low, e_high in extents if e_high >= low and e_low <= high]
        if near:
            points = read(np.concatenate(near))[0]
            points = points[(points[:, axis] >= low) & (points[:, axis] <= high)]
        if not near or not len(points):
            ratio, at = np.inf, probes[group[0]]
        else:
            ratio, at = coverage(points, eps, probes[group], probe_lfs[group])
        if ratio > best:
            best, where = ratio, at
    return float(best), where
