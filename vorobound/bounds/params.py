"""The VoroCrust sampling parameters of Section 4.1, validated once.

:class:`QualityParams` holds what does not depend on the sampling density (σ, δ/ε, ρ_f and the
length unit L_i); :class:`SamplingParams` adds ε. Every value is checked against a supported
range here, so that no later product (weights ~ (δ/ε)²ε³L², the target (ρ_f − 1)δL_i, ...)
overflows or underflows float64; the ranges are listed in README's notation section.
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass
from enum import Enum

from ..checks import checked_number
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


EPS_RANGE = (1e-12, 0.999)
"""Supported sampling densities ε (1 − ε ≥ 10⁻³ keeps every (1 − ε)⁻ᵏ of the chain small)."""
SIGMA_RANGE = (1e-6, 1e3)
"""Supported sparsity factors σ (σ ≥ 2 leaves no feasible guide triangle at small ε)."""
DELTA_RATIO_RANGE = (1e-6, 1e6)
"""Supported δ/ε (weights scale as (δ/ε)²)."""
RHO_F_MAX = 1e6
"""Largest supported quality constant ρ_f (ρ_f > 1 is required)."""
LFS_RANGE = (1e-50, 1e50)
"""Supported local feature sizes L_i (the chain multiplies up to four lengths)."""
LIPSCHITZ_RANGE = (1e-12, 1e6)
"""Supported positive Lipschitz constants λ (λ = 0, constant L, is supported too)."""


def checked_lipschitz(value) -> float | None:
    """λ as a float (0 allowed), or None for "no Lipschitz condition"; else raise InputError."""
    if value is None:
        return None
    if isinstance(value, numbers.Real) and not isinstance(value, bool) and value == 0:
        return 0.0
    return checked_number(value, "lipschitz", *LIPSCHITZ_RANGE)


@dataclass(frozen=True)
class QualityParams:
    """The ε-free parameters of a VoroCrust quality target (Section 4.1).

    Attributes
    ----------
    sigma : float
        Sparsity σ of the sample (paper: 3/4).
    delta_ratio : float
        Ball radius factor over ε, δ/ε (paper: 2, so δ = 2ε).
    rho_f : float
        Quality constant ρ_f > 1 of R ≤ ρ_f δ L_i, eq. (54)–(55) (paper: 1.38).
    lfs : float
        Local feature size L_i at the minimum-weight vertex (the length unit; ε* ignores it).
    """

    sigma: float = PAPER_SIGMA
    delta_ratio: float = PAPER_DELTA_RATIO
    rho_f: float = PAPER_RHO_F
    lfs: float = 1.0

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        set_(self, "sigma", checked_number(self.sigma, "sigma", *SIGMA_RANGE))
        set_(
            self,
            "delta_ratio",
            checked_number(self.delta_ratio, "delta_ratio", *DELTA_RATIO_RANGE),
        )
        set_(self, "rho_f", checked_number(self.rho_f, "rho_f", 1.0, RHO_F_MAX, open_low=True))
        set_(self, "lfs", checked_number(self.lfs, "lfs", *LFS_RANGE))

    def at(self, eps: float) -> SamplingParams:
        """These parameters at sampling density ``eps``."""
        return SamplingParams(eps, self)


@dataclass(frozen=True)
class SamplingParams:
    """A sampling density ε together with the quality parameters.

    Attributes
    ----------
    eps : float
        Sampling density ε: every surface point x has a sample within ε·L(x).
    quality : QualityParams
        σ, δ/ε, ρ_f and L_i.
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

    @property
    def delta(self) -> float:
        """Ball radius factor δ = (δ/ε)·ε: ball radii are δ·L (Section 4.1)."""
        return self.quality.delta_ratio * self.eps

    @property
    def target(self) -> float:
        """Largest admissible R − R̂: (ρ_f − 1)·δ·L_i, from eq. (54)–(55) and R̂ ≤ δ L_i."""
        return (self.rho_f - 1) * self.delta * self.lfs

    def with_eps(self, eps: float) -> SamplingParams:
        """The same quality parameters at another ε."""
        return SamplingParams(eps, self.quality)
