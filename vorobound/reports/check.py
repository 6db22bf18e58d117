"""The check of a real sample against the paper: sampling conditions, guide triangles, bounds.

:func:`check_surface` samples a surface (:mod:`vorobound.sampling.sampler.maximal`) and checks the
sample; :func:`check_balls` checks balls someone else made (L_i = r_i/δ). Both measure every
guide triangle (:mod:`vorobound.sampling.guides.measure`) and assemble a :class:`CheckReport`, whose
:meth:`CheckReport.summary` is the JSON summary and which :func:`output_writers` writes as
triangles.csv, summary.json, a VTU for ParaView and a histogram of the realized gap.

References
----------
Theorem 1, eq. (29), (33)–(36), (54)–(55), property H3 and the sampling conditions of
Section 4.1.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..bounds.params import QualityParams, SamplingParams, Target
from ..bounds.targets import H3_STATUS
from ..errors import NoGuideTriangles
from ..progress import Counter, Progress
from ..sampling.balls import Balls, make_balls
from ..sampling.guides.features import FEATURE_RULE
from ..sampling.guides.measure import (
    GuideMeasurements,
    ModeBound,
    measure_guides,
    mode_bounds,
)
from ..sampling.guides.triangles import Engine, equal_radii_on_sphere, find_guide_triangles
from ..sampling.io.balls import fill_vtu
from ..sampling.sampler import conditions
from .check_tally import H3_RTOL, GuideTally, class_entries, gap_edges

GAP_HISTOGRAM_STEM = "gap_histogram"
UNDEFINED_BOUND = (
    "this chain is not defined at this eps (eq. (51)-(52) take the square root of a negative "
    "number): no bound, so no violations are counted"
)
"""File name (without extension) of the histogram of the realized gap."""
NO_RATIO_BOUND = "no finite bound on R/R^ at this eps: the mode's bound on (R - R^)/R reaches 1"
LIPSCHITZ_SOURCES = {
    "exact": "exact: a local feature size is 1-Lipschitz",
    "estimated": "of the estimated L: lambda-Lipschitz by construction, the lambda the sample "
    "was made with and that vorobound lfs reports",
    "measured": "measured: the largest |L_i - L_j|/|p_i - p_j| over neighbouring samples and "
    "guide-triangle edges",
    "required": "required of the balls' L = r/delta (a condition the sample is checked for)",
}
"""What the λ of a check means, by where it comes from."""


@dataclass(frozen=True)
class CheckReport:
    """Everything the check measured on one sample."""

    source: str
    """The surface sampled, or the file the balls came from."""
    params: SamplingParams
    lipschitz: float | None
    """λ of the sample's L used in the constraint set (None: no Lipschitz condition)."""
    lipschitz_source: str
    """Where λ comes from: exact (a local feature size), measured (a mesh's L), or required of
    external balls."""
    engine: str
    balls: Balls
    lfs: np.ndarray
    """L of every ball (exact for a sampled surface, r/δ for external balls)."""
    proposed: int
    """Candidate triples the engine proposed."""
    with_seeds: int
    """Of those, triples whose seed pair exists."""
    half_covered: int
    guides: GuideMeasurements
    bounds: list[ModeBound]
    """Each mode's bound on R − R̂ (additive target)."""
    ratio_bounds: list[ModeBound]
    """Each proven mode's bound on R/R̂ (ratio target, eq. (54))."""
    sparsity: conditions.PairReport
    lipschitz_pairs: conditions.PairReport
    coverage_max: float | None
    """max distance/(εL) over the probes; None without a surface."""
    coverage_where: np.ndarray | None
    coverage_probes: int
    seed: int | None
    timings: dict[str, float] = field(default_factory=dict)
    """Wall time per stage, in seconds."""
    feature_rule: str | None = None
    """How guide triangles were split into smooth-patch and feature ones (None: no sharp
    features known, every triangle is smooth)."""

    def summary(self) -> dict:
        """The JSON summary (plain types; see docs/samples.md for the fields)."""
        g, eps = self.guides, self.params.eps
        count = len(g)
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
            "seed": self.seed,
            "engine": self.engine,
            "n_samples": len(self.balls),
            "n_candidate_triples": self.proposed,
            "n_with_seeds": self.with_seeds,
            "n_guide_triangles": count,
            "n_half_covered": self.half_covered,
            "half_covered_share": self.half_covered / seeded if seeded else None,
            "coverage_max": self.coverage_max,
            "coverage_where": None if self.coverage_where is None else self.coverage_where.tolist(),
            "coverage_probes": self.coverage_probes,
            "sparsity_min": _finite(self.sparsity.extreme),
            "sparsity_violations": self.sparsity.violations,
            "sparsity_worst": self._pairs(self.sparsity),
            "lipschitz": self.lipschitz,
            "lipschitz_source": self.lipschitz_source,
            "lipschitz_realized": _finite(self.lipschitz_pairs.extreme),
            "lipschitz_violations": self.lipschitz_pairs.violations,
            "lipschitz_worst": self._pairs(self.lipschitz_pairs),
            "rho_max": _max(g.rho),
            "quality_violations": int((g.rho > self.params.rho_f).sum()),
            "ratio_max": _max(g.quality_ratio),
            "ratio_violations": int((g.quality_ratio > self.params.rho_f).sum()),
            "ratio_bound": ratio_bound_entries(self.ratio_bounds),
            "ratio_bound_violations": {
                mode: int(rows.sum()) for mode, rows in (g.exceeds_ratio or {}).items()
            },
            "h3_ratio_max": _max(g.h3_ratio),
            "h3_violations": int((g.h3_ratio > 1 + H3_RTOL).sum()),
            "h3_premise": H3_STATUS,
            "gap_ratio_max": _max(g.gap_ratio),
            "gap_ratio_min": None if count == 0 else _finite(g.gap_ratio.min()),
            "orthoradius_sq_max": _max(g.orthoradius_sq / (self.params.delta * g.lfs[:, 0]) ** 2),
            "bound": bound_entries(self.bounds, eps),
            "violations": {
                mode: int(rows.sum()) if _finite(bounds[mode]) is not None else None
                for mode, rows in g.exceeds.items()
            },
            "outside_constraint_set": int((~g.inside).sum()),
            "constraint_violations": {n: int(rows.sum()) for n, rows in g.violated.items()},
            "timings": {k: round(v, 3) for k, v in self.timings.items()},
        }
        tally = GuideTally.of(
            g,
            np.arange(len(self.balls)),
            self.balls.centers,
            self.params,
            gap_edges(self.params, []),
        )
        out["by_class"] = class_entries(tally, self.feature_rule)
        if self.coverage_max is None:
            out["coverage_note"] = "coverage needs the surface: only the balls were given"
        if count == 0:
            out["guide_note"] = "no guide triangles: no triple of balls has both seeds uncovered"
        return out

    def _pairs(self, report: conditions.PairReport) -> list[dict]:
        centers = self.balls.centers
        return [
            {
                "i": int(i),
                "j": int(j),
                "ratio": float(value),
                "where": (0.5 * (centers[i] + centers[j])).tolist(),
            }
            for (i, j), value in zip(report.worst, report.worst_values, strict=True)
        ]


