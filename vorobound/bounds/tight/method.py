"""One entry point for the tight bound: the closed form where it is proven exact, else the
optimizer.

``method="auto"`` uses the closed form of :mod:`vorobound.bounds.tight.closed_form` wherever
docs/tight.md proves it to be the supremum itself (the worst vertex is feasible), and the
numerical optimizer elsewhere; ``"optimize"`` forces the optimizer (the independent check).
Every result says which method produced it and how strong its claim is.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

from ...progress import Progress
from ..claims import NUMERICAL, PROVEN
from ..configurations import GuideConfiguration
from ..eps_star import EpsStar, NoCrossing, check_not_empty
from ..params import EPS_RANGE, QualityParams, SamplingParams, checked_lipschitz
from .closed_form import (
    ClosedFormStatus,
    tight_eps_star_closed_form,
    tight_supremum_closed_form,
)
from .scan import TightResult, solve_tight, tight_supremum

CLOSED_FORM = "closed form"
OPTIMIZER = "optimizer"


class TightMethod(str, Enum):
    """How to evaluate the tight bound."""

    auto = "auto"
    """The closed form where it is proven exact, the optimizer elsewhere."""
    optimize = "optimize"
    """Always the numerical optimizer."""


@dataclass(frozen=True)
class TightBound:
    """The tight bound on R − R̂ at one ε."""

    value: float
    """sup R − R̂ over the constraint set (absolute units)."""
    maximizer: GuideConfiguration
    method: str
    """"closed form" or "optimizer"."""
    claim: str
    """proven or numerical (:mod:`vorobound.bounds.claims`)."""
    optimizer: TightResult | None = None
    """The optimizer's full result (infimum, evidence) when the optimizer produced the value."""


def tight_bound(
    params: SamplingParams, lipschitz: float | None = None, method: TightMethod | str = "auto"
) -> TightBound:
    """The tight bound at ``params.eps`` (see the module docstring for ``method``)."""
    method = TightMethod(method)
    lipschitz = checked_lipschitz(lipschitz)
    if method is TightMethod.auto:
        closed = tight_supremum_closed_form(
            params.eps, params.sigma, params.delta_ratio, params.lfs, lipschitz
        )
        if closed.status is ClosedFormStatus.exact:
            return TightBound(closed.value, closed.maximizer, CLOSED_FORM, PROVEN)
    result = tight_supremum(params, lipschitz)
    return TightBound(result.supremum, result.maximizer, OPTIMIZER, NUMERICAL, result)


def tight_eps_star(
    quality: QualityParams,
    lipschitz: float | None = None,
    method: TightMethod | str = "auto",
    progress: Progress | None = None,
) -> EpsStar:
    """The tight ε* (see the module docstring for ``method``).

    The closed form's ε* is the tight ε* itself when the worst vertex is feasible there
    (docs/tight.md, steps 5–6); it is used then, and the optimizer otherwise.
    """
    method = TightMethod(method)
    lipschitz = checked_lipschitz(lipschitz)
    check_not_empty(quality, "tight")
    if method is TightMethod.auto:
        if lipschitz == 0:
            raise NoCrossing(
                "with lipschitz = 0 every L is equal, so R - R_hat = 0 for every guide "
                "triangle: the tight bound never reaches the target (no crossing), so no eps*"
            )
        closed = tight_eps_star_closed_form(
            quality.sigma, quality.delta_ratio, quality.rho_f, lipschitz
        )
        if closed.status is ClosedFormStatus.exact:
            star = closed.eps_star
            maximizer = tight_supremum_closed_form(
                star, quality.sigma, quality.delta_ratio, quality.lfs, lipschitz
            ).maximizer
            return EpsStar(
                eps_star=star,
                mode="tight",
                quality=quality,
                residual=closed.residual,
                iterations=0,
                bracket=EPS_RANGE,
                method=CLOSED_FORM,
                claim=PROVEN,
                maximizer=maximizer,
                lipschitz=lipschitz,
            )
    return solve_tight(quality, lipschitz, progress=progress)
