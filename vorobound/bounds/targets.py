"""The two quality targets a bound can be asked to meet, and what H3 alone gives.

VoroCrust's Lemma 9 is quoted by the paper in the ratio form (54), R ≤ ρ_f·R̂; the paper then
uses R̂ ≤ δL_i to reach (55), R ≤ ρ_f·δ·L_i, and bounds R − R̂ to reach (55) directly:

* ``additive``: R − R̂ ≤ (ρ_f − 1)·δ·L_i, which with R̂ ≤ δL_i gives (55). The target of the
  paper's Section 4.1 (and of Figure 3).
* ``ratio``: R ≤ ρ_f·R̂, eq. (54) itself. R̂ is the orthoradius of the triangle with the minimum
  weight subtracted (Theorem 1), so R̂ ≥ 0 and, with R − R̂ = R·(a − â)/a (docs/tight.md,
  step 1), the target reads (R − R̂)/R ≤ 1 − 1/ρ_f. The additive target does not imply it.

Both are stated on the constraint set of :mod:`vorobound.bounds.constraints`, which contains
property H3, R ≤ ε/(1−ε)·L_i. H3 comes from the VoroCrust literature and is not derived here
(docs/tight.md, "What H3 is"); ``vorobound check`` measures it on real samples. H3 alone gives
(55) whenever ε/(1−ε) ≤ ρ_f·(δ/ε)·ε, i.e. for every ε ≤ 1 − 1/(ρ_f·δ/ε)
(:func:`h3_route_eps`), which is why the additive target adds nothing to (55) wherever H3 holds.

References
----------
Eq. (16), (29)–(30), (54)–(55) and property H3 of Section 4.1.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..checks import EPS_RANGE
from ..errors import NoAdmissibleEps
from .claims import PROVEN
from .params import QualityParams, Target

STATEMENT = {
    Target.additive: "R - R^ <= (rho_f - 1) * delta * L_i (gives eq. (55) through R^ <= delta L_i)",
    Target.ratio: "R <= rho_f * R^ (eq. (54))",
}
"""Each target in plain ASCII, for JSON and certificates."""

H3_STATEMENT = "H3: R <= eps/(1-eps) * L_i for every guide triangle"
H3_STATUS = (
    "assumption: H3 is taken from the VoroCrust literature and not derived here "
    "(docs/tight.md, 'What H3 is'); 'vorobound check' measures it on real samples "
    "(h3_ratio_max <= 1 where it holds)"
)
"""What every bound over the constraint set rests on, said wherever such a bound is printed."""


@dataclass(frozen=True)
class H3Route:
    """The ε up to which H3 alone gives (55): ε/(1−ε)·L_i ≤ ρ_f·δ·L_i."""

    eps_star: float
    """1 − 1/(ρ_f·δ/ε): every ε ≤ this meets (55) once H3 holds."""
    claim: str
    """proven (one line of algebra from H3)."""
    premise: str
    """H3 and its status (:data:`H3_STATUS`)."""


def h3_route(quality: QualityParams) -> H3Route:
    """The ε up to which H3, R ≤ ε/(1−ε)·L_i, gives R ≤ ρ_f·δ·L_i (eq. (55)) by itself.

    With δ = (δ/ε)·ε, ε/(1−ε) ≤ ρ_f(δ/ε)ε ⇔ 1/(1−ε) ≤ ρ_f·δ/ε ⇔ ε ≤ 1 − 1/(ρ_f·δ/ε).

    Raises
    ------
    NoAdmissibleEps
        When ρ_f·δ/ε ≤ 1 (H3 then never gives (55)).

    References
    ----------
    Eq. (55), property H3.
    """
    product = quality.rho_f * quality.delta_ratio
    if product <= 1:
        raise NoAdmissibleEps(
            f"rho_f * delta/eps = {product:g} <= 1: H3 alone never gives R <= rho_f*delta*L_i"
        )
    star = min(1 - 1 / product, EPS_RANGE[1])
    return H3Route(eps_star=star, claim=PROVEN, premise=f"{H3_STATEMENT} ({H3_STATUS})")
