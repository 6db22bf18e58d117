"""The check of a real sample against the paper: sampling conditions, guide triangles, bounds.

:func:`check_surface` samples a surface (:mod:`vorobound.sampling.sampler.maximal`) and checks the
sample; :func:`check_balls` checks balls someone else made (L_i = r_i/δ). Both run the check's
one pipeline, :func:`vorobound.tiling.job.check_part`, on the whole sample as one tile in
process (no halo, every thread, a regular triangulation in slabs or the hull engine, L exact
where the surface gives it, λ measured where a mesh's L has none), and add the stages only a
surface has around it: sampling before, coverage after. A tiled check
(:mod:`vorobound.reports.check_tiled`, on the tile engine :mod:`vorobound.tiling`) runs the same
pipeline per tile.

Both reports build their summary once, by :func:`summary_fields`, from the pipeline's
:class:`~vorobound.tiling.job.Tallies` (a whole check's one outcome, or the merge of the
tiles'); the table format is checked in :func:`checked_table` only; the error of a sample
without guide triangles is :func:`~vorobound.tiling.job.no_guide_triangles`; both write their
files through :class:`~vorobound.reports.check_outputs.CheckOutputs` (per-triangle rows,
summary.json, a VTU for ParaView and a histogram of the realized gap, as one set).

What a whole check has that tiles cannot: coverage (needs the surface and every ball), the
measured λ (a property of the whole sample), every guide triangle's row in memory (the VTU
shows them all, the gap histogram is drawn from the values, ``to_frame``), and candidate counts
of the slabs or the hull (a tile triangulates once; its guide triangles are the same).

References
----------
Theorem 1, eq. (29), (33)–(36), (54)–(55), property H3 and the sampling conditions of
Section 4.1.
"""

from __future__ import annotations

import time
from contextlib import contextmanager
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from ..bounds.params import QualityParams, SamplingParams
from ..bounds.targets import H3_STATUS
from ..progress import Counter, Progress
from ..sampling.balls import Balls, make_balls
from ..sampling.guides.features import FEATURE_RULE
from ..sampling.guides.measure import GuideMeasurements, ModeBound
from ..sampling.guides.triangles import Engine, equal_radii_on_sphere, whole_engine
from ..sampling.sampler import conditions
from ..tiling.job import Tallies, TileJob, TileSettings, check_part
from ..tiling.rows import TABLES, guide_columns
from ..tiling.tally import CLASSES, GuideTally, PairTally

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
    tallies: Tallies
    """Candidate triples, those with seeds, the half-covered ones and the tallies of the guide
    triangles and pair conditions (the pipeline's outcome, as a tile sends it back)."""
    guides: GuideMeasurements
    bounds: list[ModeBound]
    """Each mode's bound on R − R̂ (additive target)."""
    ratio_bounds: list[ModeBound]
    """Each proven mode's bound on R/R̂ (ratio target, eq. (54))."""
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

    @property
    def proposed(self) -> int:
        """Candidate triples the engine proposed."""
        return self.tallies.candidates

    @property
    def tally(self) -> GuideTally:
        """The guide triangles' counts and maxima, as one tile of a tiled check has them."""
        return self.tallies.guides

    @cached_property
    def _summary(self) -> dict:
        coverage = (self.coverage_max, self.coverage_where, self.coverage_probes)
        out = summary_fields(self, self.tallies, len(self.balls), coverage)
        out["by_class"] = class_entries(self.tally, self.feature_rule)
        if self.coverage_max is None:
            out["coverage_note"] = COVERAGE_NOTE
        return out

    def summary(self) -> dict:
        """The JSON summary (plain types; see docs/samples.md for the fields), computed once."""
        return dict(self._summary)


COVERAGE_NOTE = "coverage needs the surface: only the balls were given"


