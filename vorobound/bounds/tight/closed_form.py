"""The tight supremum of R − R̂ and the tight ε* in closed form (proven in docs/tight.md).

Over the constraint set of :mod:`vorobound.bounds.constraints` (units L_i = 1, r = δ/ε):

    sup (R − R̂) = min(1, μ*) · ε/(1−ε),   μ* = r²·X(2 + X)/σ²,
    X = (1+ε)/(1−ε) − 1 = 2ε/(1−ε), or min(2ε/(1−ε), λσε) with a Lipschitz constant λ.

μ* is the largest shifted weight δ²(L² − L_i²) over the squared shortest edge (σεL_i)²; μ* ≥ 1
is the plateau where the weights can move the orthocenter onto p_i (R̂ = 0) and the supremum is
H3's circumradius bound. The upper bound holds for every parameter set; it is attained by the
isosceles vertex b = c = σεL_i, L_j = L_k = L_i(1 + x), R = ε/(1−ε)·L_i (x = X below the
plateau, else the excess that makes μ = 1) whenever that vertex satisfies the sparsity of its
opposite edge, 2·sqrt(1 − k_sin²) ≥ 1 + x with k_sin = σ(1−ε)/2 (eq. (36) with min(L_j, L_k)).
Then the closed form is the exact supremum (:attr:`ClosedFormStatus.exact`); otherwise it is a
proven upper bound only, and the tight ε* it gives is a proven lower bound on the true one.

References
----------
Theorem 1 (eq. (16), (25)–(26)), eq. (33)–(37), (48), (54)–(55), property H3 of Section 4.1.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import Enum

import numpy as np

from ...checks import (
    DELTA_RATIO_RANGE,
    EPS_RANGE,
    LFS_RANGE,
    RHO_F_MAX,
    SIGMA_RANGE,
    checked_lipschitz,
    checked_number,
)
from ...errors import NoAdmissibleEps, NoCrossing
from .. import constraints
from ..configurations import GuideConfiguration
from ..roots import largest_root

VERTEX_MARGIN_RTOL = 1e-12
"""The worst vertex counts as feasible (the closed form as exact) only if the sparsity of its
opposite edge holds with this relative margin, so rounding cannot turn a bound into an exact
claim."""


class ClosedFormStatus(str, Enum):
    """How strong the closed form's claim is for one parameter set (both are proven)."""

    exact = "proven exact"
    """The supremum itself: the isosceles vertex is feasible and attains it."""
    upper_bound = "proven upper bound"
    """An upper bound only: the vertex violates the sparsity of its opposite edge (σ(1−ε)
    near √3, or a large excess of L_j over L_i at large ε)."""


@dataclass(frozen=True)
class ClosedFormSupremum:
    """sup(R − R̂) over the constraint set at one ε, in closed form."""

    value: float
    """min(1, μ*)·ε/(1−ε)·L_i (absolute units): the supremum or a proven upper bound on it."""
    status: ClosedFormStatus
    plateau: bool
    """True when μ* ≥ 1: the bound is H3's circumradius ε/(1−ε)·L_i, reached with R̂ = 0."""
    weight_ratio: float
    """μ* = r²X(2 + X)/σ²: the largest shifted weight over (σεL_i)² (see the module docstring)."""
    maximizer: GuideConfiguration
    """The isosceles vertex; a worst feasible configuration when ``status`` is exact, otherwise
    the (infeasible) configuration the bound comes from."""
    eps: float
    sigma: float
    delta_ratio: float
    lfs: float
    lipschitz: float | None


@dataclass(frozen=True)
class ClosedFormEpsStar:
    """The tight ε* in closed form: the root of sup(R − R̂)/((ρ_f − 1)δL_i) = 1."""

    eps_star: float
    """The root; every ε ≤ ε* keeps sup(R − R̂) ≤ (ρ_f − 1)δL_i (proven), and it is the tight ε*
    itself when ``status`` is exact."""
    status: ClosedFormStatus
    supremum: ClosedFormSupremum
    """The closed form at ε* (its maximizer is the worst guide triangle there)."""
    residual: float
    """sup(R − R̂)/target − 1 at ε* (rounding only)."""
    rho_f: float


