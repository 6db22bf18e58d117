"""``vorobound bounds``: a mode's bound at one ε against a target (every quantity of the chain
(33)–(53), or the tight supremum)."""

from __future__ import annotations

import math
import typing
from dataclasses import dataclass, field

from ..bounds.guarantee import BoundAt
from ..bounds.params import Mode, SamplingParams, Target, checked_target
from ..bounds.targets import H3_STATUS, STATEMENT
from ..constants import PAPER_DELTA_RATIO, PAPER_RHO_F, PAPER_SIGMA
from ..errors import VoroboundError
from .arguments import checked_arguments
from .result import Result, params_json

if typing.TYPE_CHECKING:
    from ..bounds.chain import ChainBounds
    from ..bounds.tight.method import TightBound

UNBOUNDED = "no finite bound: the bound on (R - R^)/R is 1 or more, so R^ may be 0"


@dataclass(frozen=True, repr=False)
class BoundResult(Result):
    """A mode's bound at one ε for one target, against what the target allows."""

    command = "bounds"
    eps: float
    mode: str
    target: str
    value: float
    """The bound on R − R̂ (additive target, absolute units) or on R/R̂ (ratio; inf: none)."""
    limit: float
    """(ρ_f − 1)·δ·L_i (additive) or ρ_f (ratio)."""
    fraction_of_target: float
    """The bound as a fraction of the target's allowance: at most 1 where it is met."""
    claim: str
    method: str
    detail: BoundAt = field(repr=False)
    params: SamplingParams = field(repr=False)

    @property
    def meets_target(self) -> bool:
        return self.fraction_of_target <= 1

    premise = H3_STATUS
    """What every bound rests on (property H3)."""

    @property
    def tight(self) -> TightBound:
        """Mode tight: the supremum, its maximizer and the optimizer's evidence."""
        return typing.cast("TightBound", self.detail.detail)

    @property
    def chain(self) -> ChainBounds:
        """Modes paper and rigorous: every quantity of the chain (33)–(53)."""
        return typing.cast("ChainBounds", self.detail.detail)

    @property
    def share_bound(self) -> float:
        """Ratio target: the bound on (R − R̂)/R (the target allows 1 − 1/ρ_f)."""
        return self.fraction_of_target * self.params.share_allowance

    def payload(self) -> dict:
        out = {
            "params": params_json(self.params.quality, self.eps, mode=self.mode),
            "mode": self.mode,
            "target": self.target,
            "target_statement": STATEMENT[Target(self.target)],
            "claim": self.claim,
            "method": self.method,
            "bound": self.value,
            "limit": self.limit,
            "fraction_of_target": self.fraction_of_target,
            "meets_target": self.meets_target,
            "premise": self.premise,
        }
        if self.target == Target.ratio.value:
            out["share_bound"] = self.share_bound
            if math.isinf(self.value):
                out["bound_note"] = UNBOUNDED
        if self.mode == Mode.tight.value:
            tight = self.tight
            out["maximizer"] = tight.maximizer
            if tight.optimizer is not None:
                out["infimum"] = tight.optimizer.infimum
                out["minimizer"] = tight.optimizer.minimizer
                out["evidence"] = tight.optimizer.evidence
                out["infimum_evidence"] = tight.optimizer.infimum_evidence
        else:
            out["quantities"] = {
                name: {"equation": eq, "description": text, "value": float(value)}
                for name, eq, text, value in self.chain.rows()
            }
        return out


@checked_arguments
def bound(
    *,
    eps: float,
    sigma: float = PAPER_SIGMA,
    delta_ratio: float = PAPER_DELTA_RATIO,
    lfs: float = 1.0,
    rho_f: float = PAPER_RHO_F,
    mode: Mode | str = "tight",
    target: Target | str = "ratio",
    lipschitz: float | None = None,
    method: str = "auto",
) -> BoundResult:
    """``mode``'s bound at ``eps`` for ``target`` (the command ``vorobound bounds``).

    Parameters are those of :func:`vorobound.solve`, plus the sampling density ``eps``.

    Raises
    ------
    EmptyConstraintSet
        No guide triangle exists at this ε (σ(1 − ε) > √3): every bound is vacuous.
    VoroboundError
        The chain's own formulas are undefined at this ε.

    References
    ----------
    Eq. (29)–(30), (33)–(55), property H3.
    """
    from ..bounds.guarantee import bound_at
    from ..bounds.params import QualityParams

    quality = QualityParams(sigma, delta_ratio, rho_f, lfs, lipschitz, checked_target(target))
    params = quality.at(eps)
    result = bound_at(params, mode, method)
    if math.isnan(result.fraction):
        raise VoroboundError(
            f"the {result.mode} chain is not defined at eps = {eps:g}, sigma = {sigma:g} "
            "(a square root of a negative number in eq. (51)-(52): no feasible guide triangle "
            "or |k_cos| > 1)"
        )
    return BoundResult(
        eps=params.eps,
        mode=result.mode,
        target=result.target,
        value=float(result.value),
        limit=float(result.limit),
        fraction_of_target=float(result.fraction),
        claim=result.claim,
        method=result.method,
        detail=result,
        params=params,
    )
