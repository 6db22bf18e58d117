"""``vorobound advise``: sampling parameters and expected sample counts for a surface."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ..errors import VoroboundError
from .common import DeltaRatio, Json, Lipschitz, RhoF, Sigma, make_params, params_dict
from .output import fmt, parse_numbers, print_json, print_table


def _surface(area, lfs, sphere, torus, mesh, sizing):
    from ..sampling import surfaces

    given = [x is not None for x in (area, sphere, torus, mesh)]
    if sum(given) > 1:
        raise VoroboundError("give one surface: --area with --lfs, --sphere, --torus or --mesh")
    if sizing is not None and mesh is None:
        raise VoroboundError("--sizing goes with --mesh")
    if area is not None:
        if lfs is None:
            raise VoroboundError("--area needs --lfs (the local feature size)")
        return surfaces.planar_area(area, lfs)
    if sphere is not None:
        return surfaces.sphere(sphere)
    if torus is not None:
        major, minor = parse_numbers(torus, "--torus", 2)
        return surfaces.torus(major, minor)
    if mesh is not None:
        return surfaces.mesh_surface(mesh, lfs, sizing)
    if lfs is not None:
        raise VoroboundError("--lfs describes a surface: use it with --area or --mesh")
    return None


def advise(
    rho_f: RhoF = 1.38,
    sigma: Sigma = 0.75,
    delta_ratio: DeltaRatio = 2.0,
    lipschitz: Lipschitz = None,
    mode: Annotated[
        str, typer.Option("--mode", help="Comma list of modes: paper, rigorous, tight.")
    ] = "paper,rigorous,tight",
    area: Annotated[float | None, typer.Option("--area", help="Surface area (with --lfs).")] = None,
    lfs: Annotated[
        float | None, typer.Option("--lfs", help="Constant local feature size L.")
    ] = None,
    sphere: Annotated[float | None, typer.Option("--sphere", help="Sphere of radius R.")] = None,
    torus: Annotated[
        str | None, typer.Option("--torus", metavar="R,r", help="Ring torus, radii R > r.")
    ] = None,
    mesh: Annotated[
        Path | None, typer.Option("--mesh", help="Triangle mesh file (any format meshio reads).")
    ] = None,
    sizing: Annotated[
        Path | None, typer.Option("--sizing", help="CSV with the local feature size per vertex.")
    ] = None,
    as_json: Json = False,
) -> None:
    """Largest ε per mode, ball radius δ·L, spacing σ·ε·L and sample counts for a surface.

    Sample counts are a covering lower and a packing upper estimate (exact bounds on a
    sphere; docs/advisor.md), and the reduction against ε = 1/500 by the same formula.
    """
    from ..bounds.params import Mode
    from ..reports.advisor import GUARANTEE
    from ..reports.advisor import advise as run_advice

    try:
        modes = [Mode(m.strip()).value for m in mode.split(",")]
    except ValueError:
        raise VoroboundError(f"--mode: expected paper, rigorous or tight, got {mode!r}") from None
    if lipschitz is not None and lipschitz < 0:
        raise VoroboundError(f"--lipschitz must be non-negative, got {lipschitz}")
    surface = _surface(area, lfs, sphere, torus, mesh, sizing)
    params = make_params(0.5, sigma, delta_ratio, 1.0, rho_f)
    from ..sampling.surfaces import planar_area

    # Without a surface, lengths are reported per unit L (counts are dropped below).
    basis = surface or planar_area(1.0, 1.0)
    advice = run_advice(params, basis, modes, lipschitz, progress=not as_json)
    entries = []
    for a in advice:
        entry = {
            "mode": a.mode,
            "eps_star": a.eps_star,
            "ball_radius": a.ball_radius,
            "min_spacing": a.min_spacing,
            "samples_low": a.samples_low,
            "samples_high": a.samples_high,
            "reduction_vs_1_500": a.reduction_vs_1_500,
            "constraint_set": a.constraint_set,
        }
        if surface is None:
            entry.update(samples_low=None, samples_high=None)
        entries.append(entry)
    surface_info = (
        None
        if surface is None
        else {
            "name": surface.name,
            "area": surface.area,
            "lfs_min": surface.lfs_min,
            "inv_lfs_sq_integral": surface.inv_lfs_sq_integral,
            "counts_exact": surface.exact,
        }
    )
    if as_json:
        print_json(
            {
                "params": params_dict(params) | {"eps": None},
                "lipschitz": lipschitz,
                "surface": surface_info,
                "modes": entries,
                "guarantee": GUARANTEE,
            }
        )
        return
    title = "Sampling advice" + (f" for {surface.name}" if surface else " (lengths per unit L)")
    print_table(
        title,
        ("mode", "ε*", "ball radius δL", "spacing σεL", "samples (low–high)", "vs ε=1/500"),
        [
            (
                e["mode"],
                fmt(e["eps_star"], 5),
                fmt(e["ball_radius"], 5),
                fmt(e["min_spacing"], 5),
                "—"
                if e["samples_low"] is None
                else f"{e['samples_low']:,.0f} – {e['samples_high']:,.0f}",
                f"{e['reduction_vs_1_500']:.2f}× fewer",
            )
            for e in entries
        ],
    )
    print(GUARANTEE)
