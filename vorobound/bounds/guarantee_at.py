"""The inverse question: which guarantee does a given ε buy (the smallest proven ρ_f per target).

At one ε, over the constraint set (33)–(36) with H3 (units L_i = 1, μ* of
:func:`vorobound.bounds.tight.closed_form.weight_ratio`):

* ratio target, eq. (54): sup R/R̂ = 1/(1 − μ*) (docs/tight.md, "The ratio target"), so
  R ≤ ρ_f·R̂ holds for every guide triangle exactly when ρ_f ≥ 1/(1 − μ*); none for μ* ≥ 1;
* additive target: sup(R − R̂) = min(1, μ*)·ε/(1−ε)·L_i, i.e. a fraction
  min(1, μ*)/((1−ε)·δ/ε) of δL_i, so R − R̂ ≤ (ρ_f − 1)δL_i for ρ_f ≥ 1 + that fraction;
* eq. (55), R ≤ ρ_f·δ·L_i: from H3 alone for ρ_f ≥ 1/((1−ε)·δ/ε) (:mod:`.targets`), and from
  the additive bound with R̂ ≤ δL_i for ρ_f ≥ 1 + the fraction; the smaller of the two.

Every value is proven (closed form, docs/tight.md): the exact supremum where the worst vertex is
feasible, otherwise a proven upper bound (``status``), and conditional on H3 like every bound
over the constraint set.

References
----------
Eq. (54)–(55), property H3; docs/tight.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .params import QualityParams
from .tight.closed_form import tight_supremum_closed_form


@dataclass(frozen=True)
class GuaranteeAt:
    """The smallest ρ_f each target is proven to meet at one ε."""

    eps: float
    rho_f_ratio: float
    """Smallest ρ_f with R ≤ ρ_f·R̂ (eq. (54)) for every guide triangle: 1/(1 − μ*); +inf when
    μ* ≥ 1 (R̂ can be 0, so no ρ_f works)."""
    additive_fraction: float
    """sup(R − R̂)/(δL_i) = min(1, μ*)/((1−ε)·δ/ε): the additive target holds for ρ_f ≥ 1 +
    this."""
    rho_f_h3: float
    """1/((1−ε)·δ/ε): the ρ_f of eq. (55) that H3 alone gives."""
    status: str
    """How strong the closed form is here: "proven exact" or "proven upper bound"."""

    @property
    def rho_f_additive(self) -> float:
        """Smallest ρ_f the additive target R − R̂ ≤ (ρ_f − 1)δL_i is proven to meet."""
        return 1 + self.additive_fraction

    @property
    def rho_f_55(self) -> float:
        """Smallest ρ_f proven for eq. (55), R ≤ ρ_f·δ·L_i: the better of H3 alone and the
        additive bound with R̂ ≤ δL_i."""
        return min(self.rho_f_h3, self.rho_f_additive)


def guarantee_at(eps: float, quality: QualityParams) -> GuaranteeAt:
    """What ``eps`` guarantees under ``quality``'s σ, δ/ε and λ (its ρ_f and target are not
    used: the answer is the ρ_f per target).

    Raises
    ------
    InputError
        ε outside the supported range, or σ(1 − ε) > √3 (no guide triangle exists).

    References
    ----------
    Eq. (54)–(55); docs/tight.md ("The ratio target").
    """
    vertex = tight_supremum_closed_form(
        eps, quality.sigma, quality.delta_ratio, 1.0, quality.lipschitz
    )
    share = min(1.0, vertex.weight_ratio)
    per_delta = (1 - vertex.eps) * quality.delta_ratio
    return GuaranteeAt(
        eps=vertex.eps,
        rho_f_ratio=math.inf if share >= 1 else 1 / (1 - share),
        additive_fraction=share / per_delta,
        rho_f_h3=1 / per_delta,
        status=vertex.status.value,
    )
