"""The VoroCrust sampling parameters of Section 4.1 and the question asked of them, validated
once.

:class:`QualityParams` holds everything a bound needs that does not depend on the sampling
density: σ, δ/ε, ρ_f, the length unit L_i, the Lipschitz constant λ of L (if any) and the
quality target. :class:`SamplingParams` adds ε. Every value is checked against its supported
range (:mod:`vorobound.checks`) where the object is made, so that no later product (weights
~ (δ/ε)²ε³L², the allowance (ρ_f − 1)δL_i, ...) overflows or underflows float64; the ranges
are listed in README's notation section.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, replace
from enum import Enum

from ..checks import (
    DELTA_RATIO_RANGE,
    EPS_RANGE,
    RHO_F_MAX,
    SIGMA_RANGE,
    checked_length,
    checked_lipschitz,
    checked_number,
)
from ..constants import PAPER_DELTA_RATIO, PAPER_RHO_F, PAPER_SIGMA
from ..errors import InputError


class Mode(str, Enum):
    """Which bound on R − R̂ to use."""

    paper = "paper"
    """The chain (33)–(53) exactly as printed (invalid: docs/errata.md E4)."""
    rigorous = "rigorous"
    """The chain with every invalid step replaced (proven: docs/errata.md)."""
    tight = "tight"
    """The supremum over the constraint set itself (docs/tight.md says what is proven)."""


class Target(str, Enum):
    """Which quality statement a bound is asked to meet (:mod:`vorobound.bounds.targets`)."""

    additive = "additive"
    """R − R̂ ≤ (ρ_f − 1)·δ·L_i (gives (55) through R̂ ≤ δL_i); the paper's target."""
    ratio = "ratio"
    """R ≤ ρ_f·R̂, eq. (54) (VoroCrust's Lemma 9 as the paper quotes it)."""


class TightMethod(str, Enum):
    """How to evaluate the tight bound."""

    auto = "auto"
    """The closed form where it is proven exact, the optimizer elsewhere."""
    optimize = "optimize"
    """Always the numerical optimizer."""


def checked_mode(mode) -> Mode:
    """``mode`` as a :class:`Mode` (InputError names the choices)."""
    try:
        return Mode(mode)
    except ValueError:
        raise InputError(f"mode must be paper, rigorous or tight, got {mode!r}") from None


def checked_target(target) -> Target:
    """``target`` as a :class:`Target` (InputError names the choices)."""
    try:
        return Target(target)
    except ValueError:
        raise InputError(f"target must be additive or ratio, got {target!r}") from None


def _listed(value) -> list:
    """``"a,b"``, one name, or a sequence of names, as a list (duplicates dropped, order
    kept)."""
    if isinstance(value, str | Enum):
        value = str(getattr(value, "value", value)).split(",")
    elif not isinstance(value, Iterable) or getattr(value, "ndim", None) == 0:
        value = [value]  # one (bad) name, for the check to refuse
    names = [str(getattr(v, "value", v)).strip() for v in value]
    return list(dict.fromkeys(names))


def checked_modes(value) -> tuple[Mode, ...]:
    """Several modes (a comma list or a sequence), each checked."""
    modes = tuple(checked_mode(name) for name in _listed(value))
    if not modes:
        raise InputError("give at least one mode: paper, rigorous or tight")
    return modes


def checked_targets(value) -> tuple[Target, ...]:
    """Several targets (a comma list or a sequence), each checked."""
    targets = tuple(checked_target(name) for name in _listed(value))
    if not targets:
        raise InputError("give at least one target: additive or ratio")
    return targets


