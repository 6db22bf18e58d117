"""What a tiled check reports: the summary of :func:`vorobound.reports.check.check_balls`,
assembled from the tiles' tallies (:mod:`vorobound.reports.check_tally`), and how the check was
cut and run.

References
----------
Theorem 1, eq. (29), (33)–(36), (54)–(55) and property H3 of Section 4.1.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..bounds.params import SamplingParams
from ..bounds.targets import H3_STATUS
from ..sampling.guides.measure import ModeBound
from .check import LIPSCHITZ_SOURCES, _finite, bound_entries, ratio_bound_entries
from .check_tally import GuideTally, PairTally, class_entries
from .tile_job import VtuRows


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
class TiledCheckReport:
    """What a tiled check measured (the fields of :class:`~vorobound.reports.check.CheckReport`
    that do not need the rows)."""

    source: str
    params: SamplingParams
    lipschitz: float | None
    engine: str
    n_balls: int
    candidates: int
    with_seeds: int
    half_covered: int
    guides: GuideTally
    bounds: list[ModeBound]
    ratio_bounds: list[ModeBound]
    sparsity: PairTally
    lipschitz_pairs: PairTally
    sparsity_exact: bool
    """False when the smallest sparsity ratio is only known to be at least the value given
    (the tiles' certainty, :mod:`vorobound.sampling.guides.tiles`)."""
    tiling: Tiling
    vtu: VtuRows | None
    gap_edges: np.ndarray
    """Bin edges of ``guides.histogram``."""
    timings: dict[str, float] = field(default_factory=dict)
    """Wall seconds per driver stage."""
    feature_rule: str | None = None
    """How guide triangles were split (None: no sharp features known)."""

    def summary(self) -> dict:
        """The JSON summary: the fields of :meth:`CheckReport.summary` (docs/samples.md) with
        the same values, plus ``tiles`` and ``worst`` (docs/scale.md)."""
        g, eps = self.guides, self.params.eps
        count = g.count
        seeded = count + self.half_covered
        bounds = {b.mode: b.value for b in self.bounds}
        out = {
            "source": self.source,
            "params": {
                "eps": eps,
                "sigma": self.params.sigma,
                "delta_ratio": self.params.delta_ratio,
                "rho_f": self.params.rho_f,
            },
            "seed": None,
            "engine": self.engine,
            "n_samples": self.n_balls,
            "n_candidate_triples": self.candidates,
            "n_with_seeds": self.with_seeds,
            "n_guide_triangles": count,
            "n_half_covered": self.half_covered,
            "half_covered_share": self.half_covered / seeded if seeded else None,
            "coverage_max": None,
            "coverage_where": None,
            "coverage_probes": 0,
            "sparsity_min": _finite(self.sparsity.extreme),
            "sparsity_violations": self.sparsity.violations,
            "sparsity_worst": _pairs(self.sparsity),
            "lipschitz": self.lipschitz,
            "lipschitz_source": LIPSCHITZ_SOURCES["required"],
            "lipschitz_realized": _finite(self.lipschitz_pairs.extreme),
            "lipschitz_violations": self.lipschitz_pairs.violations,
            "lipschitz_worst": _pairs(self.lipschitz_pairs),
            "rho_max": _maximum(g, "rho"),
            "quality_violations": g.counts["quality_violations"],
            "ratio_max": _maximum(g, "quality_ratio"),
            "ratio_violations": g.counts["ratio_violations"],
            "ratio_bound": ratio_bound_entries(self.ratio_bounds),
            "ratio_bound_violations": dict(g.ratio_bound_violations),
            "h3_ratio_max": _maximum(g, "h3_ratio"),
            "h3_violations": g.counts["h3_violations"],
            "h3_premise": H3_STATUS,
            "gap_ratio_max": _maximum(g, "gap_ratio"),
            "gap_ratio_min": None if g.gap_min is None else _finite(g.gap_min),
            "orthoradius_sq_max": _maximum(g, "orthoradius_sq"),
            "bound": bound_entries(self.bounds, eps),
            "violations": {
                mode: rows if _finite(bounds[mode]) is not None else None
                for mode, rows in g.violations.items()
            },
            "outside_constraint_set": g.counts["outside_constraint_set"],
            "constraint_violations": dict(g.constraint_violations),
            "timings": {k: round(v, 3) for k, v in self.timings.items()},
            "coverage_note": "coverage needs the surface: only the balls were given",
            "worst": {
                name: {"triangle": list(w.triple), "centroid": list(w.centroid)}
                for name, w in g.where.items()
            },
            "tiles": self._tiles(),
            "by_class": class_entries(g, self.feature_rule),
        }
        if not self.sparsity_exact:
            out["sparsity_note"] = (
                "the smallest ratio is at least this (no pair closer was seen; the tiles "
                "could not see farther)"
            )
        return out

    def _tiles(self) -> dict:
        t = self.tiling
        return {
            "count": t.tiles,
            "halo_share": t.halo_balls / self.n_balls,
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


def _maximum(g: GuideTally, name: str) -> float | None:
    return _finite(g.maxima[name]) if name in g.maxima else None


def _pairs(tally: PairTally) -> list[dict]:
    return [
        {"i": i, "j": j, "ratio": ratio, "where": list(where)} for i, j, ratio, where in tally.worst
    ]


def histogram_marks(report: TiledCheckReport) -> list[tuple[str, float, str]]:
    """(mode, bound over εL_i, claim) for each mode: the lines of the gap histogram."""
    return [(b.mode, b.value / report.params.eps, b.claim) for b in report.bounds]
