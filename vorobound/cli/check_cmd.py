"""``vorobound check``: guide triangles of a real sample measured against every bound."""

from __future__ import annotations

from enum import Enum
from pathlib import Path
from typing import Annotated

import typer

from ..errors import InputError
from .options import DeltaRatio, Eps, Json, RhoF, Seed, Sigma
from .progress import progress_bar
from .render import fmt, print_json, print_table
from .sample_cmd import MeshLfsOpt, MeshOpt, SizingOpt, SphereOpt, TorusOpt, surface_shape


class EngineChoice(str, Enum):
    auto = "auto"
    gudhi = "gudhi"
    hull = "hull"
    brute = "brute"


class TableChoice(str, Enum):
    parquet = "parquet"
    csv = "csv"
    none = "none"


def check(
    eps: Eps,
    sphere: SphereOpt = None,
    torus: TorusOpt = None,
    mesh: MeshOpt = None,
    lfs: MeshLfsOpt = None,
    sizing: SizingOpt = None,
    balls: Annotated[
        Path | None,
        typer.Option(
            "--balls",
            help="Check these balls instead of sampling: CSV or NPZ with x, y, z, r, or a "
            "point set meshio reads with a point-data array r/radius. L_i = r_i/δ. With a "
            "surface option too, coverage is measured on that surface.",
        ),
    ] = None,
    sigma: Sigma = 0.75,
    delta_ratio: DeltaRatio = 2.0,
    rho_f: RhoF = 1.38,
    seed: Seed = 0,
    lipschitz: Annotated[
        float | None,
        typer.Option(
            "--lipschitz",
            help="λ that L = r/δ of --balls should satisfy, |L_i − L_j| ≤ λ|p_i − p_j| "
            "(default 1, as for a local feature size); a sampled surface uses its own λ.",
        ),
    ] = None,
    engine: Annotated[
        EngineChoice,
        typer.Option(
            "--engine",
            help="Candidate triples: gudhi (regular triangulation, CGAL), hull (equal radii "
            "on a sphere), brute (all overlapping triples; small inputs), auto (hull for a "
            "sphere, else gudhi if installed, else brute).",
        ),
    ] = EngineChoice.auto,
    out: Annotated[
        Path | None,
        typer.Option(
            "--out",
            help="Folder for triangles.csv, summary.json, sample.vtu (ParaView) and "
            "gap_histogram.<format>.",
        ),
    ] = None,
    fmt_: Annotated[
        str, typer.Option("--format", help="Figure format for --out: png, pdf or svg.")
    ] = "png",
    workers: Annotated[
        int | None,
        typer.Option(
            "--workers",
            min=1,
            help="Check --balls in tiles on this many local processes (1: tiles one after "
            "another in this process), streaming the file: for samples too large for one "
            "process (docs/scale.md). Same guide triangles and summary as without.",
        ),
    ] = None,
    scheduler: Annotated[
        str | None,
        typer.Option(
            "--scheduler",
            help="Check --balls in tiles on a dask.distributed cluster, e.g. "
            "tcp://127.0.0.1:8786 (needs the dask extra of vorobound).",
        ),
    ] = None,
    table: Annotated[
        TableChoice | None,
        typer.Option(
            "--table",
            help="With --workers/--scheduler and --out: per-triangle rows as a Parquet "
            "dataset triangles/ (default; needs pyarrow), one triangles.csv, or none. "
            "sample.vtu then holds a share of the triangles (docs/scale.md).",
        ),
    ] = None,
    as_json: Json = False,
) -> None:
    """Sample a surface (or read balls) and measure every guide triangle against the bounds.

    Guide triangles are the ball triples whose two seeds lie outside every other ball. Each is
    measured: realized ρ = R/(δL_i), gap (R − R̂)/(εL_i) of Theorem 1, whether it lies in the
    constraint set (33)–(36), H3, sparsity and λ-Lipschitz, and whether it exceeds each mode's
    bound at this ε. The sample itself is checked for coverage, sparsity and Lipschitz L.
    """
    from ..bounds.params import SamplingParams, checked_lipschitz
    from ..checks import checked_seed
    from ..files import checked_folder
    from ..reports.check import check_balls, check_surface
    from .options import quality_params

    if fmt_ not in ("png", "pdf", "svg"):
        raise InputError(f"--format: expected png, pdf or svg, got {fmt_!r}")
    seed = checked_seed(seed)
    if out is not None:
        checked_folder(out)
    quality = quality_params(sigma, delta_ratio, rho_f)
    params = SamplingParams(eps, quality)
    if table is not None and workers is None and scheduler is None:
        raise InputError("--table goes with --workers or --scheduler (a tiled check)")
    if workers is not None or scheduler is not None:
        return _check_tiled(
            balls,
            params,
            lipschitz,
            engine,
            workers,
            scheduler,
            table,
            out,
            fmt_,
            as_json,
            (sphere, torus, mesh, lfs, sizing),
        )
    with progress_bar(not as_json) as progress:
        shape = surface_shape(sphere, torus, mesh, lfs, sizing, balls is None, progress)
        if balls is not None:
            from ..sampling.io.balls import read_balls

            lam = checked_lipschitz(1.0 if lipschitz is None else lipschitz)
            report = check_balls(
                read_balls(balls), params, lam, engine.value, shape, balls.name, progress
            )
        else:
            if lipschitz is not None:
                raise InputError("--lipschitz goes with --balls (a surface's L has a known λ)")
            report = check_surface(shape, params.eps, quality, seed, engine.value, progress)
        written = _write_outputs(report, out, fmt_) if out is not None else []
    summary = report.summary()
    if as_json:
        print_json(summary | {"written": [str(p) for p in written]})
        return
    _print_summary(summary)
    for path in written:
        print(f"wrote {path}")


