"""One entry point for the tight bound: the closed form where it is proven, else the optimizer.

``method="auto"`` picks the closed form wherever docs/tight.md proves it exact for the
parameters, and the numerical optimizer elsewhere; ``"optimize"`` forces the optimizer (the
independent check). Every result says which method produced it and how strong its claim is.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

from ...progress import Progress
from ..claims import NUMERICAL
from ..configurations import GuideConfiguration
from ..eps_star import EpsStar
from ..params import QualityParams, SamplingParams, checked_lipschitz
from .scan import TightResult, solve_tight, tight_supremum


class TightMethod(str, Enum):
    """How to evaluate the tight bound."""

    auto = "auto"
    """The closed form where it is proven, the optimizer elsewhere."""
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
    TightMethod(method)
    result = tight_supremum(params, checked_lipschitz(lipschitz))
    return TightBound(result.supremum, result.maximizer, "optimizer", NUMERICAL, result)


def tight_eps_star(
    quality: QualityParams,
    lipschitz: float | None = None,
    method: TightMethod | str = "auto",
    progress: Progress | None = None,
) -> EpsStar:
    """The tight ε* (see the module docstring for ``method``)."""
    TightMethod(method)
    return solve_tight(quality, checked_lipschitz(lipschitz), progress=progress)
