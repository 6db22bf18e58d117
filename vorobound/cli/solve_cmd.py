"""``vorobound solve``: the largest admissible ε of one mode, for one target."""

from __future__ import annotations

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
    TargetChoice,
    TargetOpt,
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
    mode: ModeOpt = ModeChoice.tight,
    target: TargetOpt = TargetChoice.ratio,
    lipschitz: Lipschitz = None,
    method: TightMethodOpt = MethodChoice.auto,
    as_json: Json = False,
) -> None:
    """The largest ε at which a bound meets a quality target, and how strong that is.

    By default the tight bound (proven) for the ratio target R ≤ ρ_f·R̂ of eq. (54). The paper
    reports ε ≤ 0.0047 for the additive target with its printed chain (--mode paper
    --target additive, invalid: docs/errata.md). Every answer rests on property H3, an
    assumption from the VoroCrust literature; the output also says up to which ε H3 alone
    gives R ≤ ρ_f·δ·L_i (eq. (55)).
    """
    from ..bounds.guarantee import eps_star
    from ..bounds.targets import H3_STATUS, STATEMENT, Target, h3_route

    quality = quality_params(sigma, delta_ratio, rho_f, lfs)
    with progress_bar(not as_json and mode is ModeChoice.tight) as progress:
        result = eps_star(quality, mode.value, target.value, lipschitz, method.value, progress)
    h3 = h3_route(quality)
    payload = {
        "mode": result.mode,
        "target": result.target,
        "target_statement": STATEMENT[Target(result.target)],
        "method": result.method,
        "claim": result.claim,
        "eps_star": result.eps_star,
        "proven_lower_bound": result.proven_lower_bound,
        "params": params_dict(quality, result.eps_star),
        "lipschitz": lipschitz,
        "residual": result.residual,
        "iterations": result.iterations,
        "bracket": list(result.bracket),
        "premise": H3_STATUS,
        "h3_route": {
            "eps_star": h3.eps_star,
            "claim": h3.claim,
            "statement": "H3 alone gives R <= rho_f*delta*L_i (eq. (55)) for every eps up to "
            "eps_star",
        },
    }
    if result.target == "additive":
        payload["target_at_eps_star"] = result.params.target
    if result.maximizer is not None:
        payload["maximizer"] = result.maximizer
    if as_json:
        print_json(payload)
        return
    rows = [
        ("eps_star", fmt(result.eps_star, 12)),
        ("claim", result.claim),
        ("method", result.method),
    ]
    if result.proven_lower_bound is not None:
        rows.append(("proven lower bound on ε* (closed form)", fmt(result.proven_lower_bound, 12)))
    rows += [
        ("eps_star / (1/500)", fmt(result.eps_star * 500, 6)),
        ("ball radius δ·L_i at eps_star", fmt(result.params.delta * lfs)),
        ("relative residual", fmt(result.residual, 3)),
        ("root-finder iterations", str(result.iterations)),
        ("bracket", f"[{fmt(result.bracket[0])}, {fmt(result.bracket[1])}]"),
        ("H3 alone gives (55) up to ε", f"{fmt(h3.eps_star, 6)} (given H3)"),
    ]
    lam = "" if lipschitz is None else f", λ = {lipschitz:g}"
    print_table(
        f"ε* for mode {result.mode}, target {result.target} (ρ_f = {rho_f:g}, σ = {sigma:g}, "
        f"δ/ε = {delta_ratio:g}{lam})",
        ("quantity", "value"),
        rows,
    )
    print(f"target: {STATEMENT[Target(result.target)]}")
    print(f"premise: {H3_STATUS}")
