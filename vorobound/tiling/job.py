"""The check's pipeline: one part of a check (a tile, or a whole sample as one tile), from
balls to guide rows and tallies.

A :class:`TileJob` carries the part's balls (a tile's core and halo, by increasing index, read
from its shard file; or a whole sample in memory, :meth:`TileJob.whole`, no halo, with L per
ball if it is known exactly) and the :class:`TileSettings` every part of one check shares.
:func:`check_part` runs the stages, each timed by the caller's clock:

1. ``triangulation``: the engine's candidate triples
   (:func:`~vorobound.sampling.guides.triangles.candidate_triples`: ``hull``, ``geogram`` or
   ``gudhi`` in slabs or as one regular triangulation, ``brute``), kept when their smallest
   vertex index is in the core;
2. ``seeds``: their seeds, classified with the whole set's lifting (W = ``top``); a whole
   check without a guide triangle stops here (:func:`no_guide_triangles`; a tiled check
   raises it after the merge, since a tile may have none);
3. ``conditions`` (only with ``measure_lipschitz``, a whole check of a mesh's L): λ measured
   from the neighbouring samples and the guide triangles' edges;
4. ``bounds`` (only when the settings carry none, a whole check: after λ): each mode's bound
   and the gap histogram's edges;
5. ``measure``: the guide triangles against the bounds, split by sharp features, tallied;
6. ``conditions``: sparsity and Lipschitz over the pairs the part owns;
7. ``rows``: the rows to the settings' sink (:class:`~vorobound.tiling.rows.PartFiles`, or
   :class:`~vorobound.tiling.rows.InMemory`) and the picks of the decimated VTU.

It returns a :class:`TileOutcome`: the mergeable :class:`Tallies`, the parameters and bounds
measured with, and the halo width the part needed (:mod:`vorobound.tiling.plan`).
:func:`run_tile` is a tiled check's worker: one thread, duplicate centers refused, then
:func:`check_part`. A whole check (:mod:`vorobound.reports.check`) calls :func:`check_part`
once, in process, on every thread, and adds the stages only a surface has (sampling before,
coverage after).

What still differs between a whole check and a tile is an option of this one pipeline, not a
second copy: the ``hull`` engine and GUDHI's slabs (``slabs``: a tile runs one regular
triangulation, so its candidate count can differ from a whole check's while its guide
triangles are the same), the exact L of an analytic surface (``lfs``), the measured λ
(``measure_lipschitz``: λ of a whole sample, so never per tile), and the owned pairs of a halo.

References
----------
The guide triangles and sampling conditions of Section 4.1; Theorem 1.
"""

from __future__ import annotations

import contextlib
import math
import os
import resource
import time
from collections.abc import Callable
from contextlib import AbstractContextManager
from dataclasses import dataclass

import numpy as np

from ..bounds.params import SamplingParams, Target
from ..errors import InputError, NoGuideTriangles
from ..geometry.threads import limited_threads
from ..progress import Progress
from ..sampling.balls import Balls
from ..sampling.guides.engines import Engine
from ..sampling.guides.measure import GuideMeasurements, ModeBound, measure_guides, mode_bounds
from ..sampling.guides.seeds import COVER_RTOL, classify, row_minima
from ..sampling.guides.triangles import candidate_triples
from ..sampling.sampler import conditions
from . import plan as tiles
from .rows import InMemory, PartFiles, PartRows, vtu_cells
from .tally import GuideTally, PairTally, gap_edges

VTU_FLAGGED = 1000
"""A tile adds at most this many triangles that break something to the decimated VTU."""
_HASH = np.array([73856093, 19349663, 83492791], dtype=np.uint64)

Clock = Callable[[str], AbstractContextManager]
"""Times a stage by name (``with clock("measure"): ...``) and keeps the seconds."""


