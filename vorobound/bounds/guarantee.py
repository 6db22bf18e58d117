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
from .eps_star import EpsStar, solve_eps_star
from .params import Mode, QualityParams, SamplingParams, checked_lipschitz
from .targets import Target

DEFAULT_MODE = Mode.tight
"""The proven mode every command defaults to (closed form where proven, docs/tight.md)."""
DEFAULT_TARGET = Target.ratio
"""The target every command that gives one answer defaults to: R ≤ ρ_f·R̂, eq. (54)."""
ALL_TARGETS = (Target.additive, Target.ratio)


def checked_question(mode, target, lipschitz):
    """(Mode, Target, λ) validated once; λ belongs to the tight mode only."""
    try:
        mode = Mode(mode)
    except ValueError:
        raise InputError(f"mode must be paper, rigorous or tight, got {mode!r}") from None
    try:
        target = Target(target)
    except ValueError:
        raise InputError(f"target must be additive or ratio, got {target!r}") from None
    lipschitz = checked_lipschitz(lipschitz)
    if mode is not Mode.tight and lipschitz is not None:
        raise InputError("a Lipschitz constant applies to the tight mode only")
    return mode, target, lipschitz


def eps_star(
    quality: QualityParams,
    mode: Mode | str = DEFAULT_MODE,
    target: Target | str = DEFAULT_TARGET,
    lipschitz: float | None = None,
    method: str = "auto",
    progress: Progress | None = None,
) -> EpsStar:
    """The largest ε at which ``mode``'s bound meets ``target`` (with its claim).

    Parameters
    ----------
    quality : QualityParams
        σ, δ/ε, ρ_f and L_i.
    mode : {"paper", "rigorous", "tight"}
        The printed chain (invalid), the corrected chain (proven) or the supremum over the
        constraint set (proven in closed form where docs/tight.md says so, else numerical).
    target : {"additive", "ratio"}
        R − R̂ ≤ (ρ_f − 1)δL_i, or R ≤ ρ_f·R̂ (eq. (54)).
    lipschitz : float, optional
        λ of the tight mode's Lipschitz conditions.
    method : {"auto", "optimize"}
        Tight mode: the closed form where proven, or always the optimizer.
    progress : Progress, optional

    Raises
    ------
    NoAdmissibleEps
        No ε meets the target (or, as NoCrossing, every supported ε does).
    """
    mode, target, lipschitz = checked_question(mode, target, lipschitz)
    if mode is Mode.tight:
        from .tight.method import tight_eps_star

        return tight_eps_star(quality, lipschitz, method, progress, target)
    return solve_eps_star(quality, mode, target)


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
    target: Target | str = DEFAULT_TARGET,
    lipschitz: float | None = None,
    method: str = "auto",
) -> BoundAt:
    """``mode``'s bound at ``params.eps`` for ``target`` (NaN fraction where a chain is
    undefined)."""
    mode, target, lipschitz = checked_question(mode, target, lipschitz)
    if mode is Mode.tight:
        from .tight.method import tight_bound

        tight = tight_bound(params, lipschitz, method, target)
        limit = params.rho_f if target is Target.ratio else params.target
        return BoundAt(
            mode.value,
            target.value,
            tight.value,
            limit,
            tight.fraction,
            tight.claim,
            tight.method,
            lipschitz,
            tight,
        )
    from .chain import chain_bounds

    chain = chain_bounds(params, mode)
    if target is Target.ratio:
        value, limit = float(chain.ratio_bound), params.rho_f
        fraction = float(chain.share_bound) / float(chain.share_target)
    else:
        value, limit = float(chain.bound), float(chain.target)
        fraction = value / limit
    return BoundAt(
        mode.value,
        target.value,
        value,
        limit,
        fraction,
        CHAIN_CLAIM[mode.value],
        "chain",
        None,
        chain,
    )
