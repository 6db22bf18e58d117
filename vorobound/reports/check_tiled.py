"""``check`` of a ball file at scale: streamed, in tiles with halos, on a pool or a cluster.

:func:`check_ball_file` gives the numbers :func:`vorobound.reports.check.check_balls` gives
(the same guide triangles bit for bit, and the same summary), without ever holding the whole
sample, its triangles or their rows in one process: the tile engine
(:mod:`vorobound.tiling.engine`) reads, plans and routes the tiles, runs the check's one
pipeline (:func:`vorobound.tiling.job.check_part`, which a whole check runs once) on each,
and merges their tallies; :class:`TiledCheckReport` is the check's report of that run, whose
summary is built by the same :func:`~vorobound.reports.check.summary_fields` as a whole
check's. Outputs
(:class:`~vorobound.reports.check_outputs.CheckOutputs`) are per-tile row files written by the
workers into a hidden folder, published with summary.json, a decimated VTU and the gap
histogram as one set when every tile is done, or removed on any failure.

References
----------
The guide triangles, sampling conditions and bounds of Section 4.1.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path

import numpy as np

from ..bounds.params import SamplingParams, Target
from ..errors import InputError
from ..progress import Progress
from ..sampling.guides.features import FEATURE_RULE
from ..sampling.guides.measure import ModeBound, mode_bounds
from ..sampling.guides.triangles import Engine, resolve_engine
from ..sampling.io.stream import CHUNK_ROWS
from ..tiling.engine import TiledRun, run_tiles
from ..tiling.job import TileSettings, no_guide_triangles
from ..tiling.rows import PartFiles
from ..tiling.tally import GuideTally, gap_edges
from .check import COVERAGE_NOTE, LIPSCHITZ_SOURCES, class_entries, summary_fields


@dataclass(frozen=True)
class TiledCheckReport:
    """What a tiled check measured (the fields of :class:`~vorobound.reports.check.CheckReport`
    that do not need the rows)."""

    source: str
    params: SamplingParams
    lipschitz: float | None
    engine: str
    bounds: list[ModeBound]
    ratio_bounds: list[ModeBound]
    run: TiledRun
    """The tiles' merged tallies and how they were cut and run."""
    gap_edges: np.ndarray
    """Bin edges of ``guides.histogram``."""
    feature_rule: str | None = None
    """How guide triangles were split (None: no sharp features known)."""
    seed: None = None
    lipschitz_source: str = LIPSCHITZ_SOURCES["required"]
    timings: dict[str, float] = field(default_factory=dict)
    """Wall seconds per driver stage."""

    @property
    def guides(self) -> GuideTally:
        """The merged tally of the guide triangles."""
        return self.run.guides

    @property
    def lfs_range(self) -> tuple[float, float]:
        """Smallest and largest L_i = r_i/δ over the file's balls."""
        low, high = self.run.radius_range
        return low / self.params.delta, high / self.params.delta

    @cached_property
    def _summary(self) -> dict:
        g = self.run.guides
        out = summary_fields(self, self.run, self.run.balls, (None, None, 0))
        out["coverage_note"] = COVERAGE_NOTE
        out["worst"] = {
            name: {"triangle": list(w.triple), "centroid": list(w.centroid)}
            for name, w in g.where.items()
        }
        out["tiles"] = self._tiles()
        out["by_class"] = class_entries(g, self.feature_rule)
        if not self.run.sparsity_exact:
            out["sparsity_note"] = (
                "the smallest ratio is at least this (no pair closer was seen; the tiles "
                "could not see farther)"
            )
        return out

    def summary(self) -> dict:
        """The JSON summary: the fields of :meth:`CheckReport.summary` (docs/samples.md) with
        the same values, plus ``tiles`` and ``worst`` (docs/scale.md); computed once."""
        return dict(self._summary)

    def _tiles(self) -> dict:
        t = self.run.tiling
        return {
            "count": t.tiles,
            "halo_share": t.halo_balls / self.run.balls,
            "rounds": t.rounds,
            "rerun": t.rerun,
            "executor": t.executor,
            "workers": t.workers,
            "driver_peak_gb": round(t.driver_peak_bytes / 1e9, 3),
            "worker_peak_gb": round(max(t.worker_peak_bytes.values(), default=0) / 1e9, 3),
            "workers_peak_gb_total": round(sum(t.worker_peak_bytes.values()) / 1e9, 3),
            "processes_peak_gb_total": round(
                (
                    t.driver_peak_bytes
                    + sum(b for p, b in t.worker_peak_bytes.items() if p != t.driver_pid)
                )
                / 1e9,
                3,
            ),
            "cpu_seconds": {k: round(v, 3) for k, v in t.cpu_seconds.items()},
            "driver_cpu_seconds": {k: round(v, 3) for k, v in t.driver_cpu_seconds.items()},
            "busiest_worker_cpu_seconds": round(max(t.worker_busy_seconds.values(), default=0), 3),
            "spill_gb": round(t.spill_bytes / 1e9, 3),
        }


