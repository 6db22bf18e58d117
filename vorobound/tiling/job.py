"""One tile of a tiled check, as a worker computes it.

A :class:`TileJob` carries the tile's balls (core and halo, by increasing index), its box and
halo width β; :func:`run_tile` finds the candidate triples of the tile's regular triangulation,
keeps those whose smallest vertex index is in the core, classifies their seeds with the whole
set's lifting, measures the guide triangles, checks the pair conditions of the owned balls,
writes the tile's rows if asked, and returns a :class:`TileOutcome` of mergeable tallies and
the halo width the tile needed (:mod:`vorobound.tiling.plan`). It runs on one thread.

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
from dataclasses import dataclass

import numpy as np

from ..bounds.params import SamplingParams
from ..errors import InputError, WriteError
from ..geometry.threads import limited_threads
from ..sampling.balls import Balls
from ..sampling.guides.measure import GuideMeasurements, ModeBound, measure_guides
from ..sampling.guides.seeds import COVER_RTOL, classify
from ..sampling.guides.triangles import Engine, overlap_triples, regular_triangles
from ..sampling.sampler import conditions
from . import plan as tiles
from .rows import guide_columns, part_path, vtu_cells, write_part
from .tally import GuideTally, PairTally

VTU_FLAGGED = 1000
"""A tile adds at most this many triangles that break something to the decimated VTU."""
_HASH = np.array([73856093, 19349663, 83492791], dtype=np.uint64)


@dataclass(frozen=True)
class TileSettings:
    """What every tile of one check shares."""

    params: SamplingParams
    lipschitz: float | None
    engine: str
    """``gudhi`` or ``brute`` (:class:`vorobound.sampling.guides.triangles.Engine`)."""
    top: float
    """W = the largest weight of the whole set (the seeds' lifting)."""
    bounds: tuple[ModeBound, ...]
    ratio_bounds: tuple[ModeBound, ...]
    edges: np.ndarray
    """Bin edges of the gap histogram."""
    table: str
    """How the rows are written: ``parquet``, ``npz``, ``csv`` or ``none``
    (:data:`vorobound.tiling.rows.TABLES`)."""
    parts: str | None
    """Folder for the tiles' row files."""
    vtu_share: float
    """Share of the guide triangles kept (uniformly) for the decimated VTU; 0: none."""
    what: str
    """The input's name, for messages."""
    total: int
    """Balls in the whole set."""
    features: object = None
    """:class:`vorobound.sampling.guides.features.SharpFeatures` of the part, or None."""


@dataclass(frozen=True)
class TileJob:
    """A tile's balls and halo (see :mod:`vorobound.tiling.plan`)."""

    tile: int
    ids: np.ndarray
    """Increasing indices of the balls in the whole set."""
    centers: np.ndarray
    radii: np.ndarray
    core: np.ndarray
    """True for the balls the tile owns."""
    lo: np.ndarray
    hi: np.ndarray
    beta: float
    settings: TileSettings


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
    """What the tiles of a check add up (and what a whole check's summary is built from):
    candidate triples, those with seeds, the half-covered ones, and the tallies of the guide
    triangles and of the pair conditions."""

    candidates: int
    with_seeds: int
    half_covered: int
    guides: GuideTally
    sparsity: PairTally
    lipschitz: PairTally


@dataclass(frozen=True)
class TileOutcome(Tallies):
    """What a tile sends back."""

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
    """Thread CPU seconds per stage."""
    pid: int
    peak_rss: int
    """The worker process's peak resident memory, bytes."""
    vtu: VtuRows | None


def run_tile(job: TileJob) -> TileOutcome:
    """Compute one tile (module docstring) on one thread."""
    with limited_threads(1):
        return _run(job)


def _run(job: TileJob) -> TileOutcome:
    s = job.settings
    clock = _Clock()
    balls = Balls(job.centers, job.radii)
    core = job.core
    _refuse_duplicates(job)
    with clock("triangulation"):
        if s.engine == Engine.brute.value:
            triples = overlap_triples(balls)
        else:
            triples = regular_triangles(balls.centers, balls.weights)
        # Local order is the global order (ids increase), so the smallest local index is the
        # smallest ball index: its owner counts the triangle.
        triples = np.sort(triples[core[triples.min(axis=1)]], axis=1)
    with clock("seeds"):
        seeded = classify(balls, triples, top=s.top)
        has = seeded.has_seeds
        seed_reach = _seed_reach(seeded, has, balls, job)
        found = seeded.take(seeded.uncovered.any(axis=1))
        guide = found.take(found.guide)
    lfs = balls.radii / s.params.delta
    with clock("measure"):
        guides = measure_guides(guide, lfs, s.params, list(s.bounds), list(s.ratio_bounds))
        guides = guides.with_features(balls.centers, balls.radii, s.features)
        tally = GuideTally.of(guides, job.ids, balls.centers, s.params, s.edges)
    with clock("conditions"):
        near = conditions.neighbours(balls.centers, owned=core)
        sparse = conditions.sparsity(balls.centers, lfs, s.params.eps, s.params.sigma, near)
        lipschitz = conditions.lipschitz(balls.centers, lfs, s.lipschitz, near)
        neighbour_reach = float(near.farthest[core].max())
        if len(balls) < min(conditions.NEIGHBOURS + 1, s.total):
            neighbour_reach = job.beta  # fewer balls than neighbours: ask for a wider halo
    vtu = None
    with clock("rows"):
        if s.table != "none":
            _write_rows(job, guides)
        if s.vtu_share > 0:
            vtu = _vtu_rows(job, guides)
    core_radius = float(balls.radii[core].max())
    sparsity_reach = s.params.sigma / s.params.quality.delta_ratio
    return TileOutcome(
        tile=job.tile,
        balls=int(core.sum()),
        halo=int((~core).sum()),
        candidates=len(triples),
        with_seeds=int(has.sum()),
        half_covered=int(found.half_covered.sum()),
        guides=tally,
        sparsity=PairTally.of(sparse, job.ids, balls.centers),
        lipschitz=PairTally.of(lipschitz, job.ids, balls.centers),
        core_radius=core_radius,
        needed_beta=tiles.needed_halo(core_radius, sparsity_reach, seed_reach, neighbour_reach),
        sparsity_certain=job.beta / (sparsity_reach * core_radius),
        seconds=clock.seconds,
        pid=os.getpid(),
        peak_rss=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024,
        vtu=vtu,
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
    seeds = seeded.seeds[has]
    r_min = np.sqrt(balls.weights[seeded.triples[has]].min(axis=1))
    gap = np.maximum(
        tiles.box_distance(seeds[:, 0], job.lo, job.hi),
        tiles.box_distance(seeds[:, 1], job.lo, job.hi),
    )
    return float((gap + math.sqrt(COVER_RTOL) * r_min).max())


def _write_rows(job: TileJob, guides: GuideMeasurements) -> None:
    """The tile's rows (the columns of triangles.csv, global ball indices) as one part file."""
    s = job.settings
    columns = guide_columns(guides, job.ids[guides.triples])
    try:
        write_part(part_path(str(s.parts), job.tile, s.table), columns)
    except OSError as exc:
        raise WriteError(
            f"cannot write the rows of tile {job.tile} into {s.parts}: "
            f"{exc.strerror or exc} (on a cluster the output folder must be on a file system "
            "its workers share)"
        ) from None


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
