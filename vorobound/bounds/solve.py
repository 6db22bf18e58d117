"""The largest ε whose bound on R − R̂ stays within the quality target (ρ_f − 1)·δ·L_i."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..errors import VoroboundError
from .chain import chain_bounds
from .params import Mode, SamplingParams

SCAN_GRID = np.geomspace(1e-7, 0.999, 600)
"""ε values scanned for the first crossing of bound and target (log-spaced)."""
XTOL = 1e-15
RTOL = 1e-13


@dataclass(frozen=True)
class EpsStar:
    """Result of the ε* root finder."""

    eps_star: float
    """Largest ε with bound(ε) ≤ (ρ_f − 1)·δ·L_i (the first crossing above the scan start)."""
    mode: str
    params: SamplingParams
    residual: float
    """bound(ε*) − target(ε*), relative to the target."""
    iterations: int
    bracket: tuple[float, float]
    """The scan cell in which brentq found the root."""
    maximizer: dict | None = None
    """For the tight mode: the worst guide triangle at ε*."""


def relative_gap_function(params: SamplingParams, mode: Mode | str) -> Callable:
    """ε ↦ bound(ε)/target(ε) − 1 for the closed-form chains (vectorized)."""

    def gap(eps):
        chain = chain_bounds(params, mode, eps=eps)
        ratio = chain.bound / chain.target - 1
        return np.where(np.isnan(ratio), np.inf, ratio)

    return gap


def find_eps_star(gap: Callable, mode: str, params: SamplingParams, grid=SCAN_GRID) -> EpsStar:
    """Scan ``grid`` for the first ε where ``gap`` turns positive, then refine with brentq.

    ``gap`` must accept an array of ε (for the scan) and a float (for brentq).
    """
    from scipy.optimize import brentq

    values = np.asarray(gap(grid), dtype=float)
    if values[0] > 0:
        raise VoroboundError(
            f"the {mode} bound exceeds the target already at eps = {grid[0]:g}: no admissible eps"
        )
    above = np.flatnonzero(values > 0)
    if above.size == 0:
        raise VoroboundError(
            f"the {mode} bound stays within the target for all eps in (0, 1): no crossing"
        )
    hi_index = int(above[0])
    lo, hi = float(grid[hi_index - 1]), float(grid[hi_index])
    root, info = brentq(lambda x: float(gap(x)), lo, hi, xtol=XTOL, rtol=RTOL, full_output=True)
    return EpsStar(
        eps_star=float(root),
        mode=mode,
        params=params.with_eps(root),
        residual=float(gap(root)),
        iterations=int(info.iterations),
        bracket=(lo, hi),
    )


def solve_eps_star(params: SamplingParams, mode: Mode | str = Mode.paper) -> EpsStar:
    """Largest ε keeping the chosen bound on R − R̂ within (ρ_f − 1)·δ·L_i.

    Parameters
    ----------
    params : SamplingParams
        σ, δ/ε, L_i and ρ_f (its ε is ignored).
    mode : {"paper", "rigorous"}
        Which closed-form chain to use; the tight mode lives in :mod:`vorobound.bounds.tight`.

    References
    ----------
    Eq. (29), (33)–(55); Figure 3.
    """
    mode = Mode(mode)
    if mode is Mode.tight:
        from .tight import solve_tight

        return solve_tight(params)
    return find_eps_star(relative_gap_function(params, mode), mode.value, params)
