"""The mesh sampler in slabs: memory bounded by a slab, few candidates per sample, exact.

The part is cut into slabs along the longest axis of its bounding box. Feature corners and
edges are sampled first over the whole part (VoroCrust protects sharp features first); their
samples stay in memory. The first cells of every triangle (the plane frames of
:mod:`.mesh_lattice`) go to the slab of their centre, and the slabs are sampled one after the
other, each refining only its own cells:

1. Every cell gets a candidate (the point of its triangle nearest a random point of the cell)
   and L there. A cell more than ``COARSE`` times larger than the lattice condition of
   :mod:`.mesh_lattice` allows is cut without visiting its candidate.
2. The other candidates are visited in a random order, each accepted unless an accepted sample
   is within σ'ε·min(L) of it (the greedy rule of :mod:`.greedy`, the same chunked visit).
3. A visited cell is done when it meets the lattice condition (then every point of it is
   within εL of a sample by :func:`.lattice.cell_reach`, whether its candidate was accepted or
   not), or when it is *certified*: with C its centre, d its diagonal, q its candidate and p
   the accepted sample nearest to C, |C − p| + d/2 < ε(L(q) − λd). Every point x of the cell
   (within d/2 of C, and of its triangle within d of q) then has |x − p| < εL(x), since L(x)
   ≥ L(q) − λ|x − q|. Other cells are cut in 2 × 2 and go back to step 1.

Sparsity holds by the greedy rule as long as each candidate is compared with every accepted
sample within its conflict radius: a slab is at least ``2·σ'ε·L_max + 2m`` thick, m = 1.5 times
the largest first-cell diagonal bounding how far a candidate lies from its cell's centre
along the axis, so a candidate of slab i conflicts only with samples of slabs i − 1 and i and
the feature samples, which are the samples it is compared with. Coverage holds because every
point of the surface lies in a done cell. Both are proven by construction; the measured
coverage and sparsity of :mod:`.conditions` only confirm them.

Certified cells need no candidates below them: about 6 candidates per sample instead of the
plain lattice's 30 (σ = 0.75).
"""

from __future__ import annotations

import math

import numpy as np

from ...errors import InputError
from ...progress import Counter
from .greedy import _chunks, _conflicts_with, _first_independent
from .lattice import SPARSITY_SLACK, candidate_limit_error
from .mesh_lattice import (
    MAX_LEVELS,
    _corner_candidates,
    _cut,
    _edge_candidates,
    _first_cells,
    _Frames,
    _positive,
    expected_candidates,
)

COARSE = 3.0
"""Candidates are visited in cells up to this many times the diagonal the lattice condition
allows; larger cells are cut first. Measured on the capped cylinder at ε = 0.03: 2 gives the
fewest candidates per sample."""
FIRST_CELL_BUDGET = 100_000
"""First cells are at most sqrt(area / FIRST_CELL_BUDGET) wide (or the coarse cell size at the
largest L, if larger), so that slabs can be thin: a candidate lies within 1.5 first-cell
diagonals of its cell's centre."""
SLAB_CANDIDATES = 8_000_000
"""Slabs are about this many plain-lattice candidates (:func:`.mesh_lattice.expected_candidates`)
thick, or thicker where the conflict radius needs it."""
MAX_SLAB_CANDIDATES: float | None = None
"""Tests set this to force thin slabs (many slab borders on a small part)."""
MAX_EXPECTED_CANDIDATES = 4e9
"""Largest plain-lattice count the slab sampler takes on: about 5 CPU-hours and 10⁸ samples
(cost.py), refused before anything is allocated."""


