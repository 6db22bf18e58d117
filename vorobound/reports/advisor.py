"""Sampling-parameter advice: largest ε per mode, ball radius, spacing, expected sample counts.

Sample counts for a surface S with local feature size L (docs/advisor.md):

* covering (lower) estimate: an ε-sample puts every point within ε L of a sample, and each
  sample's ball covers at most π (ε L)² of the surface, so N ≥ ∫ dA / (π ε² L²);
* packing (upper) estimate: samples are pairwise at least σ ε L apart, so balls of radius
  σ ε L / 2 around them are disjoint, and N ≤ ∫ dA / (π (σ ε L / 2)²) = (4/σ²) × the covering.

On a sphere both are exact bounds: the part of a sphere within chord distance r of one of its
points has area exactly π r² (Archimedes). Elsewhere they are estimates to first order in ε L
over the curvature radius.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..bounds.params import Mode, SamplingParams
from ..bounds.eps_star import solve_eps_star
from .figure_data import BASELINE_EPS
from ..sampling.surfaces import Surface

GUARANTEE = (
    "Covered: with eps <= eps_star every guide triangle has R - R_hat <= (rho_f - 1)*delta*L_i, "
    "so R <= rho_f*delta*L_i (the R - R_hat step of the VoroCrust quality analysis, eq. (54)-(55))"
    ", over all triangles allowed by the constraint set named per mode. Not covered: the rest of "
    "VoroCrust's proof (topology, approximation and other lemmas) may need its own, possibly "
    "smaller, limit on eps; check those conditions separately."
)
CONSTRAINT_SETS = {
    "paper": "the printed chain (33)-(53) (contains an invalid step, docs/errata.md E4)",
    "rigorous": "the corrected chain (33)-(53): any guide triangle of an eps-sampling",
    "tight": "exact supremum over guide triangles allowed by (33)-(36), R <= eps/(1-eps) L_i "
    "and pairwise sparsity",
}


@dataclass(frozen=True)
class ModeAdvice:
    mode: str
    eps_star: float
    ball_radius: float
    """δ·L at the smallest local feature size of the surface."""
    min_spacing: float
    """σ·ε·L at the smallest local feature size."""
    samples_low: float
    samples_high: float
    reduction_vs_1_500: float
    """Sample count at ε = 1/500 divided by the count at ε* (same formula)."""
    constraint_set: str


def covering_count(surface: Surface, eps: float) -> float:
    """∫ dA / (π ε² L²): fewest samples an ε-sample can have (see the module docstring)."""
    return surface.inv_lfs_sq_integral / (math.pi * eps**2)


def packing_count(surface: Surface, eps: float, sigma: float) -> float:
    """∫ dA / (π (σ ε L / 2)²): most samples a σ-sparse sample can have."""
    return surface.inv_lfs_sq_integral / (math.pi * (sigma * eps / 2) ** 2)


def advise(
    params: SamplingParams,
    surface: Surface,
    modes: list[str],
    lipschitz: float | None = None,
    progress: bool = False,
) -> list[ModeAdvice]:
    """Advice for each mode: ε*, ball radius, spacing and sample counts on ``surface``."""
    out = []
    for name in modes:
        mode = Mode(name)
        if mode is Mode.tight:
            from ..bounds.tight import solve_tight

            eps = solve_tight(params, lipschitz=lipschitz, progress=progress).eps_star
            label = "tight" if lipschitz is None else f"tight λ={lipschitz:g}"
            constraint = CONSTRAINT_SETS["tight"] + (
                "" if lipschitz is None else f", plus {lipschitz:g}-Lipschitz L"
            )
        else:
            eps = solve_eps_star(params, mode).eps_star
            label, constraint = mode.value, CONSTRAINT_SETS[mode.value]
        out.append(
            ModeAdvice(
                mode=label,
                eps_star=eps,
                ball_radius=params.delta_ratio * eps * surface.lfs_min,
                min_spacing=params.sigma * eps * surface.lfs_min,
                samples_low=covering_count(surface, eps),
                samples_high=packing_count(surface, eps, params.sigma),
                reduction_vs_1_500=(eps / BASELINE_EPS) ** 2,
                constraint_set=constraint,
            )
        )
    return out