def _write_outputs(report, out, fmt_: str) -> list:
    """triangles.csv, summary.json, sample.vtu and the gap histogram, written as one set."""
    from ..files import ensure_folder, write_set
    from ..plotting import figure_writer, plot_gap_histogram
    from ..reports.check import GAP_HISTOGRAM_STEM, histogram_marks, output_writers

    folder = ensure_folder(out)
    writers = output_writers(report, folder)
    figure = plot_gap_histogram(report.guides.gap_ratio, histogram_marks(report), report.source)
    writers[folder / f"{GAP_HISTOGRAM_STEM}.{fmt_}"] = figure_writer(figure, fmt_)
    return write_set(writers)


def _check_tiled(
    balls, params, lipschitz, engine, workers, scheduler, table, out, fmt_, as_json, surfaces
) -> None:
    """``check --balls`` in tiles (reports/check_tiled.py); outputs as one set."""
    from contextlib import nullcontext

    from ..bounds.params import checked_lipschitz
    from ..reports.check import GAP_HISTOGRAM_STEM
    from ..reports.check_tiled import check_ball_file
    from ..reports.tiled_outputs import TiledOutputs
    from ..reports.tiled_report import histogram_marks

    if balls is None:
        raise InputError("--workers and --scheduler go with --balls")
    if any(option is not None for option in surfaces):
        raise InputError(
            "coverage against a surface needs every ball at once: drop the surface option "
            "or --workers/--scheduler"
        )
    if table is not None and out is None:
        raise InputError("--table says how --out writes the rows: give --out too")
    table = table or (TableChoice.parquet if _has_pyarrow() else TableChoice.none)
    lam = checked_lipschitz(1.0 if lipschitz is None else lipschitz)
    staging = TiledOutputs(out, table.value) if out is not None else nullcontext()
    with progress_bar(not as_json) as progress, staging as outputs:
        report = check_ball_file(
            balls, params, lam, engine.value, workers or 1, scheduler, outputs, progress
        )
        written = []
        if outputs is not None:
            from ..plotting import figure_writer, plot_gap_counts

            g = report.guides
            figure = plot_gap_counts(
                report.gap_edges,
                g.histogram,
                (g.gap_min, g.maxima.get("gap_ratio", 0.0)),
                histogram_marks(report),
                report.source,
            )
            writers = outputs.writers(report)
            writers[outputs.folder / f"{GAP_HISTOGRAM_STEM}.{fmt_}"] = figure_writer(figure, fmt_)
            written = outputs.publish(writers)
        summary = report.summary() | ({} if outputs is None else {"rows": outputs.rows(report)})
    if as_json:
        print_json(summary | {"written": [str(p) for p in written]})
        return
    _print_summary(summary)
    for path in written:
        print(f"wrote {path}")


