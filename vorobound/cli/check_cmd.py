"""``vorobound check``: guide triangles of a real sample measured against every bound."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from ..constants import PAPER_DELTA_RATIO, PAPER_RHO_F, PAPER_SIGMA
from ..rounding import format_up
from .command import grouped, invoke
from .options import (
    LAMBDA_HELP,
    EngineChoice,
    EngineOpt,
    FigureFormat,
    FigureFormatOpt,
    Json,
    RhoF,
    Seed,
    SurfaceOptions,
    TableChoice,
)
from .render import fmt, print_table

if TYPE_CHECKING:
    from ..api.check_summary import BoundAtEps, CheckSummary


@grouped
def check(
    eps: Annotated[
        float | None,
        typer.Option(
            "--eps",
            metavar="EPS",
            help="Sampling density ε, 0 < ε < 1. Optional with --balls or --vorocrust: then "
            "the ε, σ, δ/ε and λ the balls realize are inferred from the balls and the surface, "
            "with the guarantee they give (docs/vorocrust.md).",
        ),
    ] = None,
    surface: SurfaceOptions = SurfaceOptions(),
    balls: Annotated[
        Path | None,
        typer.Option(
            "--balls",
            metavar="FILE",
            help="Check these balls instead of sampling: CSV or NPZ with x, y, z, r, or a "
            "point set meshio reads with a point-data array r/radius. L_i = r_i/δ. With a "
            "surface option too, coverage is measured on that surface.",
        ),
    ] = None,
    vorocrust: Annotated[
        Path | None,
        typer.Option(
            "--vorocrust",
            metavar="DIR",
            help="A VoroCrust run folder (vc_mesh's vc.in, the mesh it names, "
            "surface/edges/corner_spheres.csv, seeds.csv): the surface balls are checked "
            "against that mesh (or the surface given); corner and edge balls are reported "
            "apart, never in the smooth verdict (docs/vorocrust.md).",
        ),
    ] = None,
    sigma: Annotated[
        float | None,
        typer.Option(
            "--sigma",
            metavar="SIGMA",
            help=f"Sparsity σ (paper: {PAPER_SIGMA:g}; inferred without --eps).",
        ),
    ] = None,
    delta_ratio: Annotated[
        float | None,
        typer.Option(
            "--delta-ratio",
            metavar="RATIO",
            help=f"Ball radius over ε, δ/ε (paper: {PAPER_DELTA_RATIO:g}; inferred without --eps).",
        ),
    ] = None,
    rho_f: RhoF = PAPER_RHO_F,
    seed: Seed = 0,
    lipschitz: Annotated[
        float | None,
        typer.Option(
            "--lipschitz",
            metavar="LAMBDA",
            help=LAMBDA_HELP + "the λ that L = r/δ of --balls should have "
            "(default 1, as for a local feature size); a sampled surface uses its own λ.",
        ),
    ] = None,
    engine: EngineOpt = EngineChoice.auto,
    out: Annotated[
        Path | None,
        typer.Option(
            "--out",
            metavar="DIR",
            help="Folder for the per-triangle rows (triangles.parquet or .npz; --table), "
            "summary.json, sample.vtu (ParaView) and gap_histogram.<figure format>, written as "
            "one set.",
        ),
    ] = None,
    figure_format: FigureFormatOpt = FigureFormat.png,
    workers: Annotated[
        int | None,
        typer.Option(
            "--workers",
            metavar="N",
            help="Check --balls in tiles on this many local processes (1: tiles one after "
            "another in this process), streaming the file: for samples too large for one "
            "process (docs/scale.md). Same guide triangles and summary as without. N sets "
            "the tiling; at most one process per CPU runs at once.",
        ),
    ] = None,
    scheduler: Annotated[
        str | None,
        typer.Option(
            "--scheduler",
            metavar="ADDRESS",
            help="Check --balls in tiles on a dask.distributed cluster, e.g. "
            "tcp://127.0.0.1:8786 (needs the dask extra of vorobound).",
        ),
    ] = None,
    table: Annotated[
        TableChoice | None,
        typer.Option(
            "--table",
            help="How --out holds the per-triangle rows: parquet (default where pyarrow is "
            "installed), npz (the default without it), csv (10 significant digits) or none. "
            "In tiles (--workers/--scheduler): a Parquet dataset triangles/, one "
            "triangles.csv or triangles.npz joined from the tiles', or none (the default "
            "without pyarrow), and sample.vtu holds a share of the triangles (docs/scale.md).",
        ),
    ] = None,
    as_json: Json = False,
) -> int:
    """Sample a surface (or read balls) and measure every guide triangle against the bounds.

    Guide triangles are the ball triples whose two seeds lie outside every other ball. Each is
    measured: realized ρ = R/(δL_i), gap (R − R̂)/(εL_i) of Theorem 1, whether it lies in the
    constraint set (33)–(36), H3, sparsity and λ-Lipschitz, and whether it exceeds each mode's
    bound at this ε. The sample itself is checked for coverage, sparsity and Lipschitz L.
    Exit code 1 when anything checked fails (the last line counts it). Python:
    vorobound.check(eps=..., torus=(3, 1)).
    """
    return invoke(
        "check", _show, locals(), instead={"--balls FILE": balls, "--vorocrust DIR": vorocrust}
    )


def _show(result) -> None:
    summary = result.summary
    _print_summary(summary)
    if summary.realized is not None:
        _print_realized(summary)
    for path in result.written:
        print(f"wrote {path}")


def _print_classes(s: CheckSummary) -> None:
    """Smooth-patch and feature triangles apart: only the first decide the exit code."""
    worst = s.at_features.worst_h3_centroid
    notes = (
        "decides the exit code",
        "reported only"
        + ("" if worst is None else ("; worst H3 at " + ", ".join(f"{x:.6g}" for x in worst))),
    )
    rows = [
        (
            where,
            f"{c.n_guide_triangles:,}",
            *(f"{n:,}" for n in (c.outside_constraint_set, c.quality, c.ratio, c.proven_bound)),
            note,
        )
        for where, c, note in zip(
            ("smooth patches", "at sharp features"), (s.smooth, s.at_features), notes, strict=True
        )
    ]
    print_table(
        "Guide triangles by where they sit",
        (
            "where",
            "triangles",
            "outside (33)-(36)/H3",
            "R > ρ_f δL_i",
            "R > ρ_f R̂",
            "proven bound",
            "note",
        ),
        rows,
    )
    print(f"rule: {s.feature_rule}")


def _print_summary(s: CheckSummary) -> None:
    p = s.params
    title = f"Check of {s.source} at ε = {p.eps:g} (σ = {p.sigma:g}, δ = {p.delta_ratio:g}ε)"
    share = s.half_covered_share
    print_table(
        title,
        ("quantity", "value", "required / meaning"),
        [
            ("samples", f"{s.n_samples:,}", ""),
            ("guide triangles", f"{s.n_guide_triangles:,}", f"engine {s.engine}"),
            (
                "half-covered",
                f"{s.n_half_covered:,}",
                "one seed covered" + ("" if share is None else f" ({100 * share:.2f} % of seeded)"),
            ),
            ("coverage_max", fmt(s.coverage_max, 6), s.coverage_note or "< 1 (measured)"),
            (
                "sparsity_min",
                fmt(s.sparsity_min, 10),
                f"≥ 1 ({s.sparsity_violations} pairs below)",
            ),
            (
                "Lipschitz of L",
                fmt(s.lipschitz_realized, 6),
                f"≤ λ = {fmt(s.lipschitz)} ({s.lipschitz_violations} pairs above)",
            ),
            (
                "max R/(δL_i)",
                fmt(s.rho_max, 6),
                f"≤ ρ_f = {p.rho_f:g} ({s.quality_violations} above)",
            ),
            ("max (R − R̂)/(εL_i)", fmt(s.gap_ratio_max, 6), "realized gap (Theorem 1)"),
            (
                "max R/R̂",
                fmt(s.ratio_max, 6),
                f"≤ ρ_f = {p.rho_f:g}, eq. (54) ({s.ratio_violations} above)",
            ),
            (
                "max R(1−ε)/(εL_i)",
                fmt(s.h3_ratio_max, 6),
                f"≤ 1 if H3 holds (an assumption; {s.h3_violations} above)",
            ),
            (
                "outside constraint set",
                f"{s.outside_constraint_set:,}",
                ", ".join(f"{k}: {v}" for k, v in s.constraint_violations.items() if v) or "none",
            ),
        ],
    )
    _bounds_table("Bounds on (R − R̂)/(εL_i) at this ε", s.gap_bounds, s.gap_ratio_max, "n/a")
    _bounds_table(
        "Bounds on R/R̂ at this ε (ratio target, eq. (54))", s.ratio_bounds, s.ratio_max, "none (∞)"
    )
    _print_classes(s)
    for name, pairs in (("sparsity", s.sparsity_worst), ("Lipschitz", s.lipschitz_worst)):
        if pairs:
            print_table(
                f"Worst {name} violations",
                ("i", "j", "ratio", "where (midpoint)"),
                [
                    (str(r.i), str(r.j), fmt(r.ratio, 8), ", ".join(f"{x:.6g}" for x in r.where))
                    for r in pairs
                ],
            )


def _bounds_table(
    title: str, bounds: Sequence[BoundAtEps], realized: float | None, unbounded: str
) -> None:
    """Every mode's bound at this ε against the ``realized`` maximum, and how many triangles
    exceed it."""
    rows = [
        (
            b.mode + ("" if b.lipschitz is None else f" (λ = {b.lipschitz:g})"),
            b.claim,
            unbounded if b.value is None else format_up(b.value, 6),
            "n/a" if not b.value or realized is None else fmt(realized / b.value, 4),
            "n/a (not defined)" if b.above is None else f"{b.above:,}",
        )
        for b in bounds
    ]
    columns = ("mode", "claim", "bound", "realized max / bound", "triangles above")
    print_table(title, columns, rows)


def _print_realized(s: CheckSummary) -> None:
    """What the balls realize and the guarantee (check without --eps, or --vorocrust)."""
    from ..rounding import format_down

    r, g = s.realized, s.guarantee
    assert r is not None and g is not None, "balls whose parameters were inferred"
    print_table(
        "Parameters the balls realize (docs/vorocrust.md)",
        ("parameter", "value", "from"),
        [
            ("ε", format_up(r.eps), f"coverage {fmt(r.coverage_over_lfs_max, 6)} (measured)"),
            ("δ/ε", format_up(r.delta_ratio), f"max r/L {fmt(r.radius_over_lfs_max, 6)}"),
            ("σ", format_down(r.sigma), f"min |p−q|/r {fmt(r.spacing_over_radius_min, 6)}"),
            ("λ", format_up(r.lipschitz), f"max |Δr|/|p−q| {fmt(r.radius_lipschitz, 6)}"),
        ],
    )
    print(
        f"Guarantee ({g.target} target): "
        + (
            f"R ≤ {format_up(g.rho_f)}·R̂ for every guide triangle, {g.claim}"
            if g.rho_f is not None
            else f"none proven: {g.failed_condition} fails"
        )
    )
    strata = s.strata or {}
    print(f"strata: {', '.join(f'{k} {v}' for k, v in strata.items() if v is not None)}")