def bound_entries(bounds: list[ModeBound], eps: float) -> dict:
    """The summary's ``bound``: each mode's bound on R − R̂ per unit L_i, and over ε."""
    return {
        b.mode: {
            "value": _finite(b.value),
            "gap_ratio": _finite(b.value / eps),
            "claim": b.claim,
            "lipschitz": b.lipschitz,
        }
        | ({} if _finite(b.value) is not None else {"note": UNDEFINED_BOUND})
        for b in bounds
    }


def ratio_bound_entries(ratio_bounds: list[ModeBound]) -> dict:
    """The summary's ``ratio_bound``: each mode's bound on R/R̂ (eq. (54))."""
    return {
        b.mode: {"value": _finite(b.value), "claim": b.claim, "lipschitz": b.lipschitz}
        | ({} if _finite(b.value) is not None else {"note": NO_RATIO_BOUND})
        for b in ratio_bounds
    }


def _max(values: np.ndarray) -> float | None:
    return None if len(values) == 0 else _finite(values.max())


def _finite(value) -> float | None:
    """A plain float, or None where it is NaN or infinite (JSON has neither)."""
    value = float(value)
    return value if np.isfinite(value) else None


class _Stages:
    """Wall time per stage, and a progress line for the stages without their own counter."""

    def __init__(self, progress: Progress | None):
        self.progress, self.seconds = progress, {}

    @contextmanager
    def __call__(self, name: str, announce: bool = False):
        if announce:
            Counter(self.progress, name, None)
        start = time.perf_counter()
        yield
        self.seconds[name] = self.seconds.get(name, 0.0) + time.perf_counter() - start


def check_surface(
    shape,
    eps: float,
    quality: QualityParams,
    seed: int = 0,
    engine: Engine | str = Engine.auto,
    progress: Progress | None = None,
) -> CheckReport:
    """Sample ``shape`` at ``eps`` (σ-sparse ε-sample, r = δL) and check the sample.

    References
    ----------
    The sampling conditions and guide triangles of Section 4.1.
    """
    from ..sampling.sampler.maximal import sample_surface

    params = SamplingParams(eps, quality)
    stages = _Stages(progress)
    with stages("sample"):
        sample = sample_surface(shape, eps, quality.sigma, seed, progress)
    balls = make_balls(sample.points, params.delta * sample.lfs, shape.name)
    # An exact local feature size is 1-Lipschitz; a mesh's L is measured on the sample.
    kind = "exact" if getattr(shape, "lipschitz_exact", False) else "measured"
    if kind == "exact" and getattr(shape, "estimate", None) is not None:
        kind = "estimated"
    lam = shape.lipschitz
    return _check(balls, sample.lfs, params, lam, engine, shape, seed, stages, shape.name, kind)


