"""``vorobound bounds``: every quantity of the chain (33)–(53), or the tight bound, at one ε."""

from __future__ import annotations

from ..errors import VoroboundError
from .options import (
    DeltaRatio,
    Eps,
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


def bounds(
    eps: Eps,
    sigma: Sigma = 0.75,
    delta_ratio: DeltaRatio = 2.0,
    lfs: Lfs = 1.0,
    rho_f: RhoF = 1.38,
    mode: ModeOpt = ModeChoice.paper,
    lipschitz: Lipschitz = None,
    method: TightMethodOpt = MethodChoice.auto,
    as_json: Json = False,
) -> None:
    """Every quantity of the chain (33)–(53) at one ε, and whether the bound meets the target.

    The target is (ρ_f − 1)·δ·L_i: with R̂ ≤ δ L_i it gives R ≤ ρ_f δ L_i (eq. (54)–(55)).
    """
    params = quality_params(sigma, delta_ratio, rho_f, lfs).at(eps)
    from ..bounds.constraints import is_empty

    if is_empty(params.eps, params.sigma):
        raise VoroboundError(
            f"no guide triangle is feasible at eps = {eps:g}, sigma = {sigma:g} "
            "(sigma*(1-eps) > sqrt(3)): every bound is vacuous there"
        )
    if mode is ModeChoice.tight:
        return _tight_bounds(params, lipschitz, method, as_json)
    if lipschitz is not None:
        raise VoroboundError("--lipschitz applies to --mode tight only")
    from ..bounds.chain import chain_bounds
    from ..bounds.claims import CHAIN_CLAIM

    chain = chain_bounds(params, mode.value)
    bound, target = float(chain.bound), float(chain.target)
    if bound != bound:  # NaN: the chain's own formulas are undefined here
        raise VoroboundError(
            f"the {mode.value} chain is not defined at eps = {eps:g}, sigma = {sigma:g} "
            "(a square root of a negative number in eq. (51)-(52): no feasible guide triangle "
            "or |k_cos| > 1)"
        )
    quantities = {
        name: {"equation": eq, "description": text, "value": float(value)}
        for name, eq, text, value in chain.rows()
    }
    if as_json:
        print_json(
            {
                "mode": mode.value,
                "claim": CHAIN_CLAIM[mode.value],
                "params": params_dict(params.quality, params.eps),
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
        f"Chain (33)–(53), mode {mode.value} ({CHAIN_CLAIM[mode.value]}), ε = {eps:g}",
        ("quantity", "eq.", "value", "meaning"),
        rows,
    )
    verdict = "meets" if bound <= target else "exceeds"
    print(f"bound on R − R̂ = {fmt(bound)} {verdict} the target (ρ_f − 1)·δ·L_i = {fmt(target)}")


def _tight_bounds(params, lipschitz, method, as_json) -> None:
    from ..bounds.tight.method import tight_bound

    with progress_bar(not as_json) as progress:
        progress("tight supremum", 0, None)
        result = tight_bound(params, lipschitz, method.value)
    payload = {
        "mode": "tight",
        "method": result.method,
        "claim": result.claim,
        "params": params_dict(params.quality, params.eps),
        "lipschitz": lipschitz,
        "bound": result.value,
        "target": params.target,
        "meets_target": result.value <= params.target,
        "maximizer": result.maximizer,
    }
    if result.optimizer is not None:
        payload["infimum"] = result.optimizer.infimum
        payload["minimizer"] = result.optimizer.minimizer
        payload["evidence"] = result.optimizer.evidence
        payload["infimum_evidence"] = result.optimizer.infimum_evidence
    if as_json:
        print_json(payload)
        return
    rows = [
        ("sup R − R̂ (tight bound)", fmt(result.value)),
        ("target (ρ_f − 1)·δ·L_i", fmt(params.target)),
        ("method, claim", f"{result.method}, {result.claim}"),
    ]
    if result.optimizer is not None:
        rows.insert(1, ("inf R − R̂", fmt(result.optimizer.infimum)))
    rows += [(f"maximizer {k}", fmt(v)) for k, v in vars(result.maximizer).items()]
    title = f"Tight supremum, ε = {params.eps:g}, λ = {lipschitz}"
    print_table(title, ("quantity", "value"), rows)
