"""``vorobound reconstruct``: VoroCrust's surface M̂ built from the seeds and measured."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ..constants import PAPER_DELTA_RATIO, PAPER_SIGMA
from .options import (
    DeltaRatio,
    EngineChoice,
    EngineOpt,
    FigureFormat,
    FigureFormatOpt,
    Json,
    MeshLfsOpt,
    MeshOpt,
    Seed,
    Sigma,
    SizingOpt,
    SphereOpt,
    TorusOpt,
    parse_values,
    surface_args,
)
from .progress import progress_bar
from .render import emit, fmt, print_table


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
    sphere: SphereOpt = None,
    torus: TorusOpt = None,
    mesh: MeshOpt = None,
    lfs: MeshLfsOpt = None,
    sizing: SizingOpt = None,
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
    engine: EngineOpt = EngineChoice.auto,
    out: Annotated[
        Path | None,
        typer.Option(
            "--out",
            metavar="DIR",
            help="Folder for mhat.vtu (ParaView; facet fields), mhat.ply, seeds.vtu, seeds.csv, "
            "summary.json and quality.<figure format>; a sweep writes sweep.csv, summary.json "
            "and sweep.<figure format>. Written as one set.",
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
    facets' quality. Exit code 0 when M̂ is a closed manifold with the surface's topology, 1
    when it is measured to be wrong, 2 for bad input. Python: vorobound.reconstruct(...).
    """
    from ..api.reconstruct import reconstruct as run

    with progress_bar(not as_json) as progress:
        result = run(
            eps=None if eps is None else parse_values(eps, "--eps"),
            **surface_args(sphere, torus, mesh, lfs, sizing),
            balls=balls,
            seeds=seeds,
            vorocrust=vorocrust,
            half_covered=half_covered,
            compare_sheets=compare_sheets,
            sigma=sigma,
            delta_ratio=delta_ratio,
            seed=seed,
            engine=engine.value,
            out=out,
            figure_format=figure_format.value,
            progress=progress,
        )
    return emit(result, as_json, _show)


def _show(result) -> None:
    data = result.to_dict()
    if hasattr(result, "sweep"):
        _print_sweep(data)
    else:
        _print_summary(data)
    for path in result.written:
        print(f"wrote {path}")


def _topology_text(s: dict) -> str:
    expected = s["expected_euler_characteristic"]
    if expected is None:
        return "no surface to compare with"
    return f"surface: χ = {expected}, {s['expected_components']} component(s)"


def _print_summary(s: dict) -> None:
    eps = s["params"].get("eps")
    eps = "" if eps is None else f" at ε = {eps:g}"
    rows = []
    if s["n_samples"] is not None:
        rows += [
            ("balls", f"{s['n_samples']:,}", ""),
            ("guide triangles", f"{s['n_guide_triangles']:,}", f"engine {s['engine']}"),
            ("half-covered", f"{s['n_half_covered']:,}", "triples with one seed covered"),
        ]
    seeds_note = f"{s['n_inside_seeds']:,} inside; labels from the {s['labels']}"
    if s["sheet_label_disagreements"] is not None:
        seeds_note += f" ({s['sheet_label_disagreements']} differ by the union's sheets)"
    rows += [
        ("seeds", f"{s['n_seeds']:,}", seeds_note),
        (
            "facets of M̂",
            f"{s['n_facets']:,}",
            f"{s['collapsed_facets']:,} in/out pairs with no area",
        ),
        (
            "closed 2-manifold",
            "yes" if s["closed_manifold"] else "no",
            f"{s['boundary_edges']} boundary and {s['nonmanifold_edges']} non-manifold edges, "
            f"{s['nonmanifold_vertices']} pinched vertices, {s['unbounded_facets']} facets at "
            "infinity",
        ),
        ("Euler characteristic", str(s["euler_characteristic"]), _topology_text(s)),
        ("components", str(s["components"]), f"genus {fmt(s['genus'])}"),
        ("topology", "right" if s["topology_correct"] else "WRONG", ""),
        (
            "min edge ratio",
            fmt(s["edge_ratio_min"], 4),
            f"median {fmt(s['edge_ratio_median'], 4)} (shortest / longest edge)",
        ),
        (
            "min angle (°)",
            fmt(s["min_angle_min_deg"], 4),
            f"median {fmt(s['min_angle_median_deg'], 4)}",
        ),
    ]
    if "hausdorff_over_eps_lfs" in s:
        rows += [
            (
                "Hausdorff / (εL)",
                fmt(s["hausdorff_over_eps_lfs"], 4),
                f"M̂ → surface {fmt(s['mhat_to_surface_over_eps_lfs'], 4)}, surface → M̂ "
                f"{fmt(s['surface_to_mhat_over_eps_lfs'], 4)} (measured)",
            ),
            (
                "max normal deviation (°)",
                fmt(s["normal_deviation_max_deg"], 4),
                f"median {fmt(s['normal_deviation_median_deg'], 4)}; "
                f"{s['flipped_facets']} facets above 90°",
            ),
        ]
    print_table(f"M̂ of {s['source']}{eps}", ("quantity", "value", "meaning"), rows)
    if s.get("note"):
        print(s["note"])


def _print_sweep(s: dict) -> None:
    print_table(
        f"M̂ of {s['source']} against ε (σ = {s['params']['sigma']:g}, "
        f"δ = {s['params']['delta_ratio']:g}ε)",
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
                f"{r['eps']:.4g}",
                "" if r["samples"] is None else f"{r['samples']:,}",
                f"{r['facets']:,}",
                ("right" if r["topology_correct"] else "WRONG")
                + ("" if r["closed_manifold"] else " (not closed)"),
                str(r["euler_characteristic"]),
                fmt(r["hausdorff"], 4),
                fmt(r["normal_deviation_max"], 4),
                fmt(r["min_angle_min"], 4),
            )
            for r in s["rows"]
        ],
    )
    print_table(
        "Every bound's ε*",
        ("bound", "target", "ε*", "claim"),
        [(m["label"], m["target"], f"{m['eps_star']:.5g}", m["claim"]) for m in s["eps_star"]],
    )
    for r in s["rows"]:
        if r["note"]:
            print(f"ε = {r['eps']:g}: {r['note']}")
