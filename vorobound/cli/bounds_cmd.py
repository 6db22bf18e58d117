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
    TargetChoice,
    TargetOpt,
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
    mode: ModeOpt = ModeChoice.tight,
    target: TargetOpt = TargetChoice.ratio,
    lipschitz: Lipschitz = None,
    method: TightMethodOpt = MethodChoice.auto,
    as_json: Json = False,
) -> None:
    """A mode's bound at one ε, against a target: every quantity of the chain (33)–(53), or the
    tight supremum.

    Targets: ratio, R ≤ ρ_f·R̂ (eq. (54)); additive, R − R̂ ≤ (ρ_f − 1)·δ·L_i, which with
    R̂ ≤ δ·L_i gives R ≤ ρ_f·δ·L_i (eq. (55)). Every bound rests on property H3 (an assumption
    from the VoroCrust literature).
    """
    from ..bounds.constraints import is_empty
    from ..bounds.guarantee import bound_at
    from ..bounds.targets import H3_STATUS, STATEMENT, Target

    params = quality_params(sigma, delta_ratio, rho_f, lfs).at(eps)
    if is_empty(params.eps, params.sigma):
        raise VoroboundError(
            f"no guide triangle is feasible at eps = {eps:g}, sigma = {sigma:g} "
            "(sigma*(1-eps) > sqrt(3)): every bound is vacuous there"
        )
    with progress_bar(not as_json and mode is ModeChoice.tight) as progress:
        if mode is ModeChoice.tight:
            progress("tight supremum", 0, None)
        result = bound_at(params, mode.value, target.value, lipschitz, method.value)
    if result.fraction != result.fraction:  # NaN: the chain's own formulas are undefined here
        raise VoroboundError(
            f"the {mode.value} chain is not defined at eps = {eps:g}, sigma = {sigma:g} "
            "(a square root of a negative number in eq. (51)-(52): no feasible guide triangle "
            "or |k_cos| > 1)"
        )
    statement = STATEMENT[Target(target.value)]
    payload = {
        "mode": mode.value,
        "target": target.value,
        "target_statement": statement,
        "method": result.method,
        "claim": result.claim,
        "params": params_dict(params.quality, params.eps),
        "lipschitz": lipschitz,
        "bound": result.value,
        "limit": result.limit,
        "fraction_of_target": result.fraction,
        "meets_target": result.meets_target,
        "premise": H3_STATUS,
    }
    if target is TargetChoice.ratio:
        payload["share_bound"] = result.fraction * (1 - 1 / rho_f)
        if result.value == float("inf"):
            payload["bound_note"] = UNBOUNDED
    if mode is ModeChoice.tight:
        _add_tight(payload, result.detail)
    else:
        payload["quantities"] = {
            name: {"equation": eq, "description": text, "value": float(value)}
            for name, eq, text, value in result.detail.rows()
        }
    if as_json:
        print_json(payload)
        return
    quantity = "R/R̂" if target is TargetChoice.ratio else "R − R̂"
    limit = "ρ_f" if target is TargetChoice.ratio else "(ρ_f − 1)·δ·L_i"
    if mode is ModeChoice.tight:
        _print_tight(params, lipschitz, result, quantity)
    else:
        rows = [
            (name, q["equation"], fmt(q["value"]), q["description"])
            for name, q in payload["quantities"].items()
        ]
        print_table(
            f"Chain (33)–(53), mode {mode.value} ({result.claim}), ε = {eps:g}",
            ("quantity", "eq.", "value", "meaning"),
            rows,
        )
    verdict = "meets" if result.meets_target else "exceeds"
    shown = "∞ (" + UNBOUNDED + ")" if result.value == float("inf") else fmt(result.value)
    if result.target == "ratio":
        allowed = 1 - 1 / result.limit
        share = (
            f"(R − R̂)/R up to {fmt(result.fraction * allowed, 6)} against the "
            f"{fmt(allowed, 6)} that R ≤ ρ_f·R̂ allows: {fmt(result.fraction, 6)}×"
        )
    else:
        share = f"{fmt(result.fraction, 6)}× the allowance"
    print(
        f"bound on {quantity} = {shown} {verdict} the target {limit} = "
        f"{fmt(result.limit)}: {share} ({result.claim})"
    )
    if not result.meets_target:
        if result.mode == "tight":
            print(
                "the tight value is the supremum over the constraint set: guide triangles of "
                "the set come arbitrarily close to it, so the target fails for some of them at "
                "this ε (where the closed form is an upper bound only, `vorobound certify "
                "--eps` decides)"
            )
        else:
            print(
                "a chain is an upper bound: exceeding the target does not show that the target "
                "fails at this ε, only that this chain cannot prove it (mode tight gives the "
                "supremum)"
            )
    print(f"premise: {H3_STATUS}")


UNBOUNDED = "no finite bound: the bound on (R - R^)/R is 1 or more, so R^ may be 0"


def _add_tight(payload: dict, tight) -> None:
    payload["maximizer"] = tight.maximizer
    if tight.optimizer is not None:
        payload["infimum"] = tight.optimizer.infimum
        payload["minimizer"] = tight.optimizer.minimizer
        payload["evidence"] = tight.optimizer.evidence
        payload["infimum_evidence"] = tight.optimizer.infimum_evidence


def _print_tight(params, lipschitz, result, quantity: str) -> None:
    tight = result.detail
    rows = [
        (f"sup {quantity} (tight bound)", fmt(result.value)),
        ("method, claim", f"{result.method}, {result.claim}"),
    ]
    if tight.optimizer is not None:
        name = "inf (R − R̂)/R" if quantity == "R/R̂" else "inf R − R̂"
        rows.insert(1, (name, fmt(tight.optimizer.infimum)))
    rows += [(f"maximizer {k}", fmt(v)) for k, v in vars(tight.maximizer).items()]
    title = f"Tight supremum of {quantity}, ε = {params.eps:g}, λ = {lipschitz}"
    print_table(title, ("quantity", "value"), rows)