def summary_fields(report, tallies: Tallies, n_samples: int, coverage: tuple) -> dict:
    """The fields every check's summary has (docs/samples.md), from its ``tallies`` (a whole
    check's, as of one tile, or the merge of its tiles'); ``report`` gives the source,
    parameters, seed, engine, λ, bounds and timings; ``coverage`` is (max, where, probes)."""
    g, eps = tallies.guides, report.params.eps
    sparsity, lipschitz_pairs = tallies.sparsity, tallies.lipschitz
    seeded = g.count + tallies.half_covered
    bounds = {b.mode: b.value for b in report.bounds}
    coverage_max, coverage_where, probes = coverage
    return {
        "source": report.source,
        "params": {
            "eps": eps,
            "sigma": report.params.sigma,
            "delta_ratio": report.params.delta_ratio,
            "rho_f": report.params.rho_f,
        },
        "seed": report.seed,
        "engine": report.engine,
        "n_samples": n_samples,
        "n_candidate_triples": tallies.candidates,
        "n_with_seeds": tallies.with_seeds,
        "n_guide_triangles": g.count,
        "n_half_covered": tallies.half_covered,
        "half_covered_share": tallies.half_covered / seeded if seeded else None,
        "coverage_max": coverage_max,
        "coverage_where": None if coverage_where is None else coverage_where.tolist(),
        "coverage_probes": probes,
        "sparsity_min": _finite(sparsity.extreme),
        "sparsity_violations": sparsity.violations,
        "sparsity_worst": _pairs(sparsity),
        "lipschitz": report.lipschitz,
        "lipschitz_source": report.lipschitz_source,
        "lipschitz_realized": _finite(lipschitz_pairs.extreme),
        "lipschitz_violations": lipschitz_pairs.violations,
        "lipschitz_worst": _pairs(lipschitz_pairs),
        "rho_max": _maximum(g, "rho"),
        "quality_violations": g.counts["quality_violations"],
        "ratio_max": _maximum(g, "quality_ratio"),
        "ratio_violations": g.counts["ratio_violations"],
        "ratio_bound": ratio_bound_entries(report.ratio_bounds),
        "ratio_bound_violations": dict(g.ratio_bound_violations),
        "h3_ratio_max": _maximum(g, "h3_ratio"),
        "h3_violations": g.counts["h3_violations"],
        "h3_premise": H3_STATUS,
        "gap_ratio_max": _maximum(g, "gap_ratio"),
        "gap_ratio_min": None if g.gap_min is None else _finite(g.gap_min),
        "orthoradius_sq_max": _maximum(g, "orthoradius_sq"),
        "bound": bound_entries(report.bounds, eps),
        "violations": {
            mode: rows if _finite(bounds[mode]) is not None else None
            for mode, rows in g.violations.items()
        },
        "outside_constraint_set": g.counts["outside_constraint_set"],
        "constraint_violations": dict(g.constraint_violations),
        "timings": {k: round(v, 3) for k, v in report.timings.items()},
    }


def class_entries(tally: GuideTally, feature_rule: str | None) -> dict:
    """The summary's split by where the guide triangles sit: ``feature_rule`` (None: no
    features known) and per class its count, the counts of the checks on triangles, the
    violations of each mode's bounds and where each maximum occurs (ball indices, centroid)."""
    from ..sampling.guides.features import NO_FEATURES

    out: dict = {"feature_rule": feature_rule or NO_FEATURES}
    for name in CLASSES:
        t = tally.classes.get(name)
        if t is None:
            out[name] = None
            continue
        out[name] = {
            "n_guide_triangles": t.count,
            **t.counts,
            "violations": dict(t.violations),
            "ratio_bound_violations": dict(t.ratio_bound_violations),
            "maxima": {k: _finite(v) for k, v in t.maxima.items()},
            "worst": {
                k: {"triangle": list(w.triple), "centroid": list(w.centroid)}
                for k, w in t.where.items()
            },
        }
    return out


def _maximum(g: GuideTally, name: str) -> float | None:
    return _finite(g.maxima[name]) if name in g.maxima else None


