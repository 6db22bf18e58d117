"""``vorobound check``: sample a surface (or read balls) and measure every guide triangle
against every bound."""

from __future__ import annotations

import json
import os
from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING

from ..bounds.params import QualityParams
from ..constants import PAPER_DELTA_RATIO, PAPER_RHO_F, PAPER_SIGMA
from ..progress import Progress
from ..reports.check import checked_table
from .arguments import checked_arguments
from .result import Result, checked_outputs, frame, params_json, sample_lfs, typed_view

if TYPE_CHECKING:
    from ..mesh import TriangleMesh
    from ..reports.check import CheckReport
    from ..reports.check_outputs import CheckOutputs
    from ..reports.check_tiled import TiledCheckReport
    from .check_summary import CheckSummary

PROVEN_MODES = ("rigorous", "tight", "tight_lipschitz")
"""Modes whose bound a guide triangle must not exceed (the paper's printed chain is invalid,
so exceeding it is a finding about the paper, not about the sample)."""


def failures(summary: dict) -> dict[str, int]:
    """What the check found broken, by kind, from its summary (zero everywhere: ok): the
    sample's conditions and the guide triangles on smooth patches (``violations_smooth``;
    triangles at sharp features are reported apart, :func:`feature_failures`)."""
    coverage = summary.get("coverage_max")
    smooth = summary.get("by_class", {}).get("smooth") or summary
    return {
        "coverage": int(coverage is not None and coverage >= 1),
        "sparsity": summary["sparsity_violations"],
        "lipschitz": summary["lipschitz_violations"],
        **_triangle_failures(smooth),
    }


def feature_failures(summary: dict) -> dict:
    """``violations_at_features``: the same counts for the guide triangles within reach of a
    sharp feature (they do not change the exit code), how many there are, and where the worst
    of each measure sits (ball indices and centroid)."""
    found = summary.get("by_class", {}).get("at_features")
    if found is None:
        return {"n_guide_triangles": 0, **dict.fromkeys(TRIANGLE_KINDS, 0), "worst": {}}
    return {
        "n_guide_triangles": found["n_guide_triangles"],
        **_triangle_failures(found),
        "worst": found["worst"],
    }


TRIANGLE_KINDS = ("outside_constraint_set", "quality", "ratio", "proven_bound")
"""The failures counted per guide triangle (the rest are conditions of the sample)."""


def _triangle_failures(counts: dict) -> dict[str, int]:
    return {
        "outside_constraint_set": counts["outside_constraint_set"],
        "quality": counts["quality_violations"],
        "ratio": counts["ratio_violations"],
        "proven_bound": sum(counts["violations"].get(m) or 0 for m in PROVEN_MODES)
        + sum(counts["ratio_bound_violations"].get(m) or 0 for m in PROVEN_MODES),
    }


FAILURE_WORDS = {
    "coverage": "coverage_max >= 1 (not an eps-sample)",
    "sparsity": "pairs closer than the sparsity allows",
    "lipschitz": "pairs whose L changes faster than lambda",
    "outside_constraint_set": "guide triangles outside the constraint set (33)-(36)/H3",
    "quality": "guide triangles with R > rho_f*delta*L_i (eq. (55))",
    "ratio": "guide triangles with R > rho_f*R^ (eq. (54))",
    "proven_bound": "exceedances of a proven bound",
}


