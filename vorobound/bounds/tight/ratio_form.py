"""The tight supremum of R/R̂ and the ratio target's ε* in closed form (docs/tight.md, "The
ratio target").

Over the constraint set of :mod:`vorobound.bounds.constraints` (units L_i = 1, r = δ/ε), with
R̂ the orthoradius of the min-weight-shifted triangle (so R̂ ≥ 0):

    R̂/R = â/a ≥ 1 − μ*,   hence   sup R/R̂ = 1/(1 − μ*) for μ* < 1 (unbounded for μ* ≥ 1),

μ* = r²X(2 + X)/σ² the largest shifted weight over (σεL_i)² (:func:`.closed_form.weight_ratio`).
The bound follows from docs/tight.md, steps 1 and 3 (R̂/R = â/a and |d| ≤ μ*·a); it is attained
at the isosceles vertex b = c = σεL_i, L_j = L_k = L_i(1 + X), where d = μ*(C − B) and
â = (1 − μ*)a, whenever that vertex admits an angle with a ≥ σε(1 + X) and R ≤ ε/(1−ε)·L_i,
i.e. under the same condition 2·sqrt(1 − k_sin²) ≥ 1 + X as the additive closed form. Then
the value is exact (:attr:`ClosedFormStatus.exact`), otherwise a proven upper bound.

The ratio target R ≤ ρ_f·R̂ (eq. (54)) holds on the whole constraint set if
μ*(ε) ≤ 1 − 1/ρ_f (and only if, where the vertex is feasible: status exact). μ* increases
with ε, so ε*_ratio solves X(2 + X) = (σ/r)²(1 − 1/ρ_f), X = min(2ε/(1−ε), λσε), explicitly:
ε* = X/(2 + X), or with λ the larger of that and X/(λσ).

References
----------
Theorem 1 (eq. (16)–(17), (25)–(26)), eq. (30), (33)–(37), (54), property H3.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ...checks import EPS_RANGE, RHO_F_MAX
from ...errors import NoAdmissibleEps, NoCrossing
from .. import constraints
from ..roots import step_below
from .closed_form import (
    ClosedFormStatus,
    ClosedFormSupremum,
    _checked,
    _checked_quality,
    _vertex_feasible,
    tight_supremum_closed_form,
)


@dataclass(frozen=True)
class RatioSupremum:
    """sup R/R̂ over the constraint set at one ε, in closed form."""

    value: float
    """1/(1 − μ*), or +inf once μ* ≥ 1 (R̂ can reach 0)."""
    share: float
    """min(1, μ*): the supremum of (R − R̂)/R = 1 − R̂/R (or a proven upper bound on it)."""
    status: ClosedFormStatus
    """exact where the isosceles vertex is feasible, else a proven upper bound."""
    vertex: ClosedFormSupremum
    """The additive closed form at the same ε; its maximizer is the worst triangle here too."""


@dataclass(frozen=True)
class RatioEpsStar:
    """The ratio target's ε*: the largest ε with sup R/R̂ ≤ ρ_f."""

    eps_star: float
    """Every ε ≤ this keeps R ≤ ρ_f·R̂ for every guide triangle (proven); the tight ε* itself
    when ``status`` is exact."""
    status: ClosedFormStatus
    supremum: RatioSupremum
    """The closed form at ε*."""
    residual: float
    """sup R/R̂ / ρ_f − 1 at ε* (rounding only)."""
    rho_f: float


def ratio_supremum_closed_form(
    eps: float, sigma: float, delta_ratio: float, lipschitz: float | None = None
) -> RatioSupremum:
    """sup R/R̂ over every guide triangle of the constraint set at ``eps`` (module docstring).

    Parameters
    ----------
    eps, sigma, delta_ratio : float
        ε, σ and δ/ε; σ(1−ε) ≤ √3 is required (else no guide triangle is feasible).
    lipschitz : float, optional
        λ ≥ 0 of the Lipschitz conditions.

    References
    ----------
    Eq. (16)–(17), (33)–(37), (54); docs/tight.md, "The ratio target".
    """
    vertex = tight_supremum_closed_form(eps, sigma, delta_ratio, 1.0, lipschitz)
    share = min(1.0, vertex.weight_ratio)
    value = math.inf if share >= 1 else 1 / (1 - share)
    return RatioSupremum(value=value, share=share, status=vertex.status, vertex=vertex)


def ratio_eps_star_closed_form(
    sigma: float, delta_ratio: float, rho_f: float, lipschitz: float | None = None
) -> RatioEpsStar:
    """The ratio target's ε*: μ*(ε) = 1 − 1/ρ_f, solved explicitly.

    Raises
    ------
    NoCrossing
        λ = 0 (equal weights: R̂ = R everywhere) or a root above the supported ε.
    InputError
        When no guide triangle is feasible at the root (σ(1−ε) > √3): the closed form then
        proves nothing beyond "no triangle exists below 1 − √3/σ".

    References
    ----------
    Eq. (54); :func:`ratio_supremum_closed_form`.
    """
    from ...checks import checked_number

    sigma, delta_ratio, _, lipschitz = _checked_quality(sigma, delta_ratio, 1.0, lipschitz)
    rho_f = checked_number(rho_f, "rho_f", 1.0, RHO_F_MAX, open_low=True)
    if lipschitz == 0:
        raise NoCrossing(
            "with lipschitz = 0 every L is equal, so R^ = R for every guide triangle: the "
            "ratio target is met at every eps (no crossing), so no eps*"
        )
    # X(2 + X) = q, written without cancellation: X = q/(1 + sqrt(1 + q)).
    q = (sigma / delta_ratio) ** 2 * (1 - 1 / rho_f)
    excess = q / (1 + math.sqrt(1 + q))
    root = excess / (2 + excess)
    if lipschitz is not None:
        root = max(root, excess / (lipschitz * sigma))
    low, high = EPS_RANGE
    if root < low:
        raise NoAdmissibleEps(
            f"the tight ratio bound exceeds rho_f already at eps = {low:g}: no admissible eps"
        )
    if root >= high:
        raise NoCrossing(
            f"the tight ratio bound stays within rho_f up to eps = {high:g}: no crossing, so "
            "no eps* in the supported range"
        )
    _checked(root, sigma, delta_ratio, 1.0, lipschitz)
    # The explicit root is correctly rounded up to a few ulps: step down until the float
    # supremum at it meets ρ_f, so the printed ε* passes the check where it is evaluated.
    root = step_below(
        root,
        lambda eps: ratio_supremum_closed_form(eps, sigma, delta_ratio, lipschitz).value <= rho_f,
    )
    constraints.require_guide_triangles(root, sigma)
    supremum = ratio_supremum_closed_form(root, sigma, delta_ratio, lipschitz)
    exact = _vertex_feasible(root, sigma, delta_ratio, lipschitz)
    return RatioEpsStar(
        eps_star=root,
        status=ClosedFormStatus.exact if exact else ClosedFormStatus.upper_bound,
        supremum=supremum,
        residual=supremum.value / rho_f - 1,
        rho_f=rho_f,
    )