def slab_sample(shape, eps: float, sigma: float, rng: np.random.Generator, progress=None):
    """A σ-sparse ε-sample of a mesh shape, slab by slab (module docstring).

    Returns
    -------
    (points, lfs, candidates, reach_ratio)
        The samples, L there, how many candidates were made, and the largest guaranteed
        distance of a surface point to a candidate of a lattice cell or to the certifying
        sample of a certified cell, over ε·L there.

    Raises
    ------
    InputError
        When σ' ≥ 1, L is not positive, or the part needs more than
        ``MAX_EXPECTED_CANDIDATES``.
    """
    s = sigma * (1 + SPARSITY_SLACK)
    if not s < 1:
        raise InputError(f"sigma must be below 1 for a maximal sparse set to cover, got {sigma}")
    lam = np.asarray(shape.triangle_lipschitz, dtype=float)
    counts = shape.counts()
    expected = expected_candidates(counts.inv_lfs_sq_integral, eps, sigma, float(lam.max()))
    if not expected <= MAX_EXPECTED_CANDIDATES:
        raise candidate_limit_error(expected, eps, about=True, limit=MAX_EXPECTED_CANDIDATES)
    k = (1 - s) * eps / (1 + lam * s * eps)
    frames = _Frames(shape.corners)
    by_range = np.maximum(np.asarray(shape.range_reach(eps, sigma), dtype=float), 0.0)
    greedy = _Greedy(eps, sigma)
    corners = _corner_candidates(shape)
    edges = _edge_candidates(shape, eps, s, rng)
    for points, lfs in (corners, edges):
        greedy.visit(points, lfs, rng)
    greedy.close_slab()  # the feature samples stay in every slab's search
    made = len(corners[0]) + len(edges[0])

    count = len(frames.w)
    centroid = shape.corners.mean(axis=1)
    middle = np.full((count, 3), 1 / 3)
    first_lfs = _positive(shape.lfs_at(np.arange(count), middle, centroid), shape)
    # (L at the corners and centroids: the slabs are checked against L at every candidate)
    at_corners = shape.lfs_on(np.repeat(np.arange(count), 3), shape.corners.reshape(-1, 3))
    lfs_high = max(float(np.max(at_corners)), float(first_lfs.max()))
    # Small enough for thin slabs on a large part, never below the coarse cells at L_high.
    cap = max(
        math.sqrt(float(shape.areas.sum()) / FIRST_CELL_BUDGET),
        COARSE * float(k.max()) * lfs_high / math.sqrt(2),
    )
    # First cells as large as the cap allows: few per part; each slab cuts its own further.
    side = np.minimum(np.maximum(frames.w, frames.h), cap)
    cells = _first_cells(frames, side, eps)
    reach_margin = 1.5 * float(np.hypot(cells[3], cells[4]).max())
    axis = int(np.argmax(np.ptp(shape.corners.reshape(-1, 3), axis=0)))
    centre = frames.embed(cells[0], cells[1] + cells[3] / 2, cells[2] + cells[4] / 2)[:, axis]
    low, high = float(centre.min()), float(centre.max())
    per_slab = SLAB_CANDIDATES if MAX_SLAB_CANDIDATES is None else MAX_SLAB_CANDIDATES
    # Twice the conflict radius at the largest L of the corners: L at a candidate is checked
    # against the radius actually allowed (below).
    thick = 4 * s * eps * lfs_high + 2 * reach_margin
    slabs = max(1, min(math.ceil(expected / per_slab), math.floor((high - low) / thick)))
    width = (high - low) / slabs if slabs > 1 else math.inf
    allowed_radius = (width - 2 * reach_margin) if slabs > 1 else math.inf
    index = (
        np.zeros(len(centre), dtype=np.int64)
        if slabs == 1
        else np.minimum(((centre - low) / width).astype(np.int64), slabs - 1)
    )
    order = np.argsort(index, kind="stable")
    bounds = np.searchsorted(index[order], np.arange(slabs + 1))
    cells = tuple(c[order] for c in cells)
    del centre, index, order

    counter = Counter(progress, "sampling (slabs)", slabs)
    ratio = 0.0
    for slab in range(slabs):
        part = tuple(c[bounds[slab] : bounds[slab + 1]] for c in cells)
        n, r = _sample_slab(shape, frames, part, k, lam, by_range, eps, greedy, rng, allowed_radius)
        made += n
        ratio = max(ratio, r)
        greedy.close_slab()
        counter.step()
    points, lfs = greedy.result()
    if not len(points):
        raise InputError(f"{shape.name}: no candidates on the mesh")
    return points, lfs, made, ratio


def _sample_slab(shape, frames, cells, k, lam, by_range, eps, greedy, rng, allowed_radius):
    """Refine one slab's cells, visiting and certifying (module docstring); returns the
    candidates made and the largest reach ratio."""
    s = greedy.s
    made, ratio = 0, 0.0
    for _ in range(MAX_LEVELS):
        if not len(cells[0]):
            return made, ratio
        t, x0, y0, cw, ch = cells
        px = x0 + rng.random(len(t)) * cw
        py = y0 + rng.random(len(t)) * ch
        qx, qy = frames.closest(t, px, py)
        points = frames.embed(t, qx, qy)
        lfs = _positive(shape.lfs_at(t, frames.barycentric(t, qx, qy), points), shape)
        made += len(t)
        if not s * eps * float(lfs.max()) <= allowed_radius:
            raise InputError(
                f"{shape.name}: L = {float(lfs.max()):g} at a candidate exceeds what the slabs "
                "were made for"
            )
        diagonal = np.hypot(cw, ch)
        allowed = np.maximum(k[t] * lfs / (1 + k[t] * lam[t]), by_range[t])
        big = diagonal > COARSE * allowed
        visit = np.flatnonzero(~big)
        greedy.visit(points[visit], lfs[visit], rng)
        fine = ~big & (diagonal <= allowed)
        done = fine.copy()
        if fine.any():
            floor = np.maximum(lfs[fine] - lam[t[fine]] * diagonal[fine], 0)
            with np.errstate(divide="ignore"):
                reach = np.where(
                    by_range[t[fine]] >= diagonal[fine], 0, diagonal[fine] / (eps * floor)
                )
            ratio = max(ratio, float(reach.max()))
        test = np.flatnonzero(~big & ~fine)
        if len(test):
            centre = frames.embed(t[test], x0[test] + cw[test] / 2, y0[test] + ch[test] / 2)
            gap = greedy.nearest(centre)
            floor = lfs[test] - lam[t[test]] * diagonal[test]
            bound = gap + diagonal[test] / 2
            certified = bound < eps * floor * (1 - 1e-9)
            done[test[certified]] = True
            if certified.any():
                ratio = max(ratio, float((bound[certified] / (eps * floor[certified])).max()))
        cut = np.where(
            big, np.ceil(diagonal / (COARSE * np.maximum(allowed, 1e-300)) * (1 + 1e-9)), 2
        )
        rest = ~done
        cut = np.maximum(cut[rest], 2).astype(np.int64)
        cells = _cut(frames, t[rest], x0[rest], y0[rest], cw[rest], ch[rest], cut)
    raise InputError(f"{shape.name}: the lattice did not settle (L too small somewhere)")


