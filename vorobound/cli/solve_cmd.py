"""``vorobound solve``: the largest admissible ε of one mode, for one target."""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..rounding import format_down
from .command import grouped, invoke
from .options import (
    BoundOptions,
    Json,
    ModeChoice,
)

if TYPE_CHECKING:
    from ..api.solve import SolveResult
from .render import fmt, print_footer, print_table


@grouped
def solve(
    question: BoundOptions = BoundOptions(),
    as_json: Json = False,
) -> int:
    """The largest ε at which a bound meets a quality target, and how strong that is.

    By default the tight bound (proven) for the ratio target R ≤ ρ_f·R̂ of eq. (54). The paper
    reports ε ≤ 0.0047 for the additive target with its printed chain (--mode paper
    --target additive, invalid: docs/errata.md). Every answer rests on property H3, an
    assumption from the VoroCrust literature; the output also says up to which ε H3 alone
    gives R ≤ ρ_f·δ·L_i (eq. (55)). Python: vorobound.solve(...).
    """
    return invoke("solve", _show, locals(), bar=question.mode is ModeChoice.tight)


def _show(result: SolveResult) -> None:
    star, q = result.detail, result.quality
    rows = [
        ("ε*", format_down(result.eps_star, 12)),
        ("claim", result.claim),
        ("method", result.method),
    ]
    if result.proven_lower_bound is not None:
        rows.append(
            ("proven lower bound on ε* (closed form)", format_down(result.proven_lower_bound, 12))
        )
    rows += [
        ("ε* / (1/500)", format_down(result.eps_star_over_baseline, 6)),
        ("ball radius δ·L_i at ε*", format_down(result.ball_radius, 10)),
        ("relative residual", fmt(star.residual, 3)),
        ("root-finder iterations", str(star.iterations)),
        ("bracket", f"[{fmt(star.bracket[0])}, {fmt(star.bracket[1])}]"),
        ("H3 alone gives (55) up to ε", f"{format_down(result.h3_eps_star, 6)} (given H3)"),
    ]
    lam = "" if q.lipschitz is None else f", λ = {q.lipschitz:g}"
    print_table(
        f"ε* for mode {result.mode}, target {result.target} (ρ_f = {q.rho_f:g}, σ = {q.sigma:g}, "
        f"δ/ε = {q.delta_ratio:g}{lam})",
        ("quantity", "value"),
        rows,
    )
    print_footer(f"target: {result.target_statement}")
    print_footer(f"premise: {result.premise}")
