"""The tile engine: a ball file checked in tiles with halos, streamed, on any executor.

:func:`run_tiles` never holds the whole sample, its triangles or their rows in one process:

1. **Read** the file in chunks (:mod:`vorobound.sampling.io.stream`), check every row, copy
   the balls to a temporary binary file (the spill) and keep the bounding box, the largest
   weight W (the seeds' lifting) and a systematic subsample of the centers.
2. **Plan** tiles by quantile splits of the subsample (:mod:`vorobound.tiling.plan`); one
   pass over the spill gives each tile's core radius R_T, hence its first halo width.
3. **Route** each ball to its own tile and to the halos it belongs to (one more pass), as one
   shard file per tile, balls in increasing index.
4. **Run** the tiles (:func:`vorobound.tiling.job.run_tile`) on a ``concurrent.futures``
   executor (:func:`vorobound.parallel.task_executor`: in process, a local process pool, or a
   dask.distributed cluster), a few per worker at a time, and merge their tallies
   (:mod:`vorobound.tiling.tally`). Tiles whose halo turned out too thin are routed and run
   again with the width they asked for.

Memory: the driver holds chunks, the subsample and per-tile tallies (independent of the number
of balls); a worker holds one tile. The check's report is assembled from the
:class:`TiledRun` in :mod:`vorobound.reports.check_tiled`.

References
----------
The guide triangles, sampling conditions and bounds of Section 4.1.
"""

from __future__ import annotations

import concurrent.futures
import dataclasses
import math
import os
import resource
import shutil
import tempfile
import time
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError, VoroboundError
from ..files import TEMP_PREFIX
from ..parallel import task_executor, task_result
from ..progress import Counter, Progress
from ..sampling.balls import MIN_BALLS
from ..sampling.io.stream import CHUNK_ROWS, ball_chunks
from . import plan as tiles
from .job import Tallies, TileJob, TileOutcome, TileSettings, VtuRows, run_tile
from .tally import GuideTally, PairTally

TILE_BALLS = 150_000
"""Balls aimed at per tile's core (a worker computing such tiles peaks at about 0.9 GB); the
tile count is rounded to an even number, so a tile holds up to ``MAX_TILE_SHARE`` times
this."""
MAX_TILE_SHARE = 1.25
"""Tiles hold at most this multiple of ``TILE_BALLS`` (else the count is rounded up)."""
IN_FLIGHT = 2
"""Tiles submitted per worker at a time (the driver holds at most this many tiles' balls)."""
VTU_TRIANGLES = 200_000
"""About this many guide triangles go to the decimated VTU (all of them below it)."""
MAX_ROUNDS = 4
"""Runs of a tile at most (the first, then with wider halos)."""
HALO_GROWTH = 1.25
"""A tile run again gets this much more than the width it asked for."""
_RECORD = np.dtype([("id", "<i8"), ("ball", "<f8", (4,)), ("core", "u1")])
"""A ball in a shard file: index, x, y, z, r, and whether the tile owns it."""


def tile_count(balls: int) -> int:
    """Tiles of a check of ``balls``, whatever the number of workers: one up to
    ``MAX_TILE_SHARE``·``TILE_BALLS`` balls, else the even number nearest to
    balls/``TILE_BALLS`` (rounded up where tiles would exceed ``MAX_TILE_SHARE``·
    ``TILE_BALLS``). Every worker count computes the same tiles, so the answer, candidate
    counts included, and the CPU time spent on halos are those of one worker; workers take
    tiles from a queue, and an even count splits evenly between two (docs/performance.md)."""
    if balls <= MAX_TILE_SHARE * TILE_BALLS:
        return 1
    pairs = max(1, math.floor(balls / (2 * TILE_BALLS) + 0.5))
    while balls / (2 * pairs) > MAX_TILE_SHARE * TILE_BALLS:
        pairs += 1
    return 2 * pairs


def tile_size(balls: int) -> int:
    """Balls per tile of :func:`tile_count` tiles of equal size."""
    return max(1, math.ceil(balls / tile_count(balls)))


@dataclass(frozen=True)
class Tiling:
    """How a tiled check was cut and run."""

    tiles: int
    halo_balls: int
    """Balls in halos, over the tiles' final runs (copies beyond the sample's own)."""
    rounds: int
    rerun: int
    """Tile runs beyond one per tile (halos that turned out too thin)."""
    executor: str
    workers: int
    """Tiles that run at once."""
    worker_peak_bytes: dict[int, int]
    """Peak resident memory of each process that ran tiles (by process id)."""
    driver_peak_bytes: int
    """Peak resident memory of the process that read, routed and merged."""
    driver_pid: int
    cpu_seconds: dict[str, float]
    """CPU seconds per stage, summed over the tiles' runs."""
    driver_cpu_seconds: dict[str, float]
    """CPU seconds of the driver's own passes (read, plan, route), which no worker shares."""
    worker_busy_seconds: dict[int, float]
    """CPU seconds of tile work per process (every run of every tile it computed)."""
    spill_bytes: int