@dataclass(frozen=True, repr=False)
class CheckResult(Result):
    """The check of one sample: counts, the largest realized quantities, what failed."""

    command = "check"
    source: str
    n_samples: int
    n_guide_triangles: int
    n_half_covered: int
    gap_ratio_max: float | None
    """max (R − R̂)/(εL_i) over the guide triangles."""
    ratio_max: float | None
    """max R/R̂ (eq. (54))."""
    coverage_max: float | None
    n_failures: int
    """Sum of :attr:`failures` (0: everything checked holds)."""
    report: CheckReport | TiledCheckReport = field(repr=False)
    """What the check measured, whole or in tiles."""
    written: tuple[str, ...] = field(repr=False, default=())
    asked: dict = field(repr=False, default_factory=dict)
    extra: dict = field(repr=False, default_factory=dict)
    """More of the JSON (a tiled check's ``rows``: where its per-triangle rows are)."""

    @property
    def failures(self) -> dict[str, int]:
        return failures(self.report.summary())

    @property
    def summary(self) -> CheckSummary:
        """What the check found as typed fields (the numbers of :meth:`to_dict`)."""
        from .check_summary import CheckSummary

        return CheckSummary.of(self.to_dict())

    @property
    def ok(self) -> bool:
        return self.n_failures == 0

    @property
    def verdict(self) -> str:
        found = [f"{n:,} {FAILURE_WORDS[k]}" for k, n in self.failures.items() if n]
        return f"{self.n_failures:,} violations on smooth patches: " + "; ".join(found)

    def payload(self) -> dict:
        summary = self.report.summary() | self.extra
        found = failures(summary)
        summary["params"] = params_json(
            self.report.params.quality, self.report.params.eps, **self.asked
        )
        lfs = getattr(self.report, "lfs", None)  # a whole check's L per ball
        if lfs is None:  # tiles keep only the range
            lfs = getattr(self.report, "lfs_range", None)
        if lfs is not None:
            summary |= sample_lfs(summary["params"], lfs)
        return summary | {
            "ok": not any(found.values()),
            "failures": found,
            "violations_smooth": found,
            "violations_at_features": feature_failures(summary),
            "written": list(self.written),
        }

    def to_frame(self):
        """One row per guide triangle: the columns of triangles.csv, then where the triangle
        is, the centers of its balls a, b, c (``a_x`` ... ``c_z``; pandas optional)."""
        from ..errors import InputError
        from ..reports.check import CheckReport, triangle_columns

        if not isinstance(self.report, CheckReport):
            raise InputError(
                "to_frame() needs the whole check's rows: a check in tiles keeps them in its "
                "output folder (out=..., the triangles table), not in memory"
            )
        columns = triangle_columns(self.report)
        centers = self.report.balls.centers
        for name in "abc":
            points = centers[columns[f"{name}_index"]]
            for axis, coordinate in enumerate("xyz"):
                columns[f"{name}_{coordinate}"] = points[:, axis]
        return frame(
            [dict(zip(columns, row, strict=True)) for row in zip(*columns.values(), strict=True)]
        )


