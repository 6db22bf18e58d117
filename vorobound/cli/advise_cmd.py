"""``vorobound advise``: sampling parameters and expected sample counts for a surface."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ..bounds.params import LFS_RANGE
from ..errors import VoroboundError
from .options import (
    DeltaRatio,
    Json,
    Lipschitz,
    RhoF,
    Sigma,
    TargetsOpt,
    params_dict,
    parse_modes,
    parse_numbers,
    parse_targets,
    quality_params,
)
from .progress import progress_bar
from .render import fmt, print_json, print_table

AREA_RANGE = (LFS_RANGE[0] ** 2, LFS_RANGE[1] ** 2)
"""Supported areas: squares of the supported lengths."""


def _length(value: float, flag: str, bounds: tuple[float, float] = LFS_RANGE) -> float:
    """A surface dimension in the supported range (so areas and 1/L² stay finite)."""
    from ..checks import checked_number

    return checked_number(value, flag, *bounds)


def _surface(area, lfs, sphere, torus, mesh, sizing, progress):
    """The surface and where its L comes from ("exact", "given", "sizing file", "estimated")."""
    from ..sampling.surfaces import analytic as surfaces

    given = [x is not None for x in (area, sphere, torus, mesh)]
    if sum(given) > 1:
        raise VoroboundError("give one surface: --area with --lfs, --sphere, --torus or --mesh")
    if sizing is not None and mesh is None:
        raise VoroboundError("--sizing goes with --mesh")
    if area is not None:
        if lfs is None:
            raise VoroboundError("--area needs --lfs (the local feature size)")
        area_surface = surfaces.planar_area(
            _length(area, "--area", AREA_RANGE), _length(lfs, "--lfs")
        )
        return area_surface, "given (--lfs)"
    if sphere is not None:
        return surfaces.sphere(_length(sphere, "--sphere")), "exact"
    if torus is not None:
        major, minor = (_length(x, "--torus") for x in parse_numbers(torus, "--torus", 2))
        return surfaces.torus(major, minor), "exact"
    if mesh is not None and lfs is None and sizing is None:
        return _estimated_surface(mesh, progress)
    if mesh is not None:
        given = None if lfs is None else _length(lfs, "--lfs")
        source = "given (--lfs)" if sizing is None else f"sizing file {sizing.name}"
        return surfaces.mesh_surface(mesh, given, sizing), source
    if lfs is not None:
        raise VoroboundError("--lfs describes a surface: use it with --area or --mesh")
    return None, None


def _estimated_surface(mesh: Path, progress):
    """A mesh whose L nobody gave: estimate it (vorobound lfs; its warnings, e.g. about sharp
    edges, reach stderr as warning lines), and say so in the output."""
    from ..sampling.io.meshes import read_triangle_mesh
    from ..sampling.lfs.estimate import estimate_lfs

    estimate = estimate_lfs(read_triangle_mesh(mesh), progress=progress)
    return estimate.surface(), (
        f"estimated from the mesh ({estimate.method}); numerical, the L that `vorobound lfs` "
        "reports and `vorobound sample --mesh` uses (accuracy on the test meshes: docs/lfs.md)"
    )


def advise(
    rho_f: RhoF = 1.38,
    sigma: Sigma = 0.75,
    delta_ratio: DeltaRatio = 2.0,
    lipschitz: Lipschitz = None,
    mode: Annotated[
        str, typer.Option("--mode", help="Comma list of modes: paper, rigorous, tight.")
    ] = "rigorous,tight",
    target: TargetsOpt = "additive,ratio",
    area: Annotated[float | None, typer.Option("--area", help="Surface area (with --lfs).")] = None,
    lfs: Annotated[
        float | None, typer.Option("--lfs", help="Constant local feature size L.")
    ] = None,
    sphere: Annotated[float | None, typer.Option("--sphere", help="Sphere of radius R.")] = None,
    torus: Annotated[
        str | None, typer.Option("--torus", metavar="R,r", help="Ring torus, radii R > r.")
    ] = None,
    mesh: Annotated[
        Path | None,
        typer.Option(
            "--mesh",
            help="Triangle mesh file (any format meshio reads). Without --lfs or --sizing its "
            "local feature size is estimated (as by `vorobound lfs`), and the output says so.",
        ),
    ] = None,
    sizing: Annotated[
        Path | None, typer.Option("--sizing", help="CSV with the local feature size per vertex.")
    ] = None,
    as_json: Json = False,
) -> None:
    """Largest ε per mode and target, ball radius δ·L, spacing σ·ε·L and sample counts for a
    surface, and the ε to use.

    The recommendation is the most conservative proven or certified ε* among the targets asked
    for (default: both), and says which target binds. Sample counts are a covering lower and a
    packing upper estimate (exact bounds on a sphere; docs/advisor.md). Each row says how strong
    its ε* is: proven, certified, numerical or invalid.
    """
    from ..reports.advisor import GUARANTEE
    from ..reports.advisor import advise as run_advice

    modes = parse_modes(mode)
    targets = parse_targets(target)
    quality = quality_params(sigma, delta_ratio, rho_f)
    from ..sampling.surfaces.analytic import planar_area

    with progress_bar(not as_json) as progress:
        surface, lfs_source = _surface(area, lfs, sphere, torus, mesh, sizing, progress)
        # Without a surface, lengths are reported per unit L (counts are dropped below).
        basis = surface or planar_area(1.0, 1.0)
        advice = run_advice(quality, basis, modes, lipschitz, progress=progress, targets=targets)
    entries = []
    for a in advice.rows:
        entry = {
            "mode": a.mode,
            "target": a.target,
            "eps_star": a.eps_star,
            "claim": a.claim,
            "method": a.method,
            "proven_lower_bound": a.proven_lower_bound,
            "ball_radius": a.ball_radius,
            "min_spacing": a.min_spacing,
            "samples_low": a.samples_low,
            "samples_high": a.samples_high,
            "reduction_vs_1_500": a.reduction_vs_1_500,
            "constraint_set": a.constraint_set,
            "note": a.note,
        }
        if surface is None:
            entry.update(samples_low=None, samples_high=None)
        entries.append(entry)
    rec = advice.recommendation
    recommendation = None
    if rec is not None:
        recommendation = {
            "eps": rec.eps,
            "binding_target": rec.binding_target,
            "mode": rec.mode,
            "claim": rec.claim,
            "eps_per_target": rec.per_target,
            "ball_radius": rec.ball_radius,
            "min_spacing": rec.min_spacing,
            "samples_low": None if surface is None else rec.samples_low,
            "samples_high": None if surface is None else rec.samples_high,
            "reduction_vs_1_500": rec.reduction_vs_1_500,
            "feature_samples_low": None if rec.feature_samples is None else rec.feature_samples[0],
            "feature_samples_high": None if rec.feature_samples is None else rec.feature_samples[1],
            "lattice_candidates": rec.lattice_candidates,
            "samplable": rec.samplable,
        }
    h3 = advice.h3_route
    h3_entry = {
        "eps_star": h3.eps_star,
        "claim": h3.claim,
        "premise": h3.premise,
        "statement": "H3 alone gives R <= rho_f*delta*L_i (eq. (55)); not eq. (54)",
    }
    surface_info = (
        None
        if surface is None
        else {
            "name": surface.name,
            "area": surface.area,
            "lfs_min": surface.lfs_min,
            "inv_lfs_sq_integral": surface.inv_lfs_sq_integral,
            "counts_exact": surface.exact,
            "lfs_source": lfs_source,
            "feature_inv_lfs": surface.feature_inv_lfs,
        }
    )
    if as_json:
        print_json(
            {
                "params": params_dict(quality, include_lfs=False),
                "lipschitz": lipschitz,
                "surface": surface_info,
                "recommendation": recommendation,
                "modes": entries,
                "h3_route": h3_entry,
                "guarantee": GUARANTEE,
            }
        )
        return
    title = "Sampling advice" + (f" for {surface.name}" if surface else " (lengths per unit L)")
    table = [
        (
            e["mode"],
            e["target"],
            fmt(e["eps_star"], 5),
            e["claim"],
            fmt(e["ball_radius"], 5),
            fmt(e["min_spacing"], 5),
            "—"
            if e["samples_low"] is None
            else f"{e['samples_low']:,.0f} – {e['samples_high']:,.0f}",
            _versus_baseline(e["reduction_vs_1_500"]),
        )
        for e in entries
    ]
    table.append(("H3 alone", "(55) only", fmt(h3.eps_star, 5), "given H3", "", "", "", "—"))
    print_table(
        title,
        (
            "mode",
            "target",
            "ε*",
            "claim",
            "ball radius δL",
            "spacing σεL",
            "samples (low–high)",
            "vs 1/500",
        ),
        table,
    )
    for e in entries:
        if e["note"]:
            print(f"no ε* for {e['mode']}, target {e['target']}: {e['note']}")
    if rec is None:
        print("recommended ε: none (no target asked for has a proven or certified ε*)")
    else:
        counts = (
            "" if surface is None else f", {rec.samples_low:,.0f} – {rec.samples_high:,.0f} samples"
        )
        print(
            f"recommended ε = {fmt(rec.eps, 5)} ({rec.claim}; {rec.mode}, binding target "
            f"{rec.binding_target}): ball radius {fmt(rec.ball_radius, 5)}{counts}, "
            f"{_versus_baseline(rec.reduction_vs_1_500)} samples than ε = 1/500"
        )
    if rec is not None and surface is not None:
        for line in _sampler_lines(rec):
            print(line)
    if surface is not None:
        print(f"local feature size L: {lfs_source}")
    print(GUARANTEE)


def _sampler_lines(rec) -> list[str]:
    """What the counts include, and whether `vorobound sample` can make this sample."""
    lines = []
    if rec.feature_samples is not None:
        low, high = rec.feature_samples
        lines.append(
            f"  of these, {low:,.0f} – {high:,.0f} on the sharp features (sampled first, as "
            "VoroCrust protects them)"
        )
    if rec.lattice_candidates is not None:
        from ..sampling.sampler.lattice import MAX_CANDIDATES

        if rec.samplable:
            lines.append(
                f"  `vorobound sample --mesh` at this ε builds about "
                f"{rec.lattice_candidates:.3g} lattice candidates (at most {MAX_CANDIDATES:.0e})"
            )
        else:
            lines.append(
                f"  `vorobound sample --mesh` cannot make this sample: it needs about "
                f"{rec.lattice_candidates:.3g} lattice candidates, more than the "
                f"{MAX_CANDIDATES:.0e} it builds (any smaller ε needs more); the counts stand "
                "for any VoroCrust sampler"
            )
    return lines


def _versus_baseline(reduction: float | None) -> str:
    """Sample count at ε = 1/500 over the count at ε*, in words ("—" when not trusted)."""
    if reduction is None:
        return "—"
    if reduction >= 1:
        return f"{reduction:.2f}× fewer"
    return f"{1 / reduction:.2f}× more"