def sharp_features(shape):
    """The sharp features of ``shape`` the check splits guide triangles by (None: none
    known; :mod:`vorobound.sampling.guides.features`)."""
    from ..sampling.guides.features import SharpFeatures

    return None if shape is None else SharpFeatures.of_shape(shape)


def check_balls(
    balls: Balls,
    params: SamplingParams,
    engine: Engine | str = Engine.auto,
    shape=None,
    source: str = "balls",
    progress: Progress | None = None,
) -> CheckReport:
    """Check balls made elsewhere: L_i = r_i/δ with δ = (δ/ε)·ε from ``params``, and
    ``params.lipschitz`` the λ that L should satisfy.

    ``shape``, if given, is the surface the balls sample (for the coverage measurement).
    """
    lfs = balls.radii / params.delta
    stages = _Stages(progress)
    lam = params.lipschitz
    return _check(balls, lfs, params, lam, engine, shape, None, stages, source, "required")


def _check(
    balls, lfs, params, lipschitz, engine, shape, seed, stages, source, lipschitz_kind
) -> CheckReport:
    """The stages after sampling; ``lipschitz_kind`` is a key of ``LIPSCHITZ_SOURCES``."""
    progress = stages.progress
    equal_on_sphere = bool(getattr(shape, "equal_radii_on_sphere", False)) and (
        equal_radii_on_sphere(balls, shape.radius)
    )
    with stages("guide triangles"):
        search = find_guide_triangles(balls, engine, equal_on_sphere, progress)
    if len(search.guide.triples) == 0:
        raise NoGuideTriangles(
            f"{source}: no guide triangle to measure ({search.with_seeds:,} triples of balls "
            f"meet in a seed pair, {search.half_covered:,} of them half-covered): a VoroCrust "
            "sample of a closed surface has guide triangles all over it; are the radii δ·L too "
            "small for the spacing of the centers?"
        )
    with stages("conditions", announce=True):
        near = conditions.neighbours(balls.centers)
        if lipschitz_kind == "measured":
            lipschitz = _measured_lipschitz(balls.centers, lfs, search.guide.triples, near)
        sparse = conditions.sparsity(balls.centers, lfs, params.eps, params.sigma, near)
        lipschitz_pairs = conditions.lipschitz(balls.centers, lfs, lipschitz, near)
        coverage, where, probes = _coverage(shape, balls, params.eps, search.guide, seed)
    with stages("bounds", announce=True):
        params = params.but(lipschitz=lipschitz)
        bounds = mode_bounds(params, Target.additive)
        ratios = mode_bounds(params, Target.ratio)
    features = sharp_features(shape)
    with stages("measure", announce=True):
        guides = measure_guides(search.guide, lfs, params, bounds, ratios)
        guides = guides.with_features(balls.centers, balls.radii, features)
    return CheckReport(
        source=source,
        params=params,
        lipschitz=lipschitz,
        lipschitz_source=LIPSCHITZ_SOURCES[lipschitz_kind],
        engine=search.engine,
        balls=balls,
        lfs=lfs,
        proposed=search.candidates,
        with_seeds=search.with_seeds,
        half_covered=search.half_covered,
        guides=guides,
        bounds=bounds,
        ratio_bounds=ratios,
        sparsity=sparse,
        lipschitz_pairs=lipschitz_pairs,
        coverage_max=coverage,
        coverage_where=where,
        coverage_probes=probes,
        seed=seed,
        timings=stages.seconds,
        feature_rule=None if features is None else FEATURE_RULE,
    )


def _measured_lipschitz(points, lfs, triples, near: conditions.Neighbours) -> float:
    """The λ the sample has: the largest |L_a − L_b|/|p_a − p_b| over neighbouring samples and
    over the edges of the guide triangles, so every guide triangle meets the Lipschitz
    conditions with it; 0 only for a constant L."""
    from ..checks import LIPSCHITZ_RANGE

    edges = np.concatenate([triples[:, [0, 1]], triples[:, [1, 2]], triples[:, [2, 0]]])
    change = np.abs(lfs[edges[:, 0]] - lfs[edges[:, 1]])
    length = np.linalg.norm(points[edges[:, 0]] - points[edges[:, 1]], axis=1)
    ratios = [conditions.lipschitz(points, lfs, None, near).extreme]
    if len(edges):
        ratios.append(float((change / length).max()))
    value = max(ratios)
    return 0.0 if value == 0 else max(value, LIPSCHITZ_RANGE[0])