@checked_arguments
def check(
    *,
    eps: float | None = None,
    sphere: float | None = None,
    torus: Sequence[float] | None = None,
    mesh: str | os.PathLike | TriangleMesh | None = None,
    lfs: float | None = None,
    sizing: str | os.PathLike | None = None,
    balls: str | os.PathLike | None = None,
    vorocrust: str | os.PathLike | None = None,
    sigma: float | None = None,
    delta_ratio: float | None = None,
    rho_f: float = PAPER_RHO_F,
    seed: int = 0,
    lipschitz: float | None = None,
    engine: str = "auto",
    out: str | os.PathLike | None = None,
    figure_format: str = "png",
    workers: int | None = None,
    scheduler: str | None = None,
    table: str | None = None,
    progress: Progress | None = None,
) -> CheckResult:
    """Sample a surface (or read ``balls``) and measure every guide triangle against the
    bounds.

    Guide triangles are the ball triples whose two seeds lie outside every other ball. Each is
    measured: realized ρ = R/(δL_i), gap (R − R̂)/(εL_i) of Theorem 1, R/R̂, whether it lies
    in the constraint set (33)–(36), H3, sparsity and λ-Lipschitz, and whether it exceeds each
    mode's bound at this ε. The sample is checked for coverage, sparsity and Lipschitz L.
    ``ok`` is False when any of that fails (the paper's invalid chain aside). ``out`` names
    a folder for the per-triangle rows (``table``: triangles.parquet where pyarrow is
    installed, else triangles.npz; triangles.csv or none on request), summary.json,
    sample.vtu and the gap histogram, written as one set. ``lipschitz`` is the λ that L =
    r/δ of ``balls`` should satisfy (default 1); a sampled surface uses its own λ.

    On a mesh with sharp features (as ``vorobound lfs`` finds them), guide triangles with a
    ball center within 2 ball radii of a feature are reported apart
    (``violations_at_features``, docs/samples.md "Sharp features"); only the smooth-patch
    ones (``violations_smooth``, also ``failures``) make ``ok`` False.

    With ``workers`` (local processes; 1 runs the tiles one after another here) or
    ``scheduler`` (a dask.distributed address), ``balls`` is streamed and checked in tiles with
    halos (docs/scale.md): the same guide triangles and summary, memory bounded by the tile.
    ``table`` then says how ``out`` holds the per-triangle rows: a Parquet dataset
    ``triangles/`` (default, needs pyarrow), one ``triangles.csv`` or ``triangles.npz`` joined
    from the tiles', or ``none`` (the default without pyarrow). ``mesh``
    (with ``lfs`` or ``sizing`` if given) is then read for its sharp features only.
    """
    from ..checks import checked_lipschitz, checked_seed
    from ..errors import InputError
    from ..reports.check import check_balls, check_surface
    from .surfaces import Surface

    if vorocrust is not None or (eps is None and balls is not None):
        if workers is not None or scheduler is not None or table is not None:
            raise InputError("workers, scheduler and table go with balls and eps")
        from .vorocrust import check_run

        return check_run(
            eps=eps,
            vorocrust=vorocrust,
            balls=balls,
            surface={"sphere": sphere, "torus": torus, "mesh": mesh, "lfs": lfs, "sizing": sizing},
            sigma=sigma,
            delta_ratio=delta_ratio,
            rho_f=rho_f,
            lipschitz=lipschitz,
            engine=engine,
            out=out,
            figure_format=figure_format,
            seed=seed,
            progress=progress,
            finish=_finish_with,
        )
    if eps is None:
        raise InputError("give eps (or balls or vorocrust, whose parameters are then inferred)")
    sigma = PAPER_SIGMA if sigma is None else sigma
    delta_ratio = PAPER_DELTA_RATIO if delta_ratio is None else delta_ratio
    checked_outputs(out, figure_format)
    seed = checked_seed(seed)
    quality = QualityParams(sigma, delta_ratio, rho_f)
    params = quality.at(eps)
    tiled = workers is not None or scheduler is not None
    if table is not None and out is None:
        raise InputError("table says how out writes the per-triangle rows: give out too")
    if tiled:
        if balls is None:
            raise InputError("workers and scheduler go with balls")
        if any(v is not None for v in (sphere, torus)):
            raise InputError(
                "coverage against a surface needs every ball at once: drop the surface option "
                "or workers/scheduler (a mesh is taken for its sharp features only)"
            )
        features = None
        if mesh is not None:
            from ..reports.check import sharp_features

            shape = Surface(mesh=mesh, lfs=lfs, sizing=sizing).shape(progress=progress)
            features = sharp_features(shape)
        elif lfs is not None or sizing is not None:
            raise InputError("lfs and sizing describe a mesh: use them with mesh")
        from ..checks import checked_count
        from ..reports.check_tiled import check_ball_file

        if workers is not None:
            workers = checked_count(workers, "workers", 1, 1 << 16)
        table = checked_table(table, tiled=True)
        lam = checked_lipschitz(1.0 if lipschitz is None else lipschitz)
        asked = {"seed": None, "engine": engine, "balls": os.fspath(balls), "workers": workers}
        asked |= {"scheduler": scheduler, "table": table}
        with _outputs(out, table, tiled=True) as outputs:
            tiled_report = check_ball_file(
                balls,
                params.but(lipschitz=lam),
                engine,
                workers or 1,
                scheduler,
                outputs,
                progress,
                features=features,
            )
            return _finish(tiled_report, asked, {}, outputs, figure_format)
    table = checked_table(table)
    shape = Surface(sphere, torus, mesh, lfs, sizing).shape(
        required=balls is None, instead=("balls FILE",), progress=progress
    )
    if balls is not None:
        from ..reports.vorocrust import off_surface, warn_off_surface
        from ..sampling.io.balls import read_balls

        lam = checked_lipschitz(1.0 if lipschitz is None else lipschitz)
        name = os.path.basename(os.fspath(balls))
        given = read_balls(os.fspath(balls))
        measured = off_surface(given, shape)
        if measured is not None:
            warn_off_surface(measured, given, name)
        report = check_balls(given, params.but(lipschitz=lam), engine, shape, name, progress)
        asked = {"seed": None, "engine": engine, "balls": os.fspath(balls)}
    else:
        if lipschitz is not None:
            raise InputError("lipschitz goes with balls (a surface's L has a known λ)")
        report = check_surface(shape, params.eps, quality, seed, engine, progress)
        asked = {"seed": seed, "engine": engine}
    asked["table"] = table if out is not None else None
    with _outputs(out, table) as outputs:
        return _finish(report, asked, {}, outputs, figure_format)