def _pairs(tally: PairTally) -> list[dict]:
    return [
        {"i": i, "j": j, "ratio": ratio, "where": list(where)} for i, j, ratio, where in tally.worst
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


def _finite(value) -> float | None:
    """A plain float, or None where it is NaN or infinite (JSON has neither)."""
    value = float(value)
    return value if np.isfinite(value) else None


TIMED_STAGES = ("sample", "guide triangles", "conditions", "bounds", "measure")
"""The stages of a whole check's ``timings``, in order."""
_PIPELINE_STAGES = {
    "triangulation": "guide triangles",
    "seeds": "guide triangles",
    "rows": "measure",
}
"""The pipeline's stages (:func:`vorobound.tiling.job.check_part`) a whole check times
together."""


class _Stages:
    """Wall time per stage, and a progress line for the stages without their own counter
    (the pipeline's clock of a whole check)."""

    def __init__(self, progress: Progress | None):
        self.progress = progress
        self.seconds: dict[str, float] = {}

    @contextmanager
    def __call__(self, name: str):
        name = _PIPELINE_STAGES.get(name, name)
        if name not in ("sample", "guide triangles") and name not in self.seconds:
            Counter(self.progress, name, None)
        start = time.perf_counter()
        yield
        self.seconds[name] = self.seconds.get(name, 0.0) + time.perf_counter() - start

    def timings(self) -> dict[str, float]:
        return {name: self.seconds[name] for name in TIMED_STAGES if name in self.seconds}


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
    """The pipeline on the whole sample as one tile, then coverage; ``lipschitz_kind`` is a
    key of ``LIPSCHITZ_SOURCES``."""
    equal_on_sphere = bool(getattr(shape, "equal_radii_on_sphere", False)) and (
        equal_radii_on_sphere(balls, shape.radius)
    )
    features = sharp_features(shape)
    engine = whole_engine(engine, equal_on_sphere)
    measured = lipschitz_kind == "measured"
    settings = TileSettings.whole(balls, params, lipschitz, engine, source, features, measured)
    part = check_part(TileJob.whole(balls, settings, lfs), stages, stages.progress)
    assert part.kept is not None  # the InMemory sink's rows
    with stages("conditions"):
        coverage, where, probes = _coverage(shape, balls, params.eps, part.kept.circumcenters, seed)
    return CheckReport(
        source=source,
        params=part.params,
        lipschitz=part.params.lipschitz,
        lipschitz_source=LIPSCHITZ_SOURCES[lipschitz_kind],
        engine=part.engine,
        balls=balls,
        lfs=lfs,
        tallies=part,
        guides=part.kept.guides,
        bounds=list(part.bounds),
        ratio_bounds=list(part.ratio_bounds),
        coverage_max=coverage,
        coverage_where=where,
        coverage_probes=probes,
        seed=seed,
        timings=stages.timings(),
        feature_rule=None if features is None else FEATURE_RULE,
    )


def _coverage(shape, balls: Balls, eps: float, circumcenters: np.ndarray | None, seed):
    """Coverage over random probes plus the guide triangles' circumcenters on the surface."""
    if shape is None:
        return None, None, 0
    extra = circumcenters if circumcenters is not None and len(circumcenters) else None
    return conditions.surface_coverage(shape, balls.centers, eps, seed, extra)


# --- Output files ----------------------------------------------------------------------------


def triangle_columns(report: CheckReport) -> dict[str, np.ndarray]:
    """The columns of triangles.csv, one row per guide triangle."""
    return guide_columns(report.guides)


def default_table(tiled: bool = False) -> str:
    """Parquet where pyarrow is installed; else NPZ, or no rows for a tiled check (whose NPZ
    would be assembled in one process)."""
    from ..sampling.io.balls import pyarrow_available

    if pyarrow_available():
        return "parquet"
    return "none" if tiled else "npz"


def checked_table(table: str | None, tiled: bool = False) -> str:
    """How ``out`` holds the per-triangle rows (``TABLES``; None: :func:`default_table`): the
    one place the format and pyarrow are checked."""
    from ..errors import InputError
    from ..sampling.io.balls import pyarrow_available

    table = table or default_table(tiled)
    if table not in TABLES:
        raise InputError(f"table: expected {', '.join(TABLES)}, got {table!r}")
    if table == "parquet" and not pyarrow_available():
        raise InputError(
            "Parquet rows need pyarrow (pip install 'vorobound[parquet]'); "
            "or write them as NPZ (--table npz), CSV (--table csv) or not at all (--table none)"
        )
    return table


def histogram_marks(report) -> list[tuple[str, float, str]]:
    """(mode, bound over εL_i, claim) for each mode: the lines of the gap histogram (of a
    whole or a tiled check)."""
    return [(b.mode, b.value / report.params.eps, b.claim) for b in report.bounds]