@dataclass(frozen=True)
class QualityParams:
    """The ε-free parameters of a VoroCrust quality question (Section 4.1).

    Attributes
    ----------
    sigma : float
        Sparsity σ of the sample (paper: 3/4).
    delta_ratio : float
        Ball radius factor over ε, δ/ε (paper: 2, so δ = 2ε).
    rho_f : float
        Quality constant ρ_f > 1 of R ≤ ρ_f·R̂ (eq. (54)) and R ≤ ρ_f δ L_i (eq. (55))
        (paper: 1.38).
    lfs : float
        Local feature size L_i at the minimum-weight vertex (the length unit; ε* ignores it).
    lipschitz : float or None
        λ of the Lipschitz condition |L_x − L_y| ≤ λ|p_x − p_y| between the vertices of a
        guide triangle, added to the constraint set by the tight mode; None for none.
    target : Target
        The quality statement asked for: ratio (R ≤ ρ_f·R̂, eq. (54); the default) or
        additive (R − R̂ ≤ (ρ_f − 1)·δ·L_i).
    """

    sigma: float = PAPER_SIGMA
    delta_ratio: float = PAPER_DELTA_RATIO
    rho_f: float = PAPER_RHO_F
    lfs: float = 1.0
    lipschitz: float | None = None
    target: Target = Target.ratio

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        set_(self, "sigma", checked_number(self.sigma, "sigma", *SIGMA_RANGE))
        set_(
            self,
            "delta_ratio",
            checked_number(self.delta_ratio, "delta_ratio", *DELTA_RATIO_RANGE),
        )
        set_(self, "rho_f", checked_number(self.rho_f, "rho_f", 1.0, RHO_F_MAX, open_low=True))
        set_(self, "lfs", checked_length(self.lfs, "lfs"))
        set_(self, "lipschitz", checked_lipschitz(self.lipschitz))
        set_(self, "target", checked_target(self.target))

    def at(self, eps: float) -> SamplingParams:
        """These parameters at sampling density ``eps``."""
        return SamplingParams(eps, self)

    def but(self, **changes) -> QualityParams:
        """A copy with some fields changed (validated like a new object)."""
        return replace(self, **changes)

    @property
    def share_allowance(self) -> float:
        """1 − 1/ρ_f: the largest (R − R̂)/R the ratio target R ≤ ρ_f·R̂ allows (eq. (54))."""
        return 1 - 1 / self.rho_f

    def as_dict(self) -> dict:
        """σ, δ/ε, ρ_f, L_i, λ and the target as plain JSON values (the ``params`` object)."""
        return {
            "sigma": self.sigma,
            "delta_ratio": self.delta_ratio,
            "rho_f": self.rho_f,
            "lfs": self.lfs,
            "lipschitz": self.lipschitz,
            "target": self.target.value,
        }


@dataclass(frozen=True)
class SamplingParams:
    """A sampling density ε together with the quality parameters.

    Attributes
    ----------
    eps : float
        Sampling density ε: every surface point x has a sample within ε·L(x).
    quality : QualityParams
        σ, δ/ε, ρ_f, L_i, λ and the target.
    """

    eps: float
    quality: QualityParams = QualityParams()

    def __post_init__(self) -> None:
        object.__setattr__(self, "eps", checked_number(self.eps, "eps", *EPS_RANGE))
        if not isinstance(self.quality, QualityParams):
            raise InputError(f"quality must be QualityParams, got {type(self.quality).__name__}")

    sigma = property(lambda self: self.quality.sigma, doc="Sparsity σ.")
    delta_ratio = property(lambda self: self.quality.delta_ratio, doc="δ/ε.")
    rho_f = property(lambda self: self.quality.rho_f, doc="Quality constant ρ_f.")
    lfs = property(lambda self: self.quality.lfs, doc="Local feature size L_i.")
    lipschitz = property(lambda self: self.quality.lipschitz, doc="λ of L, or None.")
    target = property(lambda self: self.quality.target, doc="The quality target.")
    share_allowance = property(lambda self: self.quality.share_allowance, doc="1 − 1/ρ_f.")

    @property
    def delta(self) -> float:
        """Ball radius factor δ = (δ/ε)·ε: ball radii are δ·L (Section 4.1)."""
        return self.quality.delta_ratio * self.eps

    @property
    def gap_allowance(self) -> float:
        """Largest admissible R − R̂ of the additive target: (ρ_f − 1)·δ·L_i, from eq.
        (54)–(55) and R̂ ≤ δ L_i."""
        return (self.rho_f - 1) * self.delta * self.lfs

    @property
    def limit(self) -> float:
        """What a bound is compared with: ρ_f (ratio target, a bound on R/R̂) or
        (ρ_f − 1)·δ·L_i (additive target, a bound on R − R̂)."""
        return self.rho_f if self.target is Target.ratio else self.gap_allowance

    def with_eps(self, eps: float) -> SamplingParams:
        """The same quality parameters at another ε."""
        return SamplingParams(eps, self.quality)

    def but(self, **changes) -> SamplingParams:
        """The same ε with some quality fields changed."""
        return SamplingParams(self.eps, self.quality.but(**changes))

    def as_dict(self) -> dict:
        """ε and the quality parameters as plain JSON values."""
        return {"eps": self.eps, **self.quality.as_dict()}