@dataclass(frozen=True)
class TiledRun(Tallies):
    """The merged outcomes of every tile of one run."""

    balls: int
    sparsity_exact: bool
    """False when the smallest sparsity ratio is only known to be at least the value found
    (the tiles' certainty, :mod:`vorobound.tiling.plan`)."""
    tiling: Tiling
    vtu: VtuRows | None
    timings: dict[str, float]
    """Wall seconds per driver stage."""
    radius_range: tuple[float, float] = (math.nan, math.nan)
    """Smallest and largest ball radius of the file (the L range is this over δ)."""


def run_tiles(
    path: str | Path,
    settings: TileSettings,
    workers: int = 1,
    scheduler: str | None = None,
    progress: Progress | None = None,
    tile_balls: int | None = None,
    chunk_rows: int = CHUNK_ROWS,
) -> TiledRun:
    """Read, plan, route and run the tiles of the balls in ``path`` (module docstring).

    ``settings`` are what the tiles share; ``top`` and ``total`` are filled in from the file,
    and ``vtu_share`` (the share of guide triangles asked for in the VTU, 0: none) is capped
    so that about ``VTU_TRIANGLES`` are kept. ``workers`` local processes (1: in this
    process) or the dask.distributed ``scheduler`` run them; ``tile_balls`` is the balls per
    tile (default: :func:`tile_count` tiles of equal size), ``chunk_rows`` the rows read at
    a time.

    Raises
    ------
    InputError
        Fewer than ``MIN_BALLS`` balls, or a bad row.
    WorkerError
        A worker process died or the cluster failed.
    """
    path = Path(path)
    timings: dict[str, float] = {}
    with tempfile.TemporaryDirectory(prefix=f"{TEMP_PREFIX}spill.") as spill_name:
        spill_dir = Path(spill_name)
        start, cpu = time.perf_counter(), time.process_time()
        spill = _read(path, spill_dir / "balls.f8", chunk_rows, progress)
        timings["read"] = time.perf_counter() - start
        serial = {"read": time.process_time() - cpu}
        if spill.count < MIN_BALLS:
            raise InputError(
                f"balls {path.name}: need at least {MIN_BALLS} balls, got {spill.count}"
            )
        with task_executor(workers, scheduler) as (executor, slots):
            start, cpu = time.perf_counter(), time.process_time()
            size = tile_balls or tile_size(spill.count)
            count = None if tile_balls else tile_count(spill.count)
            assert spill.subsample is not None
            plan = tiles.plan_tiles(
                spill.subsample, spill.count, size, spill.low, spill.high, count
            )
            core_radius = _core_radii(spill, plan, chunk_rows)
            params = settings.params
            sparsity_reach = params.sigma / params.quality.delta_ratio
            beta = tiles.first_halo(core_radius, sparsity_reach)
            timings["plan"] = time.perf_counter() - start
            serial["plan"] = time.process_time() - cpu
            share = min(1.0, VTU_TRIANGLES / (2.2 * spill.count))
            settings = dataclasses.replace(
                settings, top=spill.top, total=spill.count, vtu_share=settings.vtu_share * share
            )
            run = _Rounds(executor, slots, plan, spill, settings, chunk_rows, progress)
            outcomes = run.all(beta, sparsity_reach, core_radius)
            timings.update(run.seconds)
            serial["route"] = run.route_cpu
        return _merge(outcomes, run, spill, settings, timings, serial)


@dataclass
class _Spill:
    """The balls copied to a binary file, and what the first pass learned."""

    file: Path
    count: int = 0
    low: np.ndarray = field(default_factory=lambda: np.full(3, np.inf))
    high: np.ndarray = field(default_factory=lambda: np.full(3, -np.inf))
    top: float = 0.0
    smallest: float = math.inf
    subsample: np.ndarray | None = None

    def chunks(self, rows: int) -> Iterator[tuple[int, np.ndarray]]:
        """(first row, (m, 4) x, y, z, r) of consecutive rows (read, not mapped: a mapping
        would count the whole file in this process's resident memory)."""
        with open(self.file, "rb") as handle:
            for first in range(0, self.count, rows):
                block = np.fromfile(handle, dtype="<f8", count=4 * min(rows, self.count - first))
                yield first, block.reshape(-1, 4)


