"""The data behind the figures: Figure 3 of the paper and the comparison of modes."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..bounds.chain import chain_bounds
from ..bounds.params import Mode, SamplingParams
from ..bounds.eps_star import EpsStar, solve_eps_star

BASELINE_EPS = 1 / 500
"""The sampling density of the original VoroCrust analysis."""


@dataclass(frozen=True)
class Figure3Data:
    """Bound on |R − R̂| against ε for L_i = ``params.lfs`` (Figure 3, paper mode)."""

    eps: np.ndarray
    bound_acute: np.ndarray
    """θ ≤ π/2 case of the chain, eq. (46), (50)–(51)."""
    bound_obtuse: np.ndarray
    """θ > π/2 case of the chain, eq. (46), (52)–(53)."""
    target: np.ndarray
    """(ρ_f − 1)·δ·L_i, eq. (55)."""
    eps_baseline: float
    eps_star: float
    mode: str


@dataclass(frozen=True)
class ModeCurve:
    """bound(ε)/(ε L_i) for one mode, and its ε*."""

    mode: str
    eps: np.ndarray
    bound_over_eps: np.ndarray
    eps_star: float


@dataclass(frozen=True)
class ComparisonData:
    curves: tuple[ModeCurve, ...]
    target_over_eps: float
    """(ρ_f − 1)·(δ/ε): the target divided by ε L_i, constant in ε."""


def figure3_data(params: SamplingParams, mode: Mode | str = Mode.paper, points: int = 400):
    """Curves of Figure 3 on ε ∈ (0, 1.5·max(ε*, 1/500)], both θ cases, and the markers."""
    star = solve_eps_star(params, mode)
    top = 1.5 * max(star.eps_star, BASELINE_EPS)
    eps = np.linspace(top / points, top, points)
    chain = chain_bounds(params, mode, eps=eps)
    return Figure3Data(
        eps=eps,
        bound_acute=chain.bound_acute,
        bound_obtuse=chain.bound_obtuse,
        target=chain.target,
        eps_baseline=BASELINE_EPS,
        eps_star=star.eps_star,
        mode=Mode(mode).value,
    )


COMPARISON_EPS = np.geomspace(1e-4, 0.1, 300)
"""ε grid of the comparison figure (closed-form chains)."""
TIGHT_CURVE_POINTS = 7
"""Optimizations per tight curve (each is a global search, so the curve is sampled coarsely)."""


def chain_curve(params: SamplingParams, mode: Mode | str, eps=COMPARISON_EPS) -> ModeCurve:
    star = solve_eps_star(params, mode)
    chain = chain_bounds(params, mode, eps=eps)
    return ModeCurve(Mode(mode).value, eps, chain.bound / (eps * params.lfs), star.eps_star)


def tight_curve(
    params: SamplingParams, star: EpsStar, lipschitz: float | None, step=None
) -> ModeCurve:
    """Tight supremum / (ε L_i) at a few ε around ε* (``step`` is called once per point)."""
    from ..bounds.tight import tight_supremum

    eps = np.geomspace(star.eps_star / 20, min(3 * star.eps_star, 0.5), TIGHT_CURVE_POINTS)
    values = []
    for e in eps:
        values.append(tight_supremum(params.with_eps(float(e)), lipschitz).supremum)
        if step is not None:
            step()
    name = "tight" if lipschitz is None else f"tight, λ = {lipschitz:g}"
    return ModeCurve(name, eps, np.array(values) / (eps * params.lfs), star.eps_star)


def comparison_data(curves: list[ModeCurve], params: SamplingParams) -> ComparisonData:
    return ComparisonData(tuple(curves), (params.rho_f - 1) * params.delta_ratio)
