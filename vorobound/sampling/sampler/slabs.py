"""The mesh sampler in slabs: memory bounded by a slab, few candidates per sample, exact.

The part is cut into slabs along the longest axis of its bounding box. Feature corners and
edges are sampled first over the whole part (VoroCrust protects sharp features first); their
samples stay in memory. The first cells of every triangle (the plane frames of
:mod:`.mesh_lattice`) go to the slab of their centre, and each slab refines only its own
cells (:func:`.slab_job.refine`):

1. Every cell gets a candidate (the point of its triangle nearest a random point of the cell)
   and L there. A cell more than ``COARSE`` times larger than the lattice condition of
   :mod:`.mesh_lattice` allows is cut without visiting its candidate.
2. The other candidates are visited in a random order, each accepted unless an accepted sample
   is within σ'ε·min(L) of it (the greedy rule of :mod:`.greedy`, the same chunked visit).
3. A visited cell is done when it meets the lattice condition (then every point of it is
   within εL of a sample by :func:`.lattice.cell_reach`, whether its candidate was accepted or
   not), or when it is *certified*: with C its centre, d its diagonal, q its candidate and p
   the accepted sample nearest to C among those the slab searches, |C − p| + d/2 <
   ε(L(q) − λd). Every point x of the cell (within d/2 of C, and of its triangle within d of
   q) then has |x − p| < εL(x), since L(x) ≥ L(q) − λ|x − q|. Other cells are cut in 2 × 2
   and go back to step 1.

The slabs are two-coloured: first every even slab is sampled, compared with the feature
samples and its own samples only; then every odd slab i, compared with the feature samples,
the samples of slabs i − 1 and i + 1 (both finished) and its own. Slabs of one colour do not
depend on one another, so they run concurrently (:func:`vorobound.parallel.task_executor`:
this process, a local process pool, or a dask cluster), each with a random generator of its
own seeded by (the run's seed, the slab): the sample is fixed by the seed whatever the number
of workers and the order in which slabs finish. An odd slab starts as soon as its two
neighbours are done, and a finished slab is handed on (to a file, :mod:`vorobound.reports.
sample`) in slab order and dropped once its odd neighbours are done, so memory holds a few
slabs, not the sample.

Sparsity holds by the greedy rule as long as each candidate is compared with every accepted
sample within its conflict radius. A candidate lies within m = 1.5 times the largest
first-cell diagonal of its cell's centre, so along the axis a candidate of slab i is at least
w − 2m from any sample of slabs i ± 2 and beyond (w the slab width); slabs are at least
``4·σ'ε·L_max + 2m`` wide and every candidate's σ'εL(q) is checked against w − 2m (an error,
never a silent miss). So a candidate of an even slab conflicts with no sample of another even
slab, and a candidate of an odd slab i can conflict only with samples of slabs i − 1, i, i + 1
and the features, which are the samples it is compared with; two odd slabs are at least w − 2m
apart too. The whole run is one visiting order of the greedy rule (features, the even slabs,
the odd slabs), so the sample is σ-sparse. Coverage holds because every point of the surface
lies in a done cell, and a certifying sample, whichever slab it belongs to, stays in the
sample. Both are proven by construction; the measured coverage and sparsity of
:mod:`.conditions` only confirm them.

Certified cells need no candidates below them: about 6 candidates per sample instead of the
plain lattice's 30 (σ = 0.75).
"""

from __future__ import annotations

import concurrent.futures
import math
import os
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ...errors import InputError
from ...parallel import task_executor, task_result
from ...progress import Counter
from .lattice import SPARSITY_SLACK, candidate_limit_error
from .mesh_lattice import (
    _corner_candidates,
    _edge_candidates,
    _first_cells,
    _Frames,
    _positive,
    expected_candidates,
)
from .slab_job import COARSE, Greedy, SlabDone, SlabJob, SlabShared, run_slab

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
SLABS_PER_WORKER = 2
"""Slabs in flight per worker: enough that a worker rarely waits, few enough that memory holds
a few slabs."""

Sink = Callable[[np.ndarray, np.ndarray], None]
"""Receives blocks of samples (points (n, 3), L (n,)): the feature samples, then each slab's
in slab order."""


@dataclass(frozen=True)
class SlabRun:
    """What the slab sampler made."""

    made: int
    """Candidates made."""
    reach_ratio: float
    """The largest guaranteed distance of a surface point to a candidate of a lattice cell or
    to the certifying sample of a certified cell, over ε·L there."""
    axis: int
    """The axis along which the part is cut."""
    borders: np.ndarray
    """(slabs + 1,) coordinates of the slab borders along the axis (cell centres of slab i
    lie in [borders[i], borders[i + 1]]; the outer ones are the extreme centres)."""
    margin: float
    """m: a sample of slab i lies within m of [borders[i], borders[i + 1]] along the axis."""
    rows: tuple[int, ...]
    """Samples handed to the sink in each block: the features, then each slab."""
    points: np.ndarray | None = None
    """Every sample (features, then slab by slab) when no sink was given."""
    lfs: np.ndarray | None = None