@dataclass(frozen=True)
class TileSettings:
    """What every part of one check shares."""

    params: SamplingParams
    lipschitz: float | None
    engine: str
    """``geogram``, ``gudhi``, ``brute`` or (a whole check only) ``hull``
    (:class:`vorobound.sampling.guides.triangles.Engine`, resolved)."""
    top: float
    """W = the largest weight of the whole set (the seeds' lifting)."""
    bounds: tuple[ModeBound, ...] | None
    """Each mode's bound (None: the ``bounds`` stage computes them after λ)."""
    ratio_bounds: tuple[ModeBound, ...] | None
    edges: np.ndarray | None
    """Bin edges of the gap histogram (None: with the bounds)."""
    rows: PartFiles | InMemory | None
    """Where the per-triangle rows go (None: nowhere)."""
    vtu_share: float
    """Share of the guide triangles kept (uniformly) for the decimated VTU; 0: none."""
    what: str
    """The input's name, for messages (a whole check's source)."""
    total: int
    """Balls in the whole set."""
    features: object = None
    """:class:`vorobound.sampling.guides.features.SharpFeatures` of the part, or None."""
    slabs: bool = False
    """The ``gudhi`` and ``geogram`` engines cut space into slabs on threads (a whole check),
    else one regular triangulation (a tile, on one thread)."""
    measure_lipschitz: bool = False
    """λ is measured on the part (a whole sample of a mesh's L), not ``lipschitz``."""

    @classmethod
    def whole(
        cls,
        balls: Balls,
        params: SamplingParams,
        lipschitz: float | None,
        engine: Engine,
        what: str,
        features: object = None,
        measure_lipschitz: bool = False,
    ) -> TileSettings:
        """The settings of a whole check (one part, in process): ``engine`` resolved (``hull``
        allowed), GUDHI in slabs, the bounds computed after λ, the rows kept in memory."""
        return cls(
            params=params,
            lipschitz=lipschitz,
            engine=engine.value,
            top=float(balls.weights.max()),
            bounds=None,
            ratio_bounds=None,
            edges=None,
            rows=InMemory(),
            vtu_share=0.0,
            what=what,
            total=len(balls),
            features=features,
            slabs=True,
            measure_lipschitz=measure_lipschitz,
        )


@dataclass(frozen=True)
class TileJob:
    """A part's balls and halo (see :mod:`vorobound.tiling.plan`)."""

    tile: int
    ids: np.ndarray
    """Increasing indices of the balls in the whole set."""
    centers: np.ndarray
    radii: np.ndarray
    core: np.ndarray
    """True for the balls the part owns."""
    lo: np.ndarray
    hi: np.ndarray
    beta: float
    """Halo width (infinite: the whole set, no halo)."""
    settings: TileSettings
    lfs: np.ndarray | None = None
    """L per ball (None: r/δ)."""

    @classmethod
    def whole(cls, balls: Balls, settings: TileSettings, lfs: np.ndarray | None = None):
        """Every ball as one part that owns them all: a whole check."""
        count = len(balls)
        return cls(
            tile=0,
            ids=np.arange(count),
            centers=balls.centers,
            radii=balls.radii,
            core=np.ones(count, dtype=bool),
            lo=balls.centers.min(axis=0),
            hi=balls.centers.max(axis=0),
            beta=math.inf,
            settings=settings,
            lfs=lfs,
        )

    @property
    def is_whole(self) -> bool:
        return math.isinf(self.beta)


@dataclass(frozen=True)
class VtuRows:
    """Guide triangles picked for the decimated VTU: ball indices, their centers and radii
    (rows of three), and cell values."""

    triples: np.ndarray
    centers: np.ndarray
    radii: np.ndarray
    cells: dict[str, np.ndarray]


@dataclass(frozen=True)
class Tallies:
    """What the parts of a check add up (a whole check is one part): candidate triples, those
    with seeds, the half-covered ones, and the tallies of the guide triangles and of the pair
    conditions."""

    candidates: int
    with_seeds: int
    half_covered: int
    guides: GuideTally
    sparsity: PairTally
    lipschitz: PairTally


@dataclass(frozen=True)
class TileOutcome(Tallies):
    """What a part sends back."""

    tile: int
    balls: int
    """Balls in the core."""
    halo: int
    """Balls in the halo."""
    core_radius: float
    needed_beta: float
    """The β the tile needed (above its own: recompute it with a wider halo)."""
    sparsity_certain: float
    """Every owned pair with a sparsity ratio below this was seen."""
    seconds: dict[str, float]
    """Seconds per stage, by the caller's clock (a tile's: thread CPU seconds)."""
    pid: int
    peak_rss: int
    """The worker process's peak resident memory, bytes."""
    vtu: VtuRows | None
    engine: str
    params: SamplingParams
    """The parameters measured with (λ included)."""
    bounds: tuple[ModeBound, ...]
    ratio_bounds: tuple[ModeBound, ...]
    kept: PartRows | None = None
    """The rows, where the sink keeps them in memory."""