def _coverage(shape, balls: Balls, eps: float, guides, seed):
    """Coverage over random probes plus the guide triangles' circumcenters on the surface."""
    if shape is None:
        return None, None, 0
    extra = guides.geometry.circumcenter if len(guides.triples) else None
    return conditions.surface_coverage(shape, balls.centers, eps, seed, extra)


# --- Output files ----------------------------------------------------------------------------


def triangle_columns(report: CheckReport) -> dict[str, np.ndarray]:
    """The columns of triangles.csv, one row per guide triangle."""
    return guide_columns(report.guides)


def guide_columns(g: GuideMeasurements, triples: np.ndarray | None = None) -> dict:
    """The columns of triangles.csv for measured guide triangles; ``triples`` replaces their
    ball indices (a tile's rows carry the indices of the whole set)."""
    triples = g.triples if triples is None else triples
    columns = {
        "a_index": triples[:, 0],
        "b_index": triples[:, 1],
        "c_index": triples[:, 2],
        "lfs_i": g.lfs[:, 0],
        "lfs_j": g.lfs[:, 1],
        "lfs_k": g.lfs[:, 2],
        "circumradius": g.circumradius,
        "orthoradius_sq": g.orthoradius_sq,
        "radius_gap": g.radius_gap,
        "rho": g.rho,
        "gap_ratio": g.gap_ratio,
        "quality_ratio": g.quality_ratio,
        "h3_ratio": g.h3_ratio,
        "a_over_eps_lfs": g.edges[:, 0],
        "b_over_eps_lfs": g.edges[:, 1],
        "c_over_eps_lfs": g.edges[:, 2],
        "sin_theta": g.sin_theta,
        "inside": g.inside.astype(np.int64),
        "feature_reach": np.full(len(g), np.inf) if g.feature_reach is None else g.feature_reach,
        "at_feature": g.at_feature.astype(np.int64),
    }
    for name, rows in g.violated.items():
        columns[f"breaks_{name}"] = rows.astype(np.int64)
    for mode, rows in g.exceeds.items():
        columns[f"exceeds_{mode}"] = rows.astype(np.int64)
    for mode, rows in (g.exceeds_ratio or {}).items():
        columns[f"exceeds_ratio_{mode}"] = rows.astype(np.int64)
    return columns


def _write_vtu(path: Path, report: CheckReport) -> None:
    g = report.guides
    count = len(report.balls)
    vertices = np.arange(count).reshape(-1, 1)
    blank = np.full(count, np.nan)
    cells = [("vertex", vertices), ("triangle", g.triples)]
    cell_data = {
        "rho": [blank, g.rho],
        "gap_ratio": [blank, g.gap_ratio],
        "quality_ratio": [blank, np.where(np.isfinite(g.quality_ratio), g.quality_ratio, np.nan)],
        "h3_ratio": [blank, g.h3_ratio],
        "inside_constraint_set": [blank, g.inside.astype(float)],
        "at_feature": [blank, g.at_feature.astype(float)],
    }
    point_data = {"radius": report.balls.radii, "lfs": report.lfs}
    fill_vtu(path, report.balls.centers, cells, point_data, cell_data)


TABLES = ("parquet", "npz", "csv", "none")
"""How ``--out`` holds the per-triangle rows: triangles.parquet, triangles.npz (the compact
default without pyarrow), triangles.csv (10 significant digits), or not at all."""


def default_table() -> str:
    """Parquet where pyarrow is installed, else NPZ."""
    from ..sampling.io.balls import pyarrow_available

    return "parquet" if pyarrow_available() else "npz"


def output_writers(report: CheckReport, out_dir: str | Path, table: str = "npz") -> dict:
    """Writers of the per-triangle rows (``table``) and sample.vtu in ``out_dir`` (each takes
    the temporary path to fill), for :func:`vorobound.files.write_set`.

    The summary (the command's JSON) and the gap histogram (``GAP_HISTOGRAM_STEM``, drawn by
    the plotting layer from :func:`histogram_marks`) join the same set in the workflow.
    """
    from ..sampling.io.columns import READABLE_PRECISION, columns_writer

    out = Path(out_dir)
    writers: dict[Path, Callable] = {}
    if table != "none":
        path = out / f"triangles.{table}"
        writers[path] = columns_writer(path, triangle_columns(report), READABLE_PRECISION)
    writers[out / "sample.vtu"] = lambda path: _write_vtu(path, report)
    return writers


def histogram_marks(report: CheckReport) -> list[tuple[str, float, str]]:
    """(mode, bound over εL_i, claim) for each mode: the lines of the gap histogram."""
    return [(b.mode, b.value / report.params.eps, b.claim) for b in report.bounds]
