"""``vorobound bounds`` and ``vorobound solve``: the chain (33)–(53) and the ε* root finder."""

from __future__ import annotations

from ..errors import VoroboundError
from .common import (
    DeltaRatio,
    Eps,
    Json,
    Lfs,
    Lipschitz,
    ModeChoice,
    ModeOpt,
    RhoF,
    Sigma,
    make_params,
    params_dict,
)
from .output import fmt, print_json, print_table


def bounds(
    eps: Eps,
    sigma: Sigma = 0.75,
    delta_ratio: DeltaRatio = 2.0,
    lfs: Lfs = 1.0,
    rho_f: RhoF = 1.38,
    mode: ModeOpt = ModeChoice.paper,
    lipschitz: Lipschitz = None,
    as_json: Json = False,
) -> None:
    """Every quantity of the chain (33)–(53) at one ε, and whether the bound meets the target.

    The target is (ρ_f − 1)·δ·L_i: with R̂ ≤ δ L_i it gives R ≤ ρ_f δ L_i (eq. (54)–(55)).
    """
    params = make_params(eps, sigma, delta_ratio, lfs, rho_f)
    if mode is ModeChoice.tight:
        return _tight_bounds(params, lipschitz, as_json)
    if lipschitz is not None:
        raise VoroboundError("--lipschitz applies to --mode tight only")
    from ..bounds.chain import chain_bounds

    chain = chain_bounds(params, mode.value)
    quantities = {
        name: {"equation": eq, "description": text, "value": float(value)}
        for name, eq, text, value in chain.rows()
    }
    bound, target = float(chain.bound), float(chain.target)
    if as_json:
        print_json(
            {
                "mode": mode.value,
                "params": params_dict(params),
                "quantities": quantities,
                "bound": bound,
                "target": target,
                "meets_target": bound <= target,
            }
        )
        return
    rows = [
        (name, q["equation"], fmt(q["value"]), q["description"]) for name, q in quantities.items()
    ]
    print_table(
        f"Chain (33)–(53), mode {mode.value}, ε = {eps:g}",
        ("quantity", "eq.", "value", "meaning"),
        rows,
    )
    verdict = "meets" if bound <= target else "exceeds"
    print(f"bound on R − R̂ = {fmt(bound)} {verdict} the target (ρ_f − 1)·δ·L_i = {fmt(target)}")


def _tight_bounds(params, lipschitz, as_json) -> None:
    from ..bounds.tight import tight_supremum

    result = tight_supremum(params, lipschitz=lipschitz)
    payload = {
        "mode": "tight",
        "params": params_dict(params),
        "lipschitz": lipschitz,
        "bound": result.supremum,
        "infimum": result.infimum,
        "target": params.target,
        "meets_target": result.supremum <= params.target,
        "maximizer": result.maximizer,
        "minimizer": result.minimizer,
        "evidence": result.evidence,
    }
    if as_json:
        print_json(payload)
        return
    rows = [
        ("sup R − R̂ (tight bound)", fmt(result.supremum)),
        ("inf R − R̂", fmt(result.infimum)),
        ("target (ρ_f − 1)·δ·L_i", fmt(params.target)),
    ]
    rows += [(f"maximizer {k}", fmt(v)) for k, v in result.maximizer.items()]
    print_table(f"Tight supremum, ε = {params.eps:g}, λ = {lipschitz}", ("quantity", "value"), rows)


def solve(
    sigma: Sigma = 0.75,
    delta_ratio: DeltaRatio = 2.0,
    lfs: Lfs = 1.0,
    rho_f: RhoF = 1.38,
    mode: ModeOpt = ModeChoice.paper,
    lipschitz: Lipschitz = None,
    as_json: Json = False,
) -> None:
    """The largest ε whose bound on R − R̂ stays within (ρ_f − 1)·δ·L_i (brentq on a scan).

    The paper reports ε ≤ 0.0047 (against 1/500 in the original VoroCrust analysis).
    """
    params = make_params(0.5, sigma, delta_ratio, lfs, rho_f)
    if mode is not ModeChoice.tight and lipschitz is not None:
        raise VoroboundError("--lipschitz applies to --mode tight only")
    if mode is ModeChoice.tight:
        from ..bounds.tight import solve_tight

        result = solve_tight(params, lipschitz=lipschitz, progress=not as_json)
    else:
        from ..bounds.eps_star import solve_eps_star

        result = solve_eps_star(params, mode.value)
    payload = {
        "mode": result.mode,
        "eps_star": result.eps_star,
        "params": params_dict(result.params),
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
        ("relative residual", fmt(result.residual, 3)),
        ("brentq iterations", str(result.iterations)),
        ("bracket", f"[{fmt(result.bracket[0])}, {fmt(result.bracket[1])}]"),
    ]
    print_table(
        f"ε* for mode {result.mode} (ρ_f = {rho_f:g}, σ = {sigma:g}, δ/ε = {delta_ratio:g})",
        ("quantity", "value"),
        rows,
    )
