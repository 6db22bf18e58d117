"""One place that answers "which ε for which guarantee": ε* and the bound at ε, per mode and
target.

Every command and report asks its question here, so the dispatch on mode (paper, rigorous,
tight) and target (additive, ratio; :mod:`vorobound.bounds.targets`) is written once. The
defaults are the strongest proven statement the project has: the tight mode and the ratio
target R ≤ ρ_f·R̂ of eq. (54), the form VoroCrust's Lemma 9 takes.

References
----------
Eq. (29)–(30), (33)–(55), property H3.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..errors import InputError
from ..progress import Progress
from .claims import CHAIN_CLAIM
from .constraints import require_guide_triangles
from .eps_star import EpsStar, solve_eps_star
from .params import Mode, QualityParams, SamplingParams, Target, checked_mode

DEFAULT_MODE = Mode.tight
"""The proven mode every command defaults to (closed form where proven, docs/tight.md)."""
DEFAULT_TARGET = Target.ratio
"""The target every command that gives one answer defaults to: R ≤ ρ_f·R̂, eq. (54)."""
ALL_TARGETS = (Target.additive, Target.ratio)


def checked_question(mode, quality: QualityParams) -> Mode:
    """The mode, validated against the parameters once: λ belongs to the tight mode only (the
    chains are stated without a Lipschitz condition)."""
    mode = checked_mode(mode)
    if not isinstance(quality, QualityParams):
        raise InputError(f"quality must be QualityParams, got {type(quality).__name__}")
    if mode is not Mode.tight and quality.lipschitz is not None:
        raise InputError("a Lipschitz constant applies to the tight mode only")
    return mode


def for_mode(quality: QualityParams, mode) -> QualityParams:
    """``quality`` as ``mode`` takes it: the chains drop λ (they have no Lipschitz condition)."""
    if checked_mode(mode) is Mode.tight or quality.lipschitz is None:
        return quality
    return quality.but(lipschitz=None)


def eps_star(
    quality: QualityParams,
    mode: Mode | str = DEFAULT_MODE,
    method: str = "auto",
    progress: Progress | None = None,
) -> EpsStar:
    """The largest ε at which ``mode``'s bound meets ``quality.target`` (with its claim).

    Parameters
    ----------
    quality : QualityParams
        σ, δ/ε, ρ_f, L_i, λ (tight mode only) and the target: R − R̂ ≤ (ρ_f − 1)δL_i
        (additive), or R ≤ ρ_f·R̂ (ratio, eq. (54)).
    mode : {"paper", "rigorous", "tight"}
        The printed chain (invalid), the corrected chain (proven) or the supremum over the
        constraint set (proven in closed form where docs/tight.md says so, else numerical).
    method : {"auto", "optimize"}
        Tight mode: the closed form where proven, or always the optimizer.
    progress : Progress, optional

    Raises
    ------
    NoAdmissibleEps
        No ε meets the target (or, as NoCrossing, every supported ε does).
    """
    from .tight.method import checked_method, tight_eps_star

    mode = checked_question(mode, quality)
    method = checked_method(method)  # refused in every mode, though only tight uses it
    if mode is Mode.tight:
        return tight_eps_star(quality, method, progress)
    return solve_eps_star(quality, mode)


@dataclass(frozen=True)
class BoundAt:
    """A mode's bound at one ε for one target."""

    mode: str
    target: str
    value: float
    """The bound on R − R̂ (additive, absolute units) or on R/R̂ (ratio; inf when none)."""
    limit: float
    """What it is compared with: (ρ_f − 1)δL_i, or ρ_f."""
    fraction: float
    """The bound as a fraction of the target's allowance (≤ 1 where the target is met):
    bound/((ρ_f − 1)δL_i), or the bound on (R − R̂)/R over 1 − 1/ρ_f."""
    claim: str
    method: str
    lipschitz: float | None = None
    detail: object = None
    """The chain (:class:`~vorobound.bounds.chain.ChainBounds`) or the tight result."""

    @property
    def meets_target(self) -> bool:
        return self.fraction <= 1


def bound_at(
    params: SamplingParams,
    mode: Mode | str = DEFAULT_MODE,
    method: str = "auto",
) -> BoundAt:
    """``mode``'s bound at ``params.eps`` for ``params.target``.

    Raises
    ------
    EmptyConstraintSet
        When no guide triangle exists at this ε (σ(1 − ε) > √3): every bound is vacuous.
    """
    from .tight.method import checked_method, tight_bound

    mode = checked_question(mode, params.quality)
    method = checked_method(method)  # refused in every mode, though only tight uses it
    require_guide_triangles(params.eps, params.sigma)
    if mode is Mode.tight:
        tight = tight_bound(params, method)
        return BoundAt(
            mode.value,
            params.target.value,
            tight.value,
            params.limit,
            tight.fraction,
            tight.claim,
            tight.method,
            params.lipschitz,
            tight,
        )
    from .chain import chain_bounds

    chain = chain_bounds(params, mode)
    if params.target is Target.ratio:
        value = float(chain.ratio_bound)
        fraction = float(chain.share_bound) / params.share_allowance
    else:
        value = float(chain.bound)
        fraction = value / params.gap_allowance
    return BoundAt(
        mode.value,
        params.target.value,
        value,
        params.limit,
        fraction,
        CHAIN_CLAIM[mode.value],
        "chain",
        None,
        chain,
    )