def no_guide_triangles(source: str, with_seeds: int, half_covered: int) -> NoGuideTriangles:
    """The error of a check that found no guide triangle (tiled or not)."""
    return NoGuideTriangles(
        f"{source}: no guide triangle to measure ({with_seeds:,} triples of balls "
        f"meet in a seed pair, {half_covered:,} of them half-covered): a VoroCrust sample of a "
        "closed surface has guide triangles all over it; are the radii δ·L too small for the "
        "spacing of the centers?"
    )


def run_tile(job: TileJob) -> TileOutcome:
    """A tiled check's worker: one part (module docstring) on one thread."""
    with limited_threads(1):
        _refuse_duplicates(job)
        return check_part(job)


def check_part(
    job: TileJob, clock: Clock | None = None, progress: Progress | None = None
) -> TileOutcome:
    """The check of one part, stage by stage (module docstring); ``clock`` times the stages
    (default: thread CPU seconds), ``progress`` reports the engine's and the seeds' steps."""
    s = job.settings
    if s.measure_lipschitz and not job.is_whole:
        raise InputError("a measured λ is the whole sample's: not in tiles (give lipschitz)")
    clock = clock or _Clock()
    balls = Balls(job.centers, job.radii)
    core = job.core
    owned = None if job.is_whole else core
    with clock("triangulation"):
        triples = candidate_triples(balls, Engine(s.engine), s.slabs, progress)
        # Local order is the global order (ids increase), so the smallest local index is the
        # smallest ball index: its owner counts the triangle.
        if not job.is_whole:
            triples = triples[core[row_minima(triples)]]
    with clock("seeds"):
        seeded = classify(balls, triples, progress, top=s.top)
        has = seeded.has_seeds
        guide = seeded.take(seeded.guide)
        with_seeds, half_covered = int(has.sum()), int(seeded.half_covered.sum())
        seed_reach = 0.0 if job.is_whole else _seed_reach(seeded, has, balls, job)
        del seeded  # every candidate's geometry: not kept through the later stages
    if job.is_whole and len(guide.triples) == 0:
        raise no_guide_triangles(s.what, with_seeds, half_covered)  # a tile may have none
    lfs = balls.radii / s.params.delta if job.lfs is None else job.lfs
    near, lam = None, s.lipschitz
    if s.measure_lipschitz:
        with clock("conditions"):
            near = conditions.neighbours(balls.centers, owned)
            lam = conditions.measured_lipschitz(balls.centers, lfs, guide.triples, near)
    params, bounds, ratios, edges = s.params, s.bounds, s.ratio_bounds, s.edges
    if bounds is None or ratios is None or edges is None:
        with clock("bounds"):
            params = params.but(lipschitz=lam)
            bounds = tuple(mode_bounds(params, Target.additive))
            ratios = tuple(mode_bounds(params, Target.ratio))
            edges = gap_edges(params, [b.value / params.eps for b in bounds])
    with clock("measure"):
        guides = measure_guides(guide, lfs, params, list(bounds), list(ratios))
        guides = guides.with_features(balls.centers, balls.radii, s.features)
        tally = GuideTally.of(guides, job.ids, balls.centers, params, edges)
    with clock("conditions"):
        near = near or conditions.neighbours(balls.centers, owned)
        sparse = conditions.sparsity(balls.centers, lfs, params.eps, params.sigma, near)
        lipschitz = conditions.lipschitz(balls.centers, lfs, lam, near)
    kept, vtu = None, None
    with clock("rows"):
        if s.rows is not None:
            rows = PartRows(job.tile, job.ids, guides, guide.geometry.circumcenter)
            kept = s.rows.take(rows)
        if s.vtu_share > 0:
            vtu = _vtu_rows(job, guides)
    core_radius = float(balls.radii[core].max())
    sparsity_reach = params.sigma / params.quality.delta_ratio
    needed_beta, certain = 0.0, math.inf
    if not job.is_whole:
        neighbour_reach = float(near.farthest[core].max())
        if len(balls) < min(conditions.NEIGHBOURS + 1, s.total):
            neighbour_reach = job.beta  # fewer balls than neighbours: ask for a wider halo
        needed_beta = tiles.needed_halo(core_radius, sparsity_reach, seed_reach, neighbour_reach)
        certain = job.beta / (sparsity_reach * core_radius)
    return TileOutcome(
        tile=job.tile,
        balls=int(core.sum()),
        halo=int((~core).sum()),
        candidates=len(triples),
        with_seeds=with_seeds,
        half_covered=half_covered,
        guides=tally,
        sparsity=PairTally.of(sparse, job.ids, balls.centers),
        lipschitz=PairTally.of(lipschitz, job.ids, balls.centers),
        core_radius=core_radius,
        needed_beta=needed_beta,
        sparsity_certain=certain,
        seconds=getattr(clock, "seconds", {}),
        pid=os.getpid(),
        peak_rss=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024,
        vtu=vtu,
        engine=s.engine,
        params=params,
        bounds=bounds,
        ratio_bounds=ratios,
        kept=kept,
    )


