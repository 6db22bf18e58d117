"""``vorobound bounds``: every quantity of the chain (33)–(53), or the tight bound, at one ε."""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..rounding import format_up
from .command import grouped, invoke
from .options import (
    BoundOptions,
    Eps,
    Json,
    ModeChoice,
    TargetChoice,
)

if TYPE_CHECKING:
    from ..api.bound import BoundResult
from .render import fmt, print_footer, print_table


@grouped
def bounds(
    eps: Eps,
    question: BoundOptions = BoundOptions(),
    as_json: Json = False,
) -> int:
    """A mode's bound at one ε, against a target: every quantity of the chain (33)–(53), or the
    tight supremum.

    Targets: ratio, R ≤ ρ_f·R̂ (eq. (54)); additive, R − R̂ ≤ (ρ_f − 1)·δ·L_i, which with
    R̂ ≤ δ·L_i gives R ≤ ρ_f·δ·L_i (eq. (55)). Every bound rests on property H3 (an assumption
    from the VoroCrust literature). Python: vorobound.bound(eps=...).
    """
    return invoke(
        "bound", _show, locals(), bar=question.mode is ModeChoice.tight, task="tight supremum"
    )


def _show(result: BoundResult) -> None:
    from ..api.bound import UNBOUNDED

    ratio = result.target == TargetChoice.ratio.value
    quantity = "R/R̂" if ratio else "R − R̂"
    limit = "ρ_f" if ratio else "(ρ_f − 1)·δ·L_i"
    if result.mode == ModeChoice.tight.value:
        _show_tight(result, quantity)
    else:
        rows = [
            (name, equation, format_up(float(value), 10), text)
            for name, equation, text, value in result.chain.rows()
        ]
        print_table(
            f"Chain (33)–(53), mode {result.mode} ({result.claim}), ε = {result.eps:g}",
            ("quantity", "eq.", "value", "meaning"),
            rows,
        )
    verdict = "meets" if result.meets_target else "exceeds"
    shown = "∞ (" + UNBOUNDED + ")" if result.value == float("inf") else format_up(result.value, 10)
    if ratio:
        allowed = result.params.share_allowance
        share = (
            f"(R − R̂)/R up to {format_up(result.share_bound, 6)} against the "
            f"{fmt(allowed, 6)} that R ≤ ρ_f·R̂ allows: {format_up(result.fraction_of_target, 6)}×"
        )
    else:
        share = f"{format_up(result.fraction_of_target, 6)}× the allowance"
    print_footer(
        f"bound on {quantity} = {shown} {verdict} the target {limit} = "
        f"{fmt(result.limit)}: {share} ({result.claim})"
    )
    if not result.meets_target:
        if result.mode == ModeChoice.tight.value:
            print_footer(
                "the tight value is the supremum over the constraint set: guide triangles of "
                "the set come arbitrarily close to it, so the target fails for some of them at "
                "this ε (where the closed form is an upper bound only, `vorobound certify "
                "--eps` decides)"
            )
        else:
            print_footer(
                "a chain is an upper bound: exceeding the target does not show that the target "
                "fails at this ε, only that this chain cannot prove it (mode tight gives the "
                "supremum)"
            )
    print_footer(f"premise: {result.premise}")


def _show_tight(result: BoundResult, quantity: str) -> None:
    tight = result.tight
    rows = [
        (f"sup {quantity} (tight bound)", format_up(result.value, 10)),
        ("method, claim", f"{result.method}, {result.claim}"),
    ]
    if tight.optimizer is not None:
        name = "inf (R − R̂)/R" if quantity == "R/R̂" else "inf R − R̂"
        rows.insert(1, (name, fmt(tight.optimizer.infimum)))
    rows += [(f"maximizer {k}", fmt(v)) for k, v in vars(tight.maximizer).items()]
    lam = result.params.lipschitz
    title = f"Tight supremum of {quantity}, ε = {result.eps:g}, λ = {lam}"
    print_table(title, ("quantity", "value"), rows)