def check_ball_file(
    path: str | os.PathLike,
    params: SamplingParams,
    engine: Engine | str = Engine.auto,
    workers: int = 1,
    scheduler: str | None = None,
    outputs=None,
    progress: Progress | None = None,
    tile_balls: int | None = None,
    chunk_rows: int = CHUNK_ROWS,
    features=None,
) -> TiledCheckReport:
    """Check the balls of a file in tiles (module docstring): L_i = r_i/δ.

    Parameters
    ----------
    path : path
        CSV, NPZ, Parquet or a meshio point set (:func:`~vorobound.sampling.io.stream.ball_chunks`).
    params : SamplingParams
        As for :func:`~vorobound.reports.check.check_balls` (``params.lipschitz`` the λ that
        L = r/δ should satisfy).
    engine : Engine
        ``geogram`` (default when built), ``gudhi`` or ``brute``; ``hull`` needs the whole
        sphere.
    workers : int
        Processes of the local pool (1: tiles run in this process).
    scheduler : str, optional
        Address of a dask.distributed scheduler (then ``workers`` is ignored).
    outputs : CheckOutputs, optional
        Where the tiles write their rows (:class:`~vorobound.reports.check_outputs.CheckOutputs`,
        entered).
    tile_balls : int, optional
        Balls per tile (default: :func:`vorobound.tiling.engine.tile_count` tiles of equal size).
    chunk_rows : int
        Rows read at a time.
    features : SharpFeatures, optional
        The part's sharp features (:mod:`vorobound.sampling.guides.features`): the tiles
        split their guide triangles into smooth-patch and feature ones, as the whole check
        does.

    Raises
    ------
    NoGuideTriangles
        No triple of balls has both seeds uncovered.
    WorkerError
        A worker process died or the cluster failed.
    """
    engine = resolve_engine(engine, False)
    if engine is Engine.hull:
        raise InputError(
            "engine hull needs every ball at once (a sphere's convex hull): not in tiles"
        )
    path = Path(path)
    bounds = mode_bounds(params, Target.additive)
    ratios = mode_bounds(params, Target.ratio)
    edges = gap_edges(params, [b.value / params.eps for b in bounds])
    table = "none" if outputs is None else outputs.table
    settings = TileSettings(
        params=params,
        lipschitz=params.lipschitz,
        engine=engine.value,
        top=0.0,
        bounds=tuple(bounds),
        ratio_bounds=tuple(ratios),
        edges=edges,
        rows=None if table == "none" else PartFiles(str(outputs.parts), table),
        vtu_share=0.0 if outputs is None else 1.0,
        what=f"balls {path.name}",
        total=0,
        features=features,
    )
    run = run_tiles(path, settings, workers, scheduler, progress, tile_balls, chunk_rows)
    if run.guides.count == 0:
        raise no_guide_triangles(path.name, run.with_seeds, run.half_covered)
    return TiledCheckReport(
        source=path.name,
        params=params,
        lipschitz=params.lipschitz,
        engine=engine.value,
        bounds=bounds,
        ratio_bounds=ratios,
        run=run,
        gap_edges=edges,
        feature_rule=None if features is None else FEATURE_RULE,
        timings=run.timings,
    )
