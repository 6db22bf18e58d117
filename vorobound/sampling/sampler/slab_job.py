"""One slab of the slab sampler (:mod:`.slabs`), as a worker computes it.

A :class:`SlabJob` carries the slab's first cells, what every slab shares (the shape, the
triangles' frames and constants) and the fixed samples its candidates are compared with: the
feature samples and, for an odd slab, the samples of its two finished neighbours.
:func:`run_slab` refines the cells (the module docstring of :mod:`.slabs`) with the slab's own
random generator and returns the slab's samples.
"""

from __future__ import annotations

import contextlib
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from ...errors import InputError
from ...geometry.threads import limited_threads
from .greedy import _chunks, _conflicts_with, _first_independent
from .lattice import SPARSITY_SLACK
from .mesh_lattice import MAX_LEVELS, _cut, _Frames, _positive

COARSE = 3.0
"""Candidates are visited in cells up to this many times the diagonal the lattice condition
allows; larger cells are cut first. Measured on the capped cylinder at ε = 0.03: 2 gives the
fewest candidates per sample."""


class _MeshWithL(Protocol):
    """What a slab needs of the part: its name and L at points of its triangles."""

    name: str

    def lfs_at(self, triangle: np.ndarray, bary: np.ndarray, points: np.ndarray) -> np.ndarray:
        """L at the points ``points`` (barycentric ``bary`` in triangles ``triangle``)."""
        ...


@dataclass(frozen=True)
class SlabShared:
    """What every slab of one run shares."""

    shape: _MeshWithL
    frames: _Frames
    k: np.ndarray
    """(1 − σ')ε/(1 + λσ'ε) per triangle (:mod:`.mesh_lattice`)."""
    lam: np.ndarray
    """λ per triangle."""
    by_range: np.ndarray
    """Cell diagonals below which a triangle's range of L alone covers (per triangle)."""
    eps: float
    sigma: float
    allowed_radius: float
    """The largest conflict radius σ'εL(q) the slab width allows (w − 2m)."""
    threads: int | None
    """Threads of a worker (None: the process's setting)."""


@dataclass(frozen=True)
class SlabJob:
    """One slab: its first cells, its generator's seed and the samples it is compared with."""

    slab: int
    cells: tuple
    """(triangle, x0, y0, width, height) of the first cells whose centres lie in the slab."""
    seed: tuple[int, int]
    fixed_points: np.ndarray
    """Feature samples, then the samples of slab − 1 and slab + 1 (odd slabs)."""
    fixed_lfs: np.ndarray
    shared: SlabShared


@dataclass(frozen=True)
class SlabDone:
    """A finished slab: its samples (in acceptance order), candidates made, reach ratio."""

    slab: int
    points: np.ndarray
    lfs: np.ndarray
    made: int
    ratio: float


def run_slab(job: SlabJob) -> SlabDone:
    """Sample one slab (module docstring of :mod:`.slabs`)."""
    shared = job.shared
    budget = limited_threads(shared.threads) if shared.threads else contextlib.nullcontext()
    with budget:
        greedy = Greedy(shared.eps, shared.sigma, job.fixed_points, job.fixed_lfs)
        rng = np.random.default_rng(list(job.seed))
        made, ratio = refine(shared, job.cells, greedy, rng)
        points, lfs = greedy.own()
    return SlabDone(job.slab, points, lfs, made, ratio)


def refine(shared: SlabShared, cells, greedy: Greedy, rng: np.random.Generator):
    """Refine one slab's cells, visiting and certifying (module docstring of :mod:`.slabs`);
    returns the candidates made and the largest reach ratio."""
    shape, frames, k, lam, by_range = (
        shared.shape,
        shared.frames,
        shared.k,
        shared.lam,
        shared.by_range,
    )
    eps, s = shared.eps, greedy.s
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
        if not s * eps * float(lfs.max()) <= shared.allowed_radius:
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


class Greedy:
    """Accepted samples and the greedy visit (the rule of :mod:`.greedy`): a search tree of
    the fixed samples (features, finished neighbour slabs) and one of the samples accepted
    here."""

    def __init__(self, eps: float, sigma: float, fixed_points=None, fixed_lfs=None):
        from scipy.spatial import cKDTree

        self.eps, self.sigma = eps, sigma
        self.s = sigma * (1 + SPARSITY_SLACK)
        fixed = fixed_points is not None and len(fixed_points)
        # Unbalanced, uncompacted trees: built in half the time, queried as fast (exact
        # either way).
        self.fixed = None
        if fixed:
            tree = cKDTree(fixed_points, balanced_tree=False, compact_nodes=False)
            self.fixed = (tree, fixed_points, fixed_lfs)
        self.open_points: list[np.ndarray] = []
        self.open_lfs: list[np.ndarray] = []
        self.open_tree: tuple | None = None

    def own(self) -> tuple[np.ndarray, np.ndarray]:
        """The samples accepted here, in acceptance order."""
        points = np.concatenate([np.zeros((0, 3)), *self.open_points])
        lfs = np.concatenate([np.zeros(0), *self.open_lfs])
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
            self.open_tree = (
                cKDTree(points, balanced_tree=False, compact_nodes=False),
                points,
                lfs,
            )
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
