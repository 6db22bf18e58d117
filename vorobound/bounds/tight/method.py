"""One entry point for the tight bound: the closed form where it is proven exact, else the
optimizer.

``method="auto"`` uses the closed forms of :mod:`vorobound.bounds.tight.closed_form` (additive
target) and :mod:`vorobound.bounds.tight.ratio_form` (ratio target) wherever docs/tight.md
proves them to be the supremum itself (the worst vertex is feasible), and the numerical
optimizer elsewhere; ``"optimize"`` forces the optimizer (the independent check). Every result
says which method produced it and how strong its claim is; a numerical ε* also carries the
closed form's proven lower bound when there is one.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from ...checks import EPS_RANGE, brief
from ...errors import InputError, NoCrossing, VoroboundError
from ...progress import Progress
from ..claims import NUMERICAL, PROVEN
from ..configurations import GuideConfiguration
from ..constraints import require_guide_triangles
from ..eps_star import EpsStar, feasible_start
from ..params import QualityParams, SamplingParams, Target, TightMethod
from .closed_form import (
    ClosedFormStatus,
    tight_eps_star_closed_form,
    tight_supremum_closed_form,
)
from .ratio_form import ratio_eps_star_closed_form, ratio_supremum_closed_form
from .scan import TightResult, solve_tight, tight_supremum

CLOSED_FORM = "closed form"
OPTIMIZER = "optimizer"


def checked_method(method) -> TightMethod:
    """``method`` as a :class:`TightMethod` (InputError names the choices)."""
    try:
        return TightMethod(method)
    except (ValueError, TypeError):
        raise InputError(f"method must be auto or optimize, got {brief(method)}") from None


@dataclass(frozen=True)
class TightBound:
    """The tight bound at one ε: sup R − R̂ (additive target) or sup R/R̂ (ratio target)."""

    value: float
    """sup R − R̂ over the constraint set (absolute units), or sup R/R̂ (inf where R̂ can
    reach 0)."""
    maximizer: GuideConfiguration
    method: str
    """"closed form" or "optimizer"."""
    claim: str
    """proven or numerical (:mod:`vorobound.bounds.claims`)."""
    optimizer: TightResult | None = None
    """The optimizer's full result (infimum, evidence) when the optimizer produced the value."""
    target: str = "additive"
    fraction: float = 0.0
    """The bound as a fraction of the target: sup(R − R̂)/((ρ_f − 1)δL_i), or
    sup((R − R̂)/R)/(1 − 1/ρ_f); at most 1 where the target is met."""


def tight_bound(params: SamplingParams, method: TightMethod | str = "auto") -> TightBound:
    """The tight bound at ``params.eps`` for ``params.target``, over the constraint set with
    ``params.lipschitz`` (see the module docstring for ``method``)."""
    method, target, lipschitz = checked_method(method), params.target, params.lipschitz
    require_guide_triangles(params.eps, params.sigma)
    if method is TightMethod.auto:
        if target is Target.ratio:
            ratio = ratio_supremum_closed_form(
                params.eps, params.sigma, params.delta_ratio, lipschitz
            )
            if ratio.status is ClosedFormStatus.exact:
                return TightBound(
                    ratio.value,
                    ratio.vertex.maximizer,
                    CLOSED_FORM,
                    PROVEN,
                    None,
                    target.value,
                    ratio.share / params.share_allowance,
                )
        else:
            closed = tight_supremum_closed_form(
                params.eps, params.sigma, params.delta_ratio, params.lfs, lipschitz
            )
            if closed.status is ClosedFormStatus.exact:
                return TightBound(
                    closed.value,
                    closed.maximizer,
                    CLOSED_FORM,
                    PROVEN,
                    None,
                    target.value,
                    closed.value / params.gap_allowance,
                )
    result = tight_supremum(params)
    if target is Target.ratio:
        top = result.supremum
        value = float("inf") if top >= 1 else 1 / (1 - top)
        fraction = top / params.share_allowance
    else:
        value, fraction = result.supremum, result.supremum / params.gap_allowance
    return TightBound(value, result.maximizer, OPTIMIZER, NUMERICAL, result, target.value, fraction)


def tight_eps_star(
    quality: QualityParams,
    method: TightMethod | str = "auto",
    progress: Progress | None = None,
) -> EpsStar:
    """The tight ε* for ``quality.target`` with ``quality.lipschitz`` (see the module
    docstring for ``method``).

    The closed form's ε* is the tight ε* itself when the worst vertex is feasible there
    (docs/tight.md, steps 5–6 and "The ratio target"); it is used then. Otherwise the
    optimizer's ε* is returned (numerical), with the closed form's root as
    ``proven_lower_bound`` when guide triangles exist there (it is then proven admissible).
    """
    method, lipschitz = checked_method(method), quality.lipschitz
    feasible_start(quality, "tight")
    if lipschitz == 0:
        raise NoCrossing(
            "with lipschitz = 0 every L is equal, so R - R_hat = 0 for every guide "
            "triangle: the tight bound never reaches the target (no crossing), so no eps*"
        )
    lower = None
    if method is TightMethod.auto:
        try:
            closed = _closed_eps_star(quality)
        except NoCrossing:
            raise
        except VoroboundError:
            closed = None  # the root lies where no guide triangle exists: no proof from it
        if closed is not None and closed.status is ClosedFormStatus.exact:
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
            )
        lower = None if closed is None else closed.eps_star
    result = solve_tight(quality, progress=progress)
    return replace(result, proven_lower_bound=lower)


def _closed_eps_star(quality: QualityParams):
    """The closed-form ε* of the target (its ``status`` says exact or a proven lower bound)."""
    lipschitz = quality.lipschitz
    if quality.target is Target.ratio:
        return ratio_eps_star_closed_form(
            quality.sigma, quality.delta_ratio, quality.rho_f, lipschitz
        )
    return tight_eps_star_closed_form(quality.sigma, quality.delta_ratio, quality.rho_f, lipschitz)
