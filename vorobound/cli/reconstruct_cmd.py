"""``vorobound reconstruct``: VoroCrust's surface M̂ built from the seeds and measured."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from ..constants import PAPER_DELTA_RATIO, PAPER_SIGMA
from ..rounding import format_down
from .command import grouped, invoke
from .options import (
    DeltaRatio,
    EngineChoice,
    EngineOpt,
    FigureFormat,
    FigureFormatOpt,
    Json,
    Seed,
    Sigma,
    SurfaceOptions,
    parse_values,
)
from .render import fmt, print_footer, print_table

if TYPE_CHECKING:
    from ..api.reconstruct import ReconstructDrawsResult
    from ..api.reconstruct_summary import ReconstructSummary
    from ..reports.reconstruct_draws import Spread
    from ..reports.reconstruct_sweep import EpsMark, ReconstructSweep


@grouped
def reconstruct(
    eps: Annotated[
        str | None,
        typer.Option(
            "--eps",
            metavar="EPS",
            help="Sampling density ε; start:stop:num (or a comma list) reconstructs at each ε "
            "(a sweep). With --balls or --seeds, the ε of the balls, for distances in units of "
            "ε·L.",
        ),
    ] = None,
    surface: SurfaceOptions = SurfaceOptions(),
    balls: Annotated[
        Path | None,
        typer.Option(
            "--balls",
            metavar="FILE",
            help="Balls instead of a sample (as for check --balls). Seeds are labelled by the "
            "surface option if given, else by the two sheets of the union's boundary.",
        ),
    ] = None,
    seeds: Annotated[
        Path | None,
        typer.Option(
            "--seeds",
            metavar="FILE",
            help="Labelled seeds: VoroCrust's CSV (x, y, z, sizing, region id with 0 outside, "
            "1 inside; a header naming x, y, z and region_id or region is optional).",
        ),
    ] = None,
    vorocrust: Annotated[
        Path | None,
        typer.Option(
            "--vorocrust",
            metavar="DIR",
            help="A VoroCrust run folder: M̂ of its seeds.csv against the mesh its vc.in names "
            "(or the surface given), distances in units of the local ball radius (the nearest "
            "corner, edge or surface ball's; docs/vorocrust.md).",
        ),
    ] = None,
    half_covered: Annotated[
        bool,
        typer.Option(
            "--half-covered",
            metavar="",
            help="Also seed the uncovered seed of each half-covered triple (every vertex of "
            "the union's boundary is then a seed).",
        ),
    ] = False,
    compare_sheets: Annotated[
        bool,
        typer.Option(
            "--compare-sheets",
            metavar="",
            help="Also label the seeds by the union's sheets and count where they differ from "
            "the surface's labels.",
        ),
    ] = False,
    sigma: Sigma = PAPER_SIGMA,
    delta_ratio: DeltaRatio = PAPER_DELTA_RATIO,
    seed: Seed = 0,
    repeats: Annotated[
        int | None,
        typer.Option(
            "--repeats",
            metavar="K",
            help="Sample the surface K times at each ε (draw k with seed SEED + k) and report "
            "per ε the share of draws whose M̂ has the right topology and the median and "
            "largest Hausdorff distance and normal deviation; a sweep also reports the "
            "transition band. 1 ≤ K ≤ 10000.",
        ),
    ] = None,
    engine: EngineOpt = EngineChoice.auto,
    slabs: Annotated[
        int | None,
        typer.Option(
            "--slabs",
            metavar="N",
            help="Triangulate the seeds in N overlapping slabs, one at a time: memory bounded "
            "by a slab, the same M̂ (certified complete; the whole set at once where a check "
            "fails). 1: the whole set at once. Default: one slab per 400,000 seeds above "
            "1,500,000 seeds. 1 ≤ N ≤ 10000.",
        ),
    ] = None,
    out: Annotated[
        Path | None,
        typer.Option(
            "--out",
            metavar="DIR",
            help="Folder for mhat.vtu (ParaView; facet fields), mhat.ply, seeds.vtu, seeds.csv, "
            "summary.json and quality.<figure format>; a sweep writes sweep.csv, summary.json "
            "and sweep.<figure format>; --repeats writes draws.csv, summary.json and (several "
            "ε) sweep.<figure format>. Written as one set.",
        ),
    ] = None,
    figure_format: FigureFormatOpt = FigureFormat.png,
    as_json: Json = False,
) -> int:
    """Build VoroCrust's surface M̂ (the Voronoi facets between inside and outside seeds) and
    measure it.

    Seeds are both seeds of every guide triangle of a sample (--sphere, --torus, --mesh with
    --eps), of --balls, or read from --seeds. Reported: whether M̂ is a closed 2-manifold, its
    components, Euler characteristic and genus against the surface's, the two-sided Hausdorff
    distance to the surface over ε·L, the facet normals' deviation from the surface's, and the
    facets' quality. With --repeats K, K draws per ε: the share of draws with the right
    topology, the spread of the measurements and the ε band where M̂ goes from always right to
    never right. Exit code 0 when M̂ is a closed manifold with the surface's topology (in every
    draw), 1 when it is measured to be wrong, 2 for bad input. Python:
    vorobound.reconstruct(...).
    """
    return invoke(
        "reconstruct",
        _show,
        locals(),
        instead={"--balls FILE": balls, "--seeds FILE": seeds, "--vorocrust DIR": vorocrust},
        eps=None if eps is None else parse_values(eps, "--eps"),
    )


def _show(result) -> None:
    if hasattr(result, "draws"):
        _print_draws(result)
    elif hasattr(result, "sweep"):
        _print_sweep(result.sweep)
    else:
        _print_summary(result.summary)
    for path in result.written:
        print(f"wrote {path}")


def _topology_text(s: ReconstructSummary) -> str:
    if s.expected_euler_characteristic is None:
        return "no surface to compare with"
    return f"surface: χ = {s.expected_euler_characteristic}, {s.expected_components} component(s)"


def _verdict(correct: bool | None) -> str:
    if correct is None:
        return "no reference surface"
    return "right" if correct else "WRONG"


def _print_summary(s: ReconstructSummary) -> None:
    eps = "" if s.eps is None else f" at ε = {s.eps:g}"
    rows = []
    if s.n_samples is not None:
        rows += [
            ("balls", f"{s.n_samples:,}", ""),
            ("guide triangles", f"{s.n_guide_triangles:,}", f"engine {s.engine}"),
            ("half-covered", f"{s.n_half_covered:,}", "triples with one seed covered"),
        ]
    seeds_note = f"{s.n_inside_seeds:,} inside; labels from the {s.labels}"
    if s.sheet_label_disagreements is not None:
        seeds_note += f" ({s.sheet_label_disagreements} differ by the union's sheets)"
    rows += [
        ("seeds", f"{s.n_seeds:,}", seeds_note),
        ("facets of M̂", f"{s.n_facets:,}", f"{s.collapsed_facets:,} in/out pairs with no area"),
        (
            "closed 2-manifold",
            "yes" if s.closed_manifold else "no",
            f"{s.boundary_edges} boundary and {s.nonmanifold_edges} non-manifold edges, "
            f"{s.nonmanifold_vertices} pinched vertices, {s.unbounded_facets} facets at "
            "infinity",
        ),
        ("Euler characteristic", str(s.euler_characteristic), _topology_text(s)),
        ("components", str(s.components), f"genus {fmt(s.genus)}"),
        ("topology", _verdict(s.topology_correct), ""),
        (
            "min edge ratio",
            fmt(s.edge_ratio_min, 4),
            f"median {fmt(s.edge_ratio_median, 4)} (shortest / longest edge)",
        ),
        (
            "min angle (°)",
            fmt(s.min_angle_min_deg, 4),
            f"median {fmt(s.min_angle_median_deg, 4)}",
        ),
    ]
    if s.measured:
        rows += [
            (
                "Hausdorff / (εL)",
                fmt(s.hausdorff_over_eps_lfs, 4),
                f"M̂ → surface {fmt(s.mhat_to_surface_over_eps_lfs, 4)}, surface → M̂ "
                f"{fmt(s.surface_to_mhat_over_eps_lfs, 4)} (measured)",
            ),
            (
                "max normal deviation (°)",
                fmt(s.normal_deviation_max_deg, 4),
                f"median {fmt(s.normal_deviation_median_deg, 4)}; "
                f"{s.flipped_facets} facets above 90°",
            ),
        ]
    print_table(f"M̂ of {s.source}{eps}", ("quantity", "value", "meaning"), rows)
    if s.note:
        print_footer(s.note)
    for line in readings(s):
        print_footer(line)


READING_DOC = "docs/reconstruct.md, 'Reading the measurements'"
SLIVER_EDGE_RATIO = 1e-2
"""Facets whose shortest edge is below this share of their longest are slivers."""
SLIVER_ANGLE_DEG = 1.0
"""Facets with an angle below this many degrees are slivers."""


def readings(s: ReconstructSummary) -> list[str]:
    """One line per measurement a reader cannot judge alone (facets without area, slivers,
    normal deviation): whether it matters, and where the docs explain it."""
    lines = []
    if s.collapsed_facets:
        lines.append(
            f"reading: {s.collapsed_facets:,} in/out pairs with no area are seeds on one "
            "ball's sphere meeting in a Voronoi vertex, not a facet (VoroCrust's seeds are "
            f"cospherical by construction); no part of M̂ is missing, harmless ({READING_DOC})"
        )
    ratio, angle = s.edge_ratio_min, s.min_angle_min_deg
    if ratio is not None and angle is not None:
        measured = f"min edge ratio {fmt(ratio, 3)}, min angle {fmt(angle, 3)}°"
        if ratio < SLIVER_EDGE_RATIO or angle < SLIVER_ANGLE_DEG:
            lines.append(
                f"reading: {measured}: sliver facets, where nearly cospherical seeds put Voronoi "
                "vertices close together; they are facets of M̂ like any other, harmless for the "
                f"topology and the distances, and matter only if M̂'s polygons are used as a "
                f"mesh ({READING_DOC})"
            )
        else:
            lines.append(f"reading: {measured}: no sliver facets ({READING_DOC})")
    if s.normal_deviation_max_deg is not None:
        deviation, flipped = s.normal_deviation_max_deg, s.flipped_facets
        if flipped:
            lines.append(
                f"reading: {flipped:,} facets above 90° face inward: M̂ folds there "
                "(normal_deviation_deg > 90 in mhat.vtu); this matters even where the topology "
                f"is right ({READING_DOC})"
            )
        else:
            lines.append(
                f"reading: max normal deviation {fmt(deviation, 4)}° is below 90°: every facet "
                "faces outward; the largest deviations are polygons tilted against the surface "
                "(half-covered triples, sharp features), not an error of M̂ "
                f"({READING_DOC})"
            )
    return lines


def _print_sweep(sweep: ReconstructSweep) -> None:
    q = sweep.quality
    print_table(
        f"M̂ of {sweep.source} against ε (σ = {q.sigma:g}, δ = {q.delta_ratio:g}ε)",
        (
            "ε",
            "samples",
            "facets",
            "topology",
            "χ",
            "Hausdorff/(εL)",
            "max normal dev. (°)",
            "min angle (°)",
        ),
        [
            (
                f"{r.eps:.4g}",
                "" if r.samples is None else f"{r.samples:,}",
                f"{r.facets:,}",
                _verdict(r.topology_correct) + ("" if r.closed_manifold else " (not closed)"),
                str(r.euler_characteristic),
                fmt(r.hausdorff, 4),
                fmt(r.normal_deviation_max, 4),
                fmt(r.min_angle_min, 4),
            )
            for r in sweep.rows
        ],
    )
    _print_marks(sweep.marks)
    for r in sweep.rows:
        if r.note:
            print_footer(f"ε = {r.eps:g}: {r.note}")


def _print_marks(marks: Sequence[EpsMark]) -> None:
    print_table(
        "Every bound's ε*",
        ("bound", "target", "ε*", "claim"),
        [(m.label, m.target, format_down(m.eps_star), m.claim) for m in marks],
    )


def _spread(spread: Spread) -> tuple[str, str]:
    return fmt(spread.median, 4), fmt(spread.max, 4)


def _print_draws(result: ReconstructDrawsResult) -> None:
    d, q = result.draws, result.draws.quality
    print_table(
        f"M̂ of {d.source} over {d.repeats} draws per ε (seeds {d.seed}–{d.seed + d.repeats - 1}; "
        f"σ = {q.sigma:g}, δ = {q.delta_ratio:g}ε)",
        (
            "ε",
            "right",
            "share right",
            "Hausdorff/(εL) median",
            "max",
            "max normal dev. (°) median",
            "max",
        ),
        [
            (
                f"{r.eps:.4g}",
                f"{r.correct}/{len(r.draws)}",
                f"{r.share_correct:.3g}",
                *_spread(r.hausdorff),
                *_spread(r.normal_deviation_max),
            )
            for r in d.rows
        ],
    )
    if len(d.rows) > 1:
        _print_marks(d.marks)
        print(_band_text(d.largest_all_correct_eps, d.smallest_none_correct_eps))
    else:
        print(f"share of draws with the right topology: {result.share_correct:.3g}")


def _band_text(all_right: float | None, none_right: float | None) -> str:
    """The transition band of a sweep over many draws, in words (measured)."""
    low = (
        "no swept ε had every draw right"
        if all_right is None
        else f"every draw right up to ε = {all_right:g} (the largest such ε)"
    )
    high = (
        "no swept ε had every draw wrong"
        if none_right is None
        else f"no draw right at ε = {none_right:g} (the smallest such ε)"
    )
    return f"transition band (measured): {low}; {high}"
