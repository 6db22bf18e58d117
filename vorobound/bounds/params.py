"""The VoroCrust sampling parameters of Section 4.1, validated once."""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import Enum

from ..errors import VoroboundError


class Mode(str, Enum):
    """Which bound on R − R̂ to use."""

    paper = "paper"
    """The chain (33)–(53) exactly as printed."""
    rigorous = "rigorous"
    """The same chain with every invalid step replaced by a valid one (docs/errata.md)."""
    tight = "tight"
    """The exact supremum over all feasible guide triangles (numerical optimization)."""


@dataclass(frozen=True)
class SamplingParams:
    """ε-sampling parameters of a VoroCrust guide triangle (Section 4.1).

    Attributes
    ----------
    eps : float
        Sampling density ε, 0 < ε < 1.
    sigma : float
        Sparsity σ (paper: 3/4).
    delta_ratio : float
        Ball radius over ε, δ/ε (paper: 2, so δ = 2ε).
    lfs : float
        Local feature size L_i at the minimum-weight vertex.
    rho_f : float
        Quality constant ρ_f > 1 of R ≤ ρ_f δ L_i, eq. (54)–(55) (paper: 1.38).
    """

    eps: float
    sigma: float = 0.75
    delta_ratio: float = 2.0
    lfs: float = 1.0
    rho_f: float = 1.38

    def __post_init__(self) -> None:
        checks = (
            ("eps", 0 < self.eps < 1, "must satisfy 0 < eps < 1"),
            ("sigma", self.sigma > 0, "must be positive"),
            ("delta_ratio", self.delta_ratio > 0, "must be positive"),
            ("lfs", self.lfs > 0, "must be positive"),
            ("rho_f", self.rho_f > 1, "must be greater than 1"),
        )
        for name, ok, why in checks:
            value = getattr(self, name)
            if not isinstance(value, int | float) or not math.isfinite(value) or not ok:
                raise VoroboundError(f"{name} {why}, got {value!r}")

    @property
    def delta(self) -> float:
        """Ball radius factor δ = (δ/ε)·ε."""
        return self.delta_ratio * self.eps

    @property
    def target(self) -> float:
        """Largest admissible R − R̂: (ρ_f − 1)·δ·L_i, from eq. (54)–(55) and R̂ ≤ δ L_i."""
        return (self.rho_f - 1) * self.delta * self.lfs

    def with_eps(self, eps: float) -> SamplingParams:
        return SamplingParams(eps, self.sigma, self.delta_ratio, self.lfs, self.rho_f)