def lfs_excess_max(eps, sigma: float, lipschitz: float | None = None):
    """X = max (L_j − L_i)/L_i: 2ε/(1−ε) from eq. (33), or min(that, λσε) with λ.

    With λ the excess at the worst vertex is capped by L_j − L_i ≤ λc at c = σεL_i. ``eps`` may
    be a float or an array of values in (0, 1).
    """
    span = 2 * eps / (1 - eps)
    return span if lipschitz is None else np.minimum(span, lipschitz * sigma * eps)


def weight_ratio(eps, sigma: float, delta_ratio: float, lipschitz: float | None = None):
    """μ* = (δ/ε)²·X(2 + X)/σ² = max w/(σεL_i)², w the shifted weight of eq. (37)."""
    excess = lfs_excess_max(eps, sigma, lipschitz)
    return (delta_ratio / sigma) ** 2 * excess * (2 + excess)


def tight_ratio_closed_form(
    eps, sigma: float, delta_ratio: float, rho_f: float, lipschitz: float | None = None
):
    """sup(R − R̂)/((ρ_f − 1)δL_i) = min(1, μ*)/((1−ε)(ρ_f − 1)δ/ε) (floats or arrays of ε).

    Increasing in ε, from 0 at ε → 0; an upper bound everywhere, the exact ratio where
    :func:`closed_form_is_exact` holds.
    """
    capped = np.minimum(1.0, weight_ratio(eps, sigma, delta_ratio, lipschitz))
    return capped / ((1 - eps) * (rho_f - 1) * delta_ratio)


def _vertex_excess(eps: float, sigma: float, delta_ratio: float, lipschitz: float | None):
    """(x, plateau): the excess (L − L_i)/L_i of the worst vertex, and whether μ* ≥ 1."""
    excess = float(lfs_excess_max(eps, sigma, lipschitz))
    plateau = float(weight_ratio(eps, sigma, delta_ratio, lipschitz)) >= 1
    if plateau:
        # x(2 + x) = (σ/r)²: the weight that makes w = (σε)², written without cancellation.
        q = (sigma / delta_ratio) ** 2
        excess = min(excess, q / (1 + math.sqrt(1 + q)))
    return excess, plateau


def closed_form_is_exact(
    eps: float, sigma: float, delta_ratio: float, lipschitz: float | None = None
) -> bool:
    """True where docs/tight.md proves the closed form to be the supremum itself.

    That is where the isosceles vertex is feasible: 4(1 − k_sin²) ≥ (1 + x)², the sparsity
    σε·min(L_j, L_k) ≤ a of eq. (36) at b = c = σεL_i, R = ε/(1−ε)·L_i (with a relative margin
    :data:`VERTEX_MARGIN_RTOL`). Elsewhere the closed form is a proven upper bound.
    """
    eps, sigma, delta_ratio, _, lipschitz = _checked(eps, sigma, delta_ratio, 1.0, lipschitz)
    if constraints.is_empty(eps, sigma):
        return False
    return _vertex_feasible(eps, sigma, delta_ratio, lipschitz)


def _vertex_feasible(eps, sigma, delta_ratio, lipschitz) -> bool:
    k_sin = sigma * (1 - eps) / 2
    excess, _ = _vertex_excess(eps, sigma, delta_ratio, lipschitz)
    return 4 * (1 - k_sin) * (1 + k_sin) >= (1 + excess) ** 2 * (1 + VERTEX_MARGIN_RTOL)