def _read(path: Path, file: Path, chunk_rows: int, progress: Progress | None) -> _Spill:
    """Pass 1: check and copy every ball; bounding box, W, subsample."""
    spill = _Spill(file)
    sample = tiles.Subsample()
    counter = Counter(progress, "reading balls", None)
    with open(file, "wb") as handle:
        for centers, radii in ball_chunks(path, chunk_rows):
            np.column_stack([centers, radii]).astype("<f8").tofile(handle)
            sample.add(spill.count, centers)
            spill.count += len(radii)
            spill.low = np.minimum(spill.low, centers.min(axis=0))
            spill.high = np.maximum(spill.high, centers.max(axis=0))
            spill.top = max(spill.top, float((radii * radii).max()))
            spill.smallest = min(spill.smallest, float(radii.min()))
            counter.step(len(radii))
    spill.subsample = sample.points()
    return spill


def _core_radii(spill: _Spill, plan: tiles.TilePlan, chunk_rows: int) -> np.ndarray:
    """Pass 2: the largest radius among each tile's own balls (R_T)."""
    radius = np.zeros(plan.count)
    for _, block in spill.chunks(chunk_rows):
        np.maximum.at(radius, plan.owner(block[:, :3]), block[:, 3])
    return radius


class _Rounds:
    """Routes and runs tiles, again with wider halos where a tile asks for one."""

    def __init__(
        self,
        executor: concurrent.futures.Executor,
        slots: int,
        plan: tiles.TilePlan,
        spill: _Spill,
        settings: TileSettings,
        chunk_rows: int,
        progress: Progress | None,
    ) -> None:
        self.executor, self.slots, self.plan, self.spill = executor, slots, plan, spill
        self.settings, self.chunk_rows, self.progress = settings, chunk_rows, progress
        self.seconds = {"route": 0.0, "tiles": 0.0}
        self.route_cpu = 0.0
        self.rounds, self.runs = 0, 0
        self.busy: dict[int, float] = {}
        """CPU seconds of tile work per process id, over every run."""

    def all(self, beta: np.ndarray, sparsity_reach: float, core_radius: np.ndarray) -> dict:
        outcomes: dict[int, TileOutcome] = {}
        todo = np.arange(self.plan.count)
        while len(todo):
            if self.rounds == MAX_ROUNDS:
                raise VoroboundError(
                    f"{len(todo)} tiles still need wider halos after {MAX_ROUNDS} runs "
                    "(balls far from all others?): use larger tiles (tile_balls)"
                )
            self.rounds += 1
            for outcome in self._run(todo, beta):
                outcomes[outcome.tile] = outcome
            needed = np.array([outcomes[t].needed_beta for t in range(self.plan.count)])
            smallest = min(o.sparsity.extreme for o in outcomes.values())
            if np.isfinite(smallest):
                # Every tile must have seen all its pairs below the smallest ratio found.
                needed = np.maximum(
                    needed, (1 + tiles.REACH_RTOL) * smallest * sparsity_reach * core_radius
                )
            short = needed > beta
            beta = np.where(short, np.maximum(needed, beta) * HALO_GROWTH, beta)
            todo = np.flatnonzero(short)
        return outcomes

    def _run(self, todo: np.ndarray, beta: np.ndarray) -> Iterator[TileOutcome]:
        folder = Path(tempfile.mkdtemp(prefix="shards.", dir=self.spill.file.parent))
        start, cpu = time.perf_counter(), time.process_time()
        _route(self.spill, self.plan, beta, todo, folder, self.chunk_rows, self.progress)
        self.seconds["route"] += time.perf_counter() - start
        self.route_cpu += time.process_time() - cpu
        start = time.perf_counter()
        counter = Counter(self.progress, "tiles", len(todo))
        waiting = iter(todo)
        pending: dict[concurrent.futures.Future, int] = {}
        try:
            while True:
                while len(pending) < IN_FLIGHT * self.slots:
                    tile = next(waiting, None)
                    if tile is None:
                        break
                    job = _job(int(tile), folder, self.plan, beta, self.settings)
                    pending[self.executor.submit(run_tile, job)] = int(tile)
                if not pending:
                    break
                done, _ = concurrent.futures.wait(
                    pending, return_when=concurrent.futures.FIRST_COMPLETED
                )
                for future in done:
                    tile = pending.pop(future)
                    outcome = task_result(future, f"tile {tile}")
                    self.runs += 1
                    spent = sum(outcome.seconds.values())
                    self.busy[outcome.pid] = self.busy.get(outcome.pid, 0.0) + spent
                    counter.step()
                    yield outcome
        finally:
            self.seconds["tiles"] += time.perf_counter() - start
            shutil.rmtree(folder, ignore_errors=True)