class _Greedy:
    """Accepted samples and the greedy visit (the rule of :mod:`.greedy`): a search tree of
    the samples of the last closed slab and the features, and one of the open slab's."""

    def __init__(self, eps: float, sigma: float):
        self.eps, self.sigma = eps, sigma
        self.s = sigma * (1 + SPARSITY_SLACK)
        self.kept_points: list[np.ndarray] = []
        self.kept_lfs: list[np.ndarray] = []
        self.features = (np.zeros((0, 3)), np.zeros(0))
        self.last = (np.zeros((0, 3)), np.zeros(0))
        self.fixed: tuple | None = None  # (tree, points, lfs) of features + last closed slab
        self.open_points: list[np.ndarray] = []
        self.open_lfs: list[np.ndarray] = []
        self.open_tree: tuple | None = None
        self.first = True

    def close_slab(self) -> None:
        """The open slab's samples become the last slab (features: the first call)."""
        from scipy.spatial import cKDTree

        points = np.concatenate([np.zeros((0, 3)), *self.open_points])
        lfs = np.concatenate([np.zeros(0), *self.open_lfs])
        if self.first:
            self.features, self.first = (points, lfs), False
        else:
            self.kept_points.append(points)
            self.kept_lfs.append(lfs)
            self.last = (points, lfs)
        fixed_points = np.concatenate([self.features[0], self.last[0]])
        fixed_lfs = np.concatenate([self.features[1], self.last[1]])
        # Unbalanced, uncompacted trees: built in half the time, queried as fast (exact either way)
        self.fixed = None
        if len(fixed_points):
            tree = cKDTree(fixed_points, balanced_tree=False, compact_nodes=False)
            self.fixed = (tree, fixed_points, fixed_lfs)
        self.open_points, self.open_lfs, self.open_tree = [], [], None

    def result(self) -> tuple[np.ndarray, np.ndarray]:
        points = np.concatenate([self.features[0], *self.kept_points])
        lfs = np.concatenate([self.features[1], *self.kept_lfs])
        return points, lfs

    def visit(self, points: np.ndarray, lfs: np.ndarray, rng: np.random.Generator) -> None:
        """Visit the candidates in a random order; accept those without conflict."""
        count = len(points)
        if not count:
            return
        rank = rng.permutation(count)
        for start, stop in _chunks(count):
            ids = np.flatnonzero((rank >= start) & (rank < stop))
            for tree in (self.fixed, self._open()):
                if tree is not None and len(ids):
                    ids = ids[
                        ~_conflicts_with(tree[0], tree[2], points, lfs, ids, self.eps, self.sigma)
                    ]
            if not len(ids):
                continue
            ids = ids[np.argsort(rank[ids])]
            chosen = ids[_first_independent(points[ids], lfs[ids], self.eps, self.sigma)]
            chosen = np.sort(chosen)
            self.open_points.append(points[chosen])
            self.open_lfs.append(lfs[chosen])
            self.open_tree = None

    def _open(self):
        from scipy.spatial import cKDTree

        if self.open_tree is None and self.open_points:
            points = np.concatenate(self.open_points)
            lfs = np.concatenate(self.open_lfs)
            self.open_points, self.open_lfs = [points], [lfs]
            tree = cKDTree(points, balanced_tree=False, compact_nodes=False)
            self.open_tree = (tree, points, lfs)
        return self.open_tree

    def nearest(self, points: np.ndarray) -> np.ndarray:
        """Distance from each point to the nearest accepted sample in the searched trees
        (inf where there is none)."""
        from ...geometry.threads import thread_count

        gap = np.full(len(points), np.inf)
        for tree in (self.fixed, self._open()):
            if tree is not None:
                dist, _ = tree[0].query(points, k=1, workers=thread_count())
                gap = np.minimum(gap, dist)
        return gap