def tight_supremum_closed_form(
    eps: float,
    sigma: float,
    delta_ratio: float,
    lfs: float = 1.0,
    lipschitz: float | None = None,
) -> ClosedFormSupremum:
    """sup(R − R̂) over every guide triangle of the constraint set at ``eps``, in closed form.

    Parameters
    ----------
    eps : float
        Sampling density ε in the supported range of :mod:`vorobound.bounds.params`.
    sigma, delta_ratio, lfs : float
        σ, δ/ε and L_i; σ(1−ε) ≤ √3 is required (else no guide triangle is feasible).
    lipschitz : float, optional
        λ ≥ 0 of the Lipschitz conditions |L_x − L_y| ≤ λ|p_x − p_y|.

    Returns
    -------
    ClosedFormSupremum
        The value, whether it is exact or an upper bound, and the worst vertex.

    References
    ----------
    Eq. (16), (25)–(26), (33)–(37), (48), property H3; the proof is in docs/tight.md.
    """
    eps, sigma, delta_ratio, lfs, lipschitz = _checked(eps, sigma, delta_ratio, lfs, lipschitz)
    constraints.require_guide_triangles(eps, sigma)
    k_sin = sigma * (1 - eps) / 2
    mu = float(weight_ratio(eps, sigma, delta_ratio, lipschitz))
    excess, plateau = _vertex_excess(eps, sigma, delta_ratio, lipschitz)
    exact = _vertex_feasible(eps, sigma, delta_ratio, lipschitz)
    edge = sigma * eps * lfs
    weight = (delta_ratio * eps * lfs) ** 2 * excess * (2 + excess)
    vertex = GuideConfiguration(
        b=edge,
        c=edge,
        theta=2 * math.acos(k_sin),
        lfs_j=lfs * (1 + excess),
        lfs_k=lfs * (1 + excess),
        excess_j=excess,
        excess_k=excess,
        a=2 * edge * math.sqrt((1 - k_sin) * (1 + k_sin)),
        circumradius=eps / (1 - eps) * lfs,
        w_b=weight,
        w_c=weight,
    )
    return ClosedFormSupremum(
        value=min(1.0, mu) * eps / (1 - eps) * lfs,
        status=ClosedFormStatus.exact if exact else ClosedFormStatus.upper_bound,
        plateau=plateau,
        weight_ratio=mu,
        maximizer=vertex,
        eps=eps,
        sigma=sigma,
        delta_ratio=delta_ratio,
        lfs=lfs,
        lipschitz=lipschitz,
    )


def tight_eps_star_closed_form(
    sigma: float, delta_ratio: float, rho_f: float, lipschitz: float | None = None
) -> ClosedFormEpsStar:
    """The tight ε*: the root of min(1, μ*(ε)) = (1−ε)(ρ_f − 1)δ/ε (tens of microseconds).

    Both sides are monotone (the left increases, the right decreases), so the root is unique
    and every smaller ε meets the target.

    Parameters
    ----------
    sigma, delta_ratio, rho_f : float
        σ, δ/ε and ρ_f > 1 (InputError if no guide triangle is feasible at the root).
    lipschitz : float, optional
        λ > 0 of the Lipschitz conditions (λ = 0 makes R − R̂ = 0: no root).

    Returns
    -------
    ClosedFormEpsStar
        ε*, whether it is the tight ε* itself or a proven lower bound on it, and the closed
        form there.

    References
    ----------
    Eq. (54)–(55); the supremum of :func:`tight_supremum_closed_form`.
    """
    sigma, delta_ratio, _, lipschitz = _checked_quality(sigma, delta_ratio, 1.0, lipschitz)
    rho_f = checked_number(rho_f, "rho_f", 1.0, RHO_F_MAX, open_low=True)
    scale = (rho_f - 1) * delta_ratio

    def gap(eps: float) -> float:
        """min(1, μ*) − (1−ε)(ρ_f − 1)δ/ε: increasing, with the sign of ratio − 1."""
        return min(1.0, weight_ratio(eps, sigma, delta_ratio, lipschitz)) - (1 - eps) * scale

    low, high = EPS_RANGE
    if gap(low) > 0:
        raise NoAdmissibleEps(
            f"the tight bound exceeds the target already at eps = {low:g}: no admissible eps"
        )
    if gap(high) <= 0:
        raise NoCrossing(
            f"the tight bound stays within the target up to eps = {high:g}: "
            "no crossing, so no eps* in the supported range"
        )
    root, _ = largest_root(gap, low, high)  # gap(root) ≤ 0: the ε* printed meets the target
    constraints.require_guide_triangles(root, sigma)
    supremum = tight_supremum_closed_form(root, sigma, delta_ratio, 1.0, lipschitz)
    ratio = float(tight_ratio_closed_form(root, sigma, delta_ratio, rho_f, lipschitz))
    return ClosedFormEpsStar(
        eps_star=root,
        status=supremum.status,
        supremum=supremum,
        residual=ratio - 1,
        rho_f=rho_f,
    )


def _checked_quality(sigma, delta_ratio, lfs, lipschitz):
    return (
        checked_number(sigma, "sigma", *SIGMA_RANGE),
        checked_number(delta_ratio, "delta_ratio", *DELTA_RATIO_RANGE),
        checked_number(lfs, "lfs", *LFS_RANGE),
        checked_lipschitz(lipschitz),
    )


def _checked(eps, sigma, delta_ratio, lfs, lipschitz):
    eps = checked_number(eps, "eps", *EPS_RANGE)
    return (eps, *_checked_quality(sigma, delta_ratio, lfs, lipschitz))