def _route(
    spill: _Spill,
    plan: tiles.TilePlan,
    beta: np.ndarray,
    todo: np.ndarray,
    folder: Path,
    chunk_rows: int,
    progress: Progress | None,
) -> None:
    """Pass 3: append each ball to the shard file of its own tile and of every halo it is in
    (only the tiles in ``todo``)."""
    active = np.full(plan.count, -np.inf)
    active[todo] = beta[todo]
    counter = Counter(progress, "routing balls", spill.count)
    for first, block in spill.chunks(chunk_rows):
        centers, radii = block[:, :3], block[:, 3]
        rows, tile, core = plan.members(centers, radii, active)
        order = np.argsort(tile, kind="stable")
        rows, tile = rows[order], tile[order]
        records = np.empty(len(rows), dtype=_RECORD)
        records["id"] = first + rows
        records["ball"] = block[rows]
        records["core"] = core[order]
        cuts = np.flatnonzero(np.diff(tile)) + 1
        for part, start in zip(np.split(records, cuts), np.concatenate([[0], cuts]), strict=True):
            if len(part):
                with open(folder / f"{tile[start]}.bin", "ab") as handle:
                    part.tofile(handle)
        counter.step(len(block))


def _job(tile: int, folder: Path, plan, beta, settings) -> TileJob:
    records = np.fromfile(folder / f"{tile}.bin", dtype=_RECORD)
    (folder / f"{tile}.bin").unlink()
    return TileJob(
        tile=tile,
        ids=records["id"].copy(),
        centers=np.ascontiguousarray(records["ball"][:, :3]),
        radii=np.ascontiguousarray(records["ball"][:, 3]),
        core=records["core"].astype(bool),
        lo=plan.lo[tile],
        hi=plan.hi[tile],
        beta=float(beta[tile]),
        settings=settings,
    )


def _merge(outcomes, run, spill, settings, timings, serial) -> TiledRun:
    """The tiles' outcomes as one run."""
    done = [outcomes[t] for t in sorted(outcomes)]
    sparsity = PairTally.merge([o.sparsity for o in done], smallest=True)
    cpu: dict[str, float] = {}
    peaks: dict[int, int] = {}
    for o in done:
        for stage, seconds in o.seconds.items():
            cpu[stage] = cpu.get(stage, 0.0) + seconds
        peaks[o.pid] = max(peaks.get(o.pid, 0), o.peak_rss)
    vtu = None
    if settings.vtu_share > 0:
        vtu = _merge_vtu([o.vtu for o in done if o.vtu is not None])
    tiling = Tiling(
        tiles=len(done),
        halo_balls=sum(o.halo for o in done),
        rounds=run.rounds,
        rerun=run.runs - len(done),
        executor=_executor_name(run.executor),
        workers=run.slots,
        worker_peak_bytes=peaks,
        driver_peak_bytes=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024,
        driver_pid=os.getpid(),
        cpu_seconds=cpu,
        driver_cpu_seconds=serial,
        worker_busy_seconds=dict(run.busy),
        spill_bytes=spill.count * 32,
    )
    return TiledRun(
        balls=spill.count,
        candidates=sum(o.candidates for o in done),
        with_seeds=sum(o.with_seeds for o in done),
        half_covered=sum(o.half_covered for o in done),
        guides=GuideTally.merge([o.guides for o in done]),
        sparsity=sparsity,
        lipschitz=PairTally.merge([o.lipschitz for o in done], smallest=False),
        sparsity_exact=all(o.sparsity_certain > sparsity.extreme for o in done),
        tiling=tiling,
        vtu=vtu,
        timings=timings,
        radius_range=(spill.smallest, math.sqrt(spill.top)),
    )


def _executor_name(executor) -> str:
    name = type(executor).__name__
    return {
        "InlineExecutor": "in process",
        "ProcessPoolExecutor": "local process pool",
        "ClientExecutor": "dask.distributed",
    }.get(name, name)


def _merge_vtu(parts: list[VtuRows]) -> VtuRows | None:
    if not parts:
        return None
    return VtuRows(
        triples=np.concatenate([p.triples for p in parts]),
        centers=np.concatenate([p.centers for p in parts]),
        radii=np.concatenate([p.radii for p in parts]),
        cells={k: np.concatenate([p.cells[k] for p in parts]) for k in parts[0].cells},
    )
