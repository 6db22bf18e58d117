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

from ..bounds.eps_star import EpsStar, solve_eps_star
from ..bounds.params import Mode, QualityParams, checked_lipschitz
from ..constants import BASELINE_EPS
from ..errors import InputError
from ..progress import Progress
from ..sampling.surfaces import Surface

GUARANTEE = (
    "What eps <= eps_star gives: every guide triangle of the mode's constraint set has "
    "R - R_hat <= (rho_f - 1)*delta*L_i, so R <= rho_f*delta*L_i (the R - R_hat step of the "
    "VoroCrust quality analysis, eq. (54)-(55)), with the strength stated per mode: proven "
    "(algebra in docs/errata.md or docs/tight.md), certified (an interval certificate, "
    "`vorobound certify`), numerical (optimizer evidence only) or invalid (the printed chain). "
    "Not covered: the rest of VoroCrust's proof (topology, approximation and other lemmas) may "
    "need its own, possibly smaller, limit on eps; check those conditions separately."
)
CONSTRAINT_SETS = {
    "paper": "the printed chain (33)-(53)",
    "rigorous": "the corrected chain (33)-(53), valid for any guide triangle of an eps-sample",
    "tight": "the supremum over guide triangles allowed by (33)-(36), R <= eps/(1-eps) L_i "
    "and pairwise sparsity (closed form, docs/tight.md)",
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
    """Which guide triangles the bound covers."""
    claim: str
    """Strength of ε*: proven, certified, numerical or invalid (:mod:`vorobound.bounds.claims`)."""
    method: str
    """How ε* was found (chain, closed form, optimizer)."""


def covering_count(surface: Surface, eps: float) -> float:
    """∫ dA / (π ε² L²): fewest samples an ε-sample can have (see the module docstring)."""
    return _finite_count(surface.inv_lfs_sq_integral / (math.pi * eps**2), surface)


def packing_count(surface: Surface, eps: float, sigma: float) -> float:
    """∫ dA / (π (σ ε L / 2)²): most samples a σ-sparse sample can have."""
    return _finite_count(surface.inv_lfs_sq_integral / (math.pi * (sigma * eps / 2) ** 2), surface)


def _finite_count(count: float, surface: Surface) -> float:
    if not math.isfinite(count):
        raise InputError(f"the sample count for {surface.name} overflows: no advice possible")
    return count


def solve_mode(
    quality: QualityParams, mode: Mode | str, lipschitz: float | None, progress: Progress | None
) -> EpsStar:
    """ε* of one mode (the tight mode through :func:`vorobound.bounds.tight.method`)."""
    mode = Mode(mode)
    if mode is Mode.tight:
        from ..bounds.tight import method

        return method.tight_eps_star(quality, lipschitz, progress=progress)
    return solve_eps_star(quality, mode)


def advise(
    quality: QualityParams,
    surface: Surface,
    modes: list[str],
    lipschitz: float | None = None,
    progress: Progress | None = None,
) -> list[ModeAdvice]:
    """Advice for each mode: ε*, ball radius, spacing and sample counts on ``surface``."""
    lipschitz = checked_lipschitz(lipschitz)
    for name, value in (("area", surface.area), ("integral of 1/L²", surface.inv_lfs_sq_integral)):
        if not (math.isfinite(value) and value > 0):
            raise InputError(f"{surface.name}: its {name} is not a positive finite number")
    out = []
    for name in dict.fromkeys(modes):  # each mode once, in the order given
        mode = Mode(name)
        star = solve_mode(quality, mode, lipschitz, progress)
        label, constraint = mode.value, CONSTRAINT_SETS[mode.value]
        if mode is Mode.tight and lipschitz is not None:
            label = f"tight λ={lipschitz:g}"
            constraint += f", plus {lipschitz:g}-Lipschitz L"
        eps = star.eps_star
        out.append(
            ModeAdvice(
                mode=label,
                eps_star=eps,
                ball_radius=quality.delta_ratio * eps * surface.lfs_min,
                min_spacing=quality.sigma * eps * surface.lfs_min,
                samples_low=covering_count(surface, eps),
                samples_high=packing_count(surface, eps, quality.sigma),
                reduction_vs_1_500=(eps / BASELINE_EPS) ** 2,
                constraint_set=constraint,
                claim=star.claim,
                method=star.method,
            )
        )
    return out
