"""``vorobound reconstruct``: VoroCrust's surface M̂ built from the seeds and measured."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ..errors import InputError
from .check_cmd import EngineChoice
from .options import DeltaRatio, Json, Seed, Sigma, parse_values
from .progress import progress_bar
from .render import fmt, print_json, print_table
from .sample_cmd import MeshLfsOpt, MeshOpt, SizingOpt, SphereOpt, TorusOpt, surface_shape

EXIT_WRONG = 1
"""M̂ was built and measured to be wrong: not a closed manifold, or not the surface's
topology (for a sweep: at some ε)."""


def reconstruct(
    eps: Annotated[
        str | None,
        typer.Option(
            "--eps",
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
            help="Balls instead of a sample (as for check --balls). Seeds are labelled by the "
            "surface option if given, else by the two sheets of the union's boundary.",
        ),
    ] = None,
    seeds: Annotated[
        Path | None,
        typer.Option(
            "--seeds",
            help="Labelled seeds: VoroCrust's CSV (x, y, z, sizing, region id with 0 outside, "
            "1 inside; a header naming x, y, z and region_id or region is optional).",
        ),
    ] = None,
    half_covered: Annotated[
        bool,
        typer.Option(
            "--half-covered",
            help="Also seed the uncovered seed of each half-covered triple (every vertex of "
            "the union's boundary is then a seed).",
        ),
    ] = False,
    compare_sheets: Annotated[
        bool,
        typer.Option(
            "--compare-sheets",
            help="Also label the seeds by the union's sheets and count where they differ from "
            "the surface's labels.",
        ),
    ] = False,
    sigma: Sigma = 0.75,
    delta_ratio: DeltaRatio = 2.0,
    seed: Seed = 0,
    engine: Annotated[
        EngineChoice,
        typer.Option(
            "--engine", help="Candidate triples, as for check (auto, gudhi, hull, brute)."
        ),
    ] = EngineChoice.auto,
    out: Annotated[
        Path | None,
        typer.Option(
            "--out",
            help="Folder for mhat.vtu (ParaView; facet fields), mhat.ply, seeds.vtu, seeds.csv, "
            "summary.json and quality.<format>; a sweep writes sweep.csv, summary.json and "
            "sweep.<format>.",
        ),
    ] = None,
    fmt_: Annotated[
        str, typer.Option("--format", help="Figure format for --out: png, pdf or svg.")
    ] = "png",
    as_json: Json = False,
) -> None:
    """Build VoroCrust's surface M̂ (the Voronoi facets between inside and outside seeds) and
    measure it.

    Seeds are both seeds of every guide triangle of a sample (--sphere, --torus, --mesh with
    --eps), of --balls, or read from --seeds. Reported: whether M̂ is a closed 2-manifold, its
    components, Euler characteristic and genus against the surface's, the two-sided Hausdorff
    distance to the surface over ε·L, the facet normals' deviation from the surface's, and the
    facets' quality. Exit code 0 when M̂ is a closed manifold with the surface's topology, 1
    when it is measured to be wrong, 2 for bad input.
    """
    from ..bounds.params import SamplingParams
    from ..checks import checked_seed
    from ..files import checked_folder
    from .options import quality_params

    if fmt_ not in ("png", "pdf", "svg"):
        raise InputError(f"--format: expected png, pdf or svg, got {fmt_!r}")
    if balls is not None and seeds is not None:
        raise InputError("give --balls or --seeds, not both")
    seed = checked_seed(seed)
    if out is not None:
        checked_folder(out)
    quality = quality_params(sigma, delta_ratio, 1.38)
    values = None if eps is None else parse_values(eps, "--eps")
    sampled = balls is None and seeds is None
    if sampled and values is None:
        raise InputError("give --eps (a sample of the surface needs it)")
    if values is not None and len(values) > 1 and not sampled:
        raise InputError(
            "an ε sweep samples a surface: --eps start:stop:num goes without --balls/--seeds"
        )
    with progress_bar(not as_json) as progress:
        shape = surface_shape(sphere, torus, mesh, lfs, sizing, sampled, progress)
        if shape is not None and not sampled and values is None:
            raise InputError("give --eps to measure against the surface (distances over ε·L)")
        params = None if values is None else SamplingParams(values[0], quality)
        if values is not None and len(values) > 1:
            return _sweep(
                shape,
                values,
                quality,
                seed,
                half_covered,
                engine,
                compare_sheets,
                out,
                fmt_,
                as_json,
                progress,
            )
        report = _one(
            shape,
            params,
            quality,
            seed,
            balls,
            seeds,
            half_covered,
            engine,
            compare_sheets,
            progress,
        )
        written = _write_outputs(report, out, fmt_) if out is not None else []
    summary = report.summary()
    if as_json:
        print_json(summary | {"written": [str(p) for p in written]})
    else:
        _print_summary(summary)
        for path in written:
            print(f"wrote {path}")
    if not report.topology_correct:
        raise typer.Exit(EXIT_WRONG)


def _one(shape, params, quality, seed, balls, seeds, half_covered, engine, compare, progress):
    """The report of one reconstruction, from a sample, balls or seeds."""
    from ..reports import reconstruct as workflow

    if seeds is not None:
        from ..sampling.reconstruct.seeds import read_seed_file

        if half_covered or compare:
            raise InputError("--half-covered and --compare-sheets need balls, not --seeds")
        return workflow.reconstruct_seeds(read_seed_file(seeds), shape, params, seed, progress)
    if balls is not None:
        from ..sampling.io.balls import read_balls

        return workflow.reconstruct_balls(
            read_balls(balls),
            params,
            shape,
            half_covered,
            engine.value,
            balls.name,
            compare,
            progress,
        )
    return workflow.reconstruct_surface(
        shape, params.eps, quality, seed, half_covered, engine.value, compare, progress
    )


def _sweep(
    shape, values, quality, seed, half_covered, engine, compare, out, fmt_, as_json, progress
):
    from ..reports.reconstruct_sweep import reconstruct_sweep

    sweep = reconstruct_sweep(
        shape, values, quality, seed, half_covered, engine.value, compare, progress
    )
    written = _write_sweep(sweep, out, fmt_) if out is not None else []
    summary = sweep.summary()
    if as_json:
        print_json(summary | {"written": [str(p) for p in written]})
    else:
        _print_sweep(summary)
        for path in written:
            print(f"wrote {path}")
    if not summary["all_correct"]:
        raise typer.Exit(EXIT_WRONG)


def _write_outputs(report, out, fmt_: str) -> list:
    from ..files import ensure_folder, write_set
    from ..plotting import figure_writer, plot_reconstruct_quality
    from ..reports.reconstruct_files import (
        QUALITY_FIGURE_STEM,
        output_writers,
        quality_distributions,
    )

    folder = ensure_folder(out)
    writers = output_writers(report, folder)
    figure = plot_reconstruct_quality(quality_distributions(report), f"M̂ of {report.source}")
    writers[folder / f"{QUALITY_FIGURE_STEM}.{fmt_}"] = figure_writer(figure, fmt_)
    return write_set(writers)


def _write_sweep(sweep, out, fmt_: str) -> list:
    from ..files import ensure_folder, write_set
    from ..plotting import figure_writer, plot_reconstruct_sweep
    from ..reports.reconstruct_sweep import SWEEP_FIGURE_STEM, sweep_writers

    folder = ensure_folder(out)
    writers = sweep_writers(sweep, folder)
    rows = sweep.rows
    panels = {
        "Hausdorff / (εL)": [r.hausdorff for r in rows],
        "max normal dev. (°)": [r.normal_deviation_max for r in rows],
        "min angle (°)": [r.min_angle_min for r in rows],
    }
    marks = [(m.label, m.target, m.eps_star) for m in sweep.marks]
    figure = plot_reconstruct_sweep(
        [r.eps for r in rows],
        panels,
        [r.topology_correct for r in rows],
        marks,
        f"M̂ of {sweep.source}",
    )
    writers[folder / f"{SWEEP_FIGURE_STEM}.{fmt_}"] = figure_writer(figure, fmt_)
    return write_set(writers)


def _topology_text(s: dict) -> str:
    expected = s["expected_euler_characteristic"]
    if expected is None:
        return "no surface to compare with"
    return f"surface: χ = {expected}, {s['expected_components']} component(s)"


def _print_summary(s: dict) -> None:
    eps = "" if s["eps"] is None else f" at ε = {s['eps']:g}"
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