def _has_pyarrow() -> bool:
    from ..sampling.io.balls import pyarrow_available

    return pyarrow_available()


def _print_summary(s: dict) -> None:
    p = s["params"]
    title = (
        f"Check of {s['source']} at ε = {p['eps']:g} "
        f"(σ = {p['sigma']:g}, δ = {p['delta_ratio']:g}ε)"
    )
    share = s["half_covered_share"]
    print_table(
        title,
        ("quantity", "value", "required / meaning"),
        [
            ("samples", f"{s['n_samples']:,}", ""),
            ("guide triangles", f"{s['n_guide_triangles']:,}", f"engine {s['engine']}"),
            (
                "half-covered",
                f"{s['n_half_covered']:,}",
                "one seed covered" + ("" if share is None else f" ({100 * share:.2f} % of seeded)"),
            ),
            ("coverage_max", fmt(s["coverage_max"], 6), s.get("coverage_note", "< 1 (measured)")),
            (
                "sparsity_min",
                fmt(s["sparsity_min"], 10),
                f"≥ 1 ({s['sparsity_violations']} pairs below)",
            ),
            (
                "Lipschitz of L",
                fmt(s["lipschitz_realized"], 6),
                f"≤ λ = {fmt(s['lipschitz'])} ({s['lipschitz_violations']} pairs above)",
            ),
            (
                "max R/(δL_i)",
                fmt(s["rho_max"], 6),
                f"≤ ρ_f = {p['rho_f']:g} ({s['quality_violations']} above)",
            ),
            ("max (R − R̂)/(εL_i)", fmt(s["gap_ratio_max"], 6), "realized gap (Theorem 1)"),
            (
                "max R/R̂",
                fmt(s["ratio_max"], 6),
                f"≤ ρ_f = {p['rho_f']:g}, eq. (54) ({s['ratio_violations']} above)",
            ),
            (
                "max R(1−ε)/(εL_i)",
                fmt(s["h3_ratio_max"], 6),
                f"≤ 1 if H3 holds (an assumption; {s['h3_violations']} above)",
            ),
            (
                "outside constraint set",
                f"{s['outside_constraint_set']:,}",
                ", ".join(f"{k}: {v}" for k, v in s["constraint_violations"].items() if v)
                or "none",
            ),
        ],
    )
    print_table(
        "Bounds on (R − R̂)/(εL_i) at this ε",
        ("mode", "claim", "bound", "realized max / bound", "triangles above"),
        [
            (
                mode + ("" if b["lipschitz"] is None else f" (λ = {b['lipschitz']:g})"),
                b["claim"],
                fmt(b["gap_ratio"], 6),
                "n/a"
                if not b["gap_ratio"] or s["gap_ratio_max"] is None
                else fmt(s["gap_ratio_max"] / b["gap_ratio"], 4),
                "n/a (not defined)"
                if s["violations"][mode] is None
                else f"{s['violations'][mode]:,}",
            )
            for mode, b in s["bound"].items()
        ],
    )
    print_table(
        "Bounds on R/R̂ at this ε (ratio target, eq. (54))",
        ("mode", "claim", "bound", "realized max / bound", "triangles above"),
        [
            (
                mode + ("" if b["lipschitz"] is None else f" (λ = {b['lipschitz']:g})"),
                b["claim"],
                "none (∞)" if b["value"] is None else fmt(b["value"], 6),
                "n/a"
                if b["value"] is None or s["ratio_max"] is None
                else fmt(s["ratio_max"] / b["value"], 4),
                f"{s['ratio_bound_violations'].get(mode, 0):,}",
            )
            for mode, b in s["ratio_bound"].items()
        ],
    )
    for name, key in (("sparsity", "sparsity_worst"), ("Lipschitz", "lipschitz_worst")):
        rows = s[key]
        if rows:
            print_table(
                f"Worst {name} violations",
                ("i", "j", "ratio", "where (midpoint)"),
                [
                    (
                        str(r["i"]),
                        str(r["j"]),
                        fmt(r["ratio"], 8),
                        ", ".join(f"{x:.6g}" for x in r["where"]),
                    )
                    for r in rows
                ],
            )