def slab_sample(
    shape,
    eps: float,
    sigma: float,
    rng: np.random.Generator,
    progress=None,
    *,
    workers: int = 1,
    scheduler: str | None = None,
    sink: Sink | None = None,
) -> SlabRun:
    """A σ-sparse ε-sample of a mesh shape, slab by slab (module docstring).

    ``workers`` local processes (1: this process) or a dask ``scheduler`` sample the slabs of
    one colour concurrently; the sample is the same for any number of workers. With ``sink``
    the samples are handed to it block by block (features, then slab by slab) and not kept;
    without, they are returned in :attr:`SlabRun.points`.

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
    greedy = Greedy(eps, sigma)
    corners = _corner_candidates(shape)
    edges = _edge_candidates(shape, eps, s, rng)
    for points, lfs in (corners, edges):
        greedy.visit(points, lfs, rng)
    features = greedy.own()  # compared with every slab's candidates
    made = len(corners[0]) + len(edges[0])
    base = int(rng.integers(1 << 62))  # the slabs' generators: (base, slab)

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
    # against the radius actually allowed (run_slab).
    thick = 4 * s * eps * lfs_high + 2 * reach_margin
    slabs = max(1, min(math.ceil(expected / per_slab), math.floor((high - low) / thick)))
    width = (high - low) / slabs if slabs > 1 else math.inf
    index = (
        np.zeros(len(centre), dtype=np.int64)
        if slabs == 1
        else np.minimum(((centre - low) / width).astype(np.int64), slabs - 1)
    )
    order = np.argsort(index, kind="stable")
    bounds = np.searchsorted(index[order], np.arange(slabs + 1))
    cells = tuple(c[order] for c in cells)
    del centre, index, order
    borders = low + (high - low) * np.arange(slabs + 1) / slabs

    collected: list[tuple[np.ndarray, np.ndarray]] = []
    hand_on = sink if sink is not None else (lambda p, f: collected.append((p, f)))
    hand_on(*features)
    with task_executor(workers, scheduler) as (executor, slots):
        shared = SlabShared(
            shape,
            frames,
            k,
            lam,
            by_range,
            eps,
            sigma,
            (width - 2 * reach_margin) if slabs > 1 else math.inf,
            # Processes share the cores: one thread each beyond one worker.
            None if slots == 1 else max(1, (os.cpu_count() or 1) // slots),
        )
        jobs = _Jobs(shared, cells, bounds, base, features)
        run = _schedule(
            executor, slots, jobs, slabs, hand_on, Counter(progress, "sampling (slabs)", slabs)
        )
    made += run[0]
    rows = (len(features[0]), *run[2])
    points = lfs = None
    if sink is None:
        points = np.concatenate([p for p, _ in collected])
        lfs = np.concatenate([f for _, f in collected])
        if not len(points):
            raise InputError(f"{shape.name}: no candidates on the mesh")
    elif not sum(rows):
        raise InputError(f"{shape.name}: no candidates on the mesh")
    return SlabRun(made, run[1], axis, borders, reach_margin, rows, points, lfs)


@dataclass(frozen=True)
class _Jobs:
    """Builds the job of a slab from the run's shared data and its neighbours' samples."""

    shared: SlabShared
    cells: tuple
    bounds: np.ndarray
    base: int
    features: tuple[np.ndarray, np.ndarray]

    def job(self, slab: int, finished: dict[int, SlabDone]) -> SlabJob:
        part = tuple(c[self.bounds[slab] : self.bounds[slab + 1]] for c in self.cells)
        near = [finished[n] for n in (slab - 1, slab + 1) if slab % 2 and n in finished]
        points = np.concatenate([self.features[0], *(d.points for d in near)])
        lfs = np.concatenate([self.features[1], *(d.lfs for d in near)])
        return SlabJob(slab, part, (self.base, slab), points, lfs, self.shared)


def _schedule(executor, slots: int, jobs: _Jobs, slabs: int, hand_on: Sink, counter: Counter):
    """Run the slabs, even ones first, each odd one once its neighbours are done; hand the
    finished slabs on in slab order. Returns (candidates made, reach ratio, rows per slab)."""
    finished: dict[int, SlabDone] = {}
    pending: dict[concurrent.futures.Future, int] = {}
    next_even, next_odd, emitted = 0, 1, 0
    made, ratio, rows = 0, 0.0, []

    def ready(odd: int) -> bool:
        return all(n in finished for n in (odd - 1, odd + 1) if n < slabs)

    while emitted < slabs:
        while len(pending) < SLABS_PER_WORKER * slots:
            if next_odd < slabs and ready(next_odd):
                slab, next_odd = next_odd, next_odd + 2
            elif next_even < slabs and next_even <= next_odd + 2 * SLABS_PER_WORKER * slots - 1:
                slab, next_even = next_even, next_even + 2
            else:
                break
            pending[executor.submit(run_slab, jobs.job(slab, finished))] = slab
        done, _ = concurrent.futures.wait(pending, return_when=concurrent.futures.FIRST_COMPLETED)
        for future in sorted(done, key=pending.__getitem__):
            slab = pending.pop(future)
            finished[slab] = task_result(future, f"slab {slab}")
            made += finished[slab].made
            ratio = max(ratio, finished[slab].ratio)
            counter.step()
        while emitted in finished and emitted < slabs:
            hand_on(finished[emitted].points, finished[emitted].lfs)
            rows.append(len(finished[emitted].points))
            emitted += 1
        # An even slab is kept until both odd neighbours are done (their jobs hold its samples).
        for slab in [s for s in finished if s < emitted]:
            if slab % 2 or all(n < next_odd for n in (slab - 1, slab + 1) if 0 <= n < slabs):
                del finished[slab]
    return made, ratio, rows