def _result(report, asked: dict) -> CheckResult:
    """The result of a check report (whole or tiled: the same summary)."""
    summary = report.summary()
    return typed_view(
        CheckResult,
        summary,
        source=report.source,
        n_failures=sum(failures(summary).values()),
        report=report,
        asked=asked,
    )


def _finish_with(report, asked: dict, extra: dict, out, figure_format: str) -> CheckResult:
    """The result of a check report with more JSON (``extra``), written to ``out`` if given."""
    table = checked_table(None)
    asked["table"] = table if out is not None else None
    with _outputs(out, table) as outputs:
        return _finish(report, asked, extra, outputs, figure_format)


def _outputs(out, table: str, tiled: bool = False):
    """The output set of a check in ``out`` (a context manager; nothing without ``out``)."""
    from contextlib import nullcontext

    from ..reports.check_outputs import CheckOutputs

    return nullcontext() if out is None else CheckOutputs(out, table, tiled)


def _finish(
    report, asked: dict, extra: dict, outputs: CheckOutputs | None, figure_format: str
) -> CheckResult:
    """The result of a check, whole or tiled, written into ``outputs`` if given."""
    import dataclasses

    result = dataclasses.replace(_result(report, asked), extra=extra)
    if outputs is None:
        return result
    return write_outputs(result, outputs, figure_format)


def write_outputs(result: CheckResult, outputs: CheckOutputs, figure_format: str) -> CheckResult:
    """The per-triangle rows, summary.json (the result's JSON), sample.vtu and the gap
    histogram of a check, whole or tiled, written into ``outputs``
    (:class:`vorobound.reports.check_outputs.CheckOutputs`) as one set; the result names
    them."""
    import dataclasses

    from ..plotting import figure_writer, plot_gap_counts, plot_gap_histogram
    from ..reports.check import GAP_HISTOGRAM_STEM, histogram_marks
    from ..reports.check_tiled import TiledCheckReport

    report = result.report
    marks = histogram_marks(report)
    if isinstance(report, TiledCheckReport):
        g = report.guides
        span = (g.gap_min, g.maxima.get("gap_ratio", 0.0))
        figure = plot_gap_counts(report.gap_edges, g.histogram, span, marks, report.source)
    else:
        figure = plot_gap_histogram(report.guides.gap_ratio, marks, report.source)
    writers = outputs.writers(report)
    writers[outputs.folder / f"{GAP_HISTOGRAM_STEM}.{figure_format}"] = figure_writer(
        figure, figure_format
    )
    result = dataclasses.replace(
        result,
        written=tuple(os.fspath(p) for p in outputs.listed(writers)),
        extra=result.extra | outputs.extra(report),
    )
    text = json.dumps(result.to_dict(), indent=2, allow_nan=False) + "\n"
    writers[outputs.folder / "summary.json"] = partial(_write_text, text=text)
    outputs.publish(writers)
    return result


def _write_text(path: Path, text: str) -> None:
    path.write_text(text, encoding="utf-8")