class _Clock:
    """Thread CPU seconds per stage."""

    def __init__(self) -> None:
        self.seconds: dict[str, float] = {}

    @contextlib.contextmanager
    def __call__(self, name: str):
        start = time.thread_time()
        try:
            yield
        finally:
            spent = time.thread_time() - start
            self.seconds[name] = self.seconds.get(name, 0.0) + spent


def _refuse_duplicates(job: TileJob) -> None:
    """Equal centers fall in the same tile's core: refuse them as make_balls does."""
    centers = job.centers[job.core]
    # Equal centers have equal x: only the rows whose x occurs twice are sorted in full.
    x = np.sort(centers[:, 0])
    repeated = x[1:][x[1:] == x[:-1]]
    rows = np.flatnonzero(np.isin(centers[:, 0], repeated))
    order = rows[np.lexsort(centers[rows].T[::-1])]
    same = np.flatnonzero((np.diff(centers[order], axis=0) == 0).all(axis=1))
    if len(same):
        ids = job.ids[job.core]
        first, second = sorted((int(ids[order[same[0]]]), int(ids[order[same[0] + 1]])))
        raise InputError(
            f"{job.settings.what}: centers {first} and {second} coincide ({len(same)} "
            "duplicate pairs in that part of space)"
        )


def _seed_reach(seeded, has: np.ndarray, balls: Balls, job: TileJob) -> float:
    """How far beyond the box a ball covering a seed of an owned triple can lie, less its
    radius: the seed's distance to the box plus the cover tolerance (seeds.COVER_RTOL)."""
    if not has.any():
        return 0.0
    seeds, triples = seeded.seeds, seeded.triples
    if not has.all():
        seeds, triples = seeds[has], triples[has]
    w_min = row_minima(balls.weights[triples])
    gap = np.maximum(
        tiles.box_distance(seeds[:, 0], job.lo, job.hi),
        tiles.box_distance(seeds[:, 1], job.lo, job.hi),
    )
    gap += math.sqrt(COVER_RTOL) * np.sqrt(w_min)  # r_min
    return float(gap.max())


def _vtu_rows(job: TileJob, guides: GuideMeasurements) -> VtuRows:
    """A uniform share of the tile's guide triangles (by a hash of their indices, so the pick
    does not depend on the tiling) plus up to VTU_FLAGGED that break a bound or condition."""
    s = job.settings
    triples = job.ids[guides.triples]
    key = np.sort(triples, axis=1).astype(np.uint64) * _HASH
    spread = (key[:, 0] ^ key[:, 1] ^ key[:, 2]) % np.uint64(1 << 30)
    picked = spread < np.uint64(int(s.vtu_share * (1 << 30)))
    flagged = ~guides.inside | (guides.h3_ratio > 1) | (guides.rho > s.params.rho_f)
    for rows in (*guides.exceeds.values(), *(guides.exceeds_ratio or {}).values()):
        flagged |= rows
    extra = np.flatnonzero(flagged & ~picked)
    extra = extra[np.argsort(-guides.gap_ratio[extra], kind="stable")][:VTU_FLAGGED]
    picked[extra] = True
    rows = np.flatnonzero(picked)
    local = guides.triples[rows]
    return VtuRows(
        triples=triples[rows],
        centers=job.centers[local],
        radii=job.radii[local],
        cells=vtu_cells(guides, rows),
    )
