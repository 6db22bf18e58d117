"""``vorobound solve``: the largest admissible ε of one mode."""

from __future__ import annotations

from ..errors import VoroboundError
from .options import (
    DeltaRatio,
    Json,
    Lfs,
    Lipschitz,
    MethodChoice,
    ModeChoice,
    ModeOpt,
    RhoF,
    Sigma,
    TightMethodOpt,
    params_dict,
    quality_params,
)
from .progress import progress_bar
from .render import fmt, print_json, print_table


def solve(
    sigma: Sigma = 0.75,
    delta_ratio: DeltaRatio = 2.0,
    lfs: Lfs = 1.0,
    rho_f: RhoF = 1.38,
    mode: ModeOpt = ModeChoice.paper,
    lipschitz: Lipschitz = None,
    method: TightMethodOpt = MethodChoice.auto,
    as_json: Json = False,
) -> None:
    """The largest ε whose bound on R − R̂ stays within (ρ_f − 1)·δ·L_i.

    The paper reports ε ≤ 0.0047 (against 1/500 in the original VoroCrust analysis). The
    output says how strong the answer is: proven, numerical or invalid.
    """
    quality = quality_params(sigma, delta_ratio, rho_f, lfs)
    if mode is not ModeChoice.tight and lipschitz is not None:
        raise VoroboundError("--lipschitz applies to --mode tight only")
    if mode is ModeChoice.tight:
        from ..bounds.tight.method import tight_eps_star

        with progress_bar(not as_json) as progress:
            result = tight_eps_star(quality, lipschitz, method.value, progress)
    else:
        from ..bounds.eps_star import solve_eps_star

        result = solve_eps_star(quality, mode.value)
    payload = {
        "mode": result.mode,
        "method": result.method,
        "claim": result.claim,
        "eps_star": result.eps_star,
        "params": params_dict(quality, result.eps_star),
        "residual": result.residual,
        "iterations": result.iterations,
        "bracket": list(result.bracket),
        "target_at_eps_star": result.params.target,
    }
    if result.maximizer is not None:
        payload["lipschitz"] = lipschitz
        payload["maximizer"] = result.maximizer
    if as_json:
        print_json(payload)
        return
    rows = [
        ("eps_star", fmt(result.eps_star, 12)),
        ("eps_star / (1/500)", fmt(result.eps_star * 500, 6)),
        ("ball radius δ·L_i at eps_star", fmt(result.params.delta * lfs)),
        ("method", result.method),
        ("claim", result.claim),
        ("relative residual", fmt(result.residual, 3)),
        ("root-finder iterations", str(result.iterations)),
        ("bracket", f"[{fmt(result.bracket[0])}, {fmt(result.bracket[1])}]"),
    ]
    print_table(
        f"ε* for mode {result.mode} (ρ_f = {rho_f:g}, σ = {sigma:g}, δ/ε = {delta_ratio:g})",
        ("quantity", "value"),
        rows,
    )
