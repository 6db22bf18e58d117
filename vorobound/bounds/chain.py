"""The chain of bounds (33)–(53) on R − R̂ for a VoroCrust guide triangle, printed and corrected.

Setting (Section 4.1): vertices p_i, p_j, p_k with L_i ≤ L_j ≤ L_k, weights δ²L² shifted by the
minimum δ²L_i², so w_B = δ²(L_j² − L_i²), w_C = δ²(L_k² − L_i²); A = p_i, c = |p_i p_j|,
b = |p_i p_k|, a = |p_j p_k|, θ the angle at p_i, and R ≤ ε/(1−ε)·L_i.

``paper`` mode evaluates every step as printed. ``rigorous`` mode replaces the invalid ones
(docs/errata.md, E4–E6):

* eq. (49) bounds a²/(2bc) with the *largest* b c; the valid lower bound on cos θ follows from
  the other two angles, each at least arcsin(k_sin): cos θ ≥ 2 k_sin² − 1;
* eq. (52) then holds with that k_cos;
* a − sqrt(a² − k) = k/(a + sqrt(a² − k)) ≤ min(sqrt(k), k/a) for 0 ≤ k ≤ a², with a ≥ a_min.

The same bound on k also bounds the ratio target R ≤ ρ_f·R̂ of eq. (54): by eq. (30),
(R − R̂)/R = (a − sqrt(a² − k))/a, so (R − R̂)/R ≤ sqrt(k)/a_min as printed (``paper``) and
≤ min(sqrt(k), k/a_min)/a_min (``rigorous``), and R/R̂ ≤ 1/(1 − that) while it is below 1.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields

import numpy as np

from ..checks import EPS_RANGE
from ..errors import InputError
from . import constraints as limits
from .params import Mode, SamplingParams


def _eq(label: str, text: str):
    return field(metadata={"eq": label, "text": text})


@dataclass(frozen=True)
class ChainBounds:
    """Every quantity of the chain (33)–(53), for one mode; arrays broadcast over ε.

    Lengths are in units of L_i times ``lfs`` (i.e. absolute), weights in length².
    """

    mode: str
    eps: np.ndarray = _eq("", "sampling density ε")
    lfs_j_max: np.ndarray = _eq("(33)", "L_j, L_k ≤ (1+ε)/(1−ε)·L_i")
    c_min: np.ndarray = _eq("(34)", "c = |p_i p_j| ≥ σ ε L_i")
    c_max: np.ndarray = _eq("(34)", "c ≤ 2ε/(1−ε)·L_i")
    b_min: np.ndarray = _eq("(35)", "b = |p_i p_k| ≥ σ ε L_i")
    b_max: np.ndarray = _eq("(35)", "b ≤ 2ε/(1−ε)·L_i")
    a_min: np.ndarray = _eq("(36)", "a = |p_j p_k| ≥ σ ε L_i")
    a_max: np.ndarray = _eq("(36)", "a ≤ 2ε(1+ε)/(1−ε)²·L_i")
    weight_max: np.ndarray = _eq("(38)–(40)", "w_B, w_C ≤ (δ/ε)²·4ε³/(1−ε)²·L_i²")
    k1_max: np.ndarray = _eq("(44)", "k1 ≤ 2(w_B + w_C) upper bound")
    k2_min: np.ndarray = _eq("(45)", "k2 lower bound")
    k2_max: np.ndarray = _eq("(45)", "k2 upper bound")
    k_sin: np.ndarray = _eq("(48)", "sin θ ≥ k_sin = σ(1−ε)/2")
    k_cos: np.ndarray = _eq("(49)", "cos θ ≥ k_cos")
    cos_max_acute: np.ndarray = _eq("(51)", "θ ≤ π/2: cos θ ≤ sqrt(1 − k_sin²)")
    sin_min_obtuse: np.ndarray = _eq("(52)", "θ > π/2: sin θ ≥ sqrt(1 − k_cos²)")
    k_max_acute: np.ndarray = _eq("(46)", "θ ≤ π/2: k ≤ UB(k1) + UB(k2)·UB(cos θ)")
    k_max_obtuse: np.ndarray = _eq("(46)", "θ > π/2: k ≤ UB(k1) + LB(k2)·LB(cos θ)")
    bound_acute: np.ndarray = _eq("(29)", "θ ≤ π/2: bound on R − R̂")
    bound_obtuse: np.ndarray = _eq("(29)", "θ > π/2: bound on R − R̂")
    bound: np.ndarray = _eq("(29)", "upper bound on R − R̂ (worse case)")
    gap_allowance: np.ndarray = _eq("(55)", "largest R − R̂ of the additive target: (ρ_f − 1)·δ·L_i")
    share_bound: np.ndarray = _eq("(30)", "upper bound on (R − R̂)/R (worse case)")
    ratio_bound: np.ndarray = _eq("(30), (54)", "upper bound on R/R̂: 1/(1 − that), ∞ from 1 on")
    share_allowance: np.ndarray = _eq("(54)", "largest (R − R̂)/R with R ≤ ρ_f·R̂: 1 − 1/ρ_f")

    def rows(self):
        """(name, equation, description, value) for every quantity, in chain order."""
        for f in fields(self):
            if f.metadata:
                yield f.name, f.metadata["eq"], f.metadata["text"], getattr(self, f.name)


def chain_bounds(params: SamplingParams, mode: Mode | str = Mode.paper, eps=None) -> ChainBounds:
    """Evaluate the chain (33)–(53) for ``params`` (ε taken from ``eps`` if given, may be an array).

    Parameters
    ----------
    params : SamplingParams
        σ, δ/ε, L_i and ρ_f (and ε unless ``eps`` is given).
    mode : {"paper", "rigorous"}
        ``paper``: as printed; ``rigorous``: with the invalid steps replaced.
    eps : float or array_like, optional
        Values of ε (in the supported range of :data:`~vorobound.bounds.params.EPS_RANGE`) to
        evaluate at, overriding ``params.eps``.

    References
    ----------
    Eq. (29), (33)–(53), (55).
    """
    e = np.asarray(params.eps if eps is None else eps, dtype=float)
    low, high = EPS_RANGE
    if not np.all((e >= low) & (e <= high)):  # also rejects NaN
        raise InputError(f"eps must lie in [{low:g}, {high:g}]")
    return chain_arrays(e, params.sigma, params.delta_ratio, params.lfs, params.rho_f, mode)


def chain_arrays(eps, sigma, delta_ratio, lfs, rho_f, mode: Mode | str) -> ChainBounds:
    """The chain with every parameter an array (broadcast together); no validation.

    Used by sweeps over σ, δ/ε and ρ_f; :func:`chain_bounds` is the validated entry point.
    The limits of the constraint set come from :mod:`vorobound.bounds.constraints`.
    """
    mode = Mode(mode)
    if mode is Mode.tight:
        raise InputError("the tight bound is not a chain: use vorobound.bounds.tight")
    e, sigma, ratio, lfs, rho_f = np.broadcast_arrays(
        *(np.asarray(x, dtype=float) for x in (eps, sigma, delta_ratio, lfs, rho_f))
    )
    edge_max = limits.edge_max(e) * lfs
    edge_min = limits.edge_min(e, sigma) * lfs
    lfs_j_max = limits.lfs_max(e) * lfs
    a_max = limits.opposite_edge_max(e) * lfs
    weight_max = limits.weight_max(e, ratio) * lfs**2
    k1_max = 4 * weight_max
    # −2(c w_C/b + b w_B/c) with c, b at their extremes; 2 w_B w_C/(b c) with b, c at the minimum.
    k2_min = -4 * (edge_max / edge_min) * weight_max
    k2_max = 2 * weight_max**2 / edge_min**2
    k_sin = limits.k_sin(e, sigma)
    with np.errstate(invalid="ignore"):
        if mode is Mode.paper:
            one_m = 1 - e
            k_cos = sigma**2 * one_m**2 / 4 - 0.5 * (1 + e) ** 2 / one_m**2
        else:
            k_cos = limits.cos_min(e, sigma)
        cos_max_acute = np.sqrt(1 - k_sin**2)
        sin_min_obtuse = np.sqrt(1 - k_cos**2)
    k_max_acute = k1_max + k2_max * cos_max_acute
    k_max_obtuse = k1_max + k2_min * k_cos
    with np.errstate(invalid="ignore", divide="ignore"):  # sin → 0 at the domain edge: +inf
        if mode is Mode.paper:
            bound_acute = np.sqrt(k_max_acute) / (2 * k_sin)
            bound_obtuse = np.sqrt(k_max_obtuse) / (2 * sin_min_obtuse)
        else:
            # (48) holds for every θ, so the obtuse case may use the better of (48) and (52).
            sin_obtuse = np.fmax(k_sin, sin_min_obtuse)
            bound_acute = _gap_bound(k_max_acute, edge_min) / (2 * k_sin)
            bound_obtuse = _gap_bound(k_max_obtuse, edge_min) / (2 * sin_obtuse)
    bound = np.fmax(bound_acute, bound_obtuse)
    bound = np.where(np.isnan(bound_acute) | np.isnan(bound_obtuse), np.nan, bound)
    k_max = np.fmax(k_max_acute, k_max_obtuse)
    k_max = np.where(np.isnan(k_max_acute) | np.isnan(k_max_obtuse), np.nan, k_max)
    with np.errstate(invalid="ignore", divide="ignore"):
        if mode is Mode.paper:
            share_bound = np.sqrt(k_max) / edge_min  # eq. (30) as printed
        else:
            share_bound = _gap_bound(k_max, edge_min) / edge_min
        ratio_bound = np.where(share_bound < 1, 1 / (1 - share_bound), np.inf)
    ratio_bound = np.where(np.isnan(share_bound), np.nan, ratio_bound)
    return ChainBounds(
        mode=mode.value,
        eps=e,
        lfs_j_max=lfs_j_max,
        c_min=edge_min,
        c_max=edge_max,
        b_min=edge_min,
        b_max=edge_max,
        a_min=edge_min,
        a_max=a_max,
        weight_max=weight_max,
        k1_max=k1_max,
        k2_min=k2_min,
        k2_max=k2_max,
        k_sin=k_sin,
        k_cos=k_cos,
        cos_max_acute=cos_max_acute,
        sin_min_obtuse=sin_min_obtuse,
        k_max_acute=k_max_acute,
        k_max_obtuse=k_max_obtuse,
        bound_acute=bound_acute,
        bound_obtuse=bound_obtuse,
        bound=bound,
        gap_allowance=(rho_f - 1) * ratio * e * lfs,
        share_bound=share_bound,
        ratio_bound=ratio_bound,
        share_allowance=1 - 1 / rho_f,
    )


def _gap_bound(k_max, a_min):
    """Upper bound on a − sqrt(a² − k) given k ≤ k_max and a ≥ a_min.

    a − sqrt(a² − k) = k/(a + sqrt(a² − k)) ≤ k/a ≤ sqrt(k) when 0 ≤ k ≤ a² (and ≤ 0 when
    k < 0), so min(sqrt(k_max), k_max/a_min) bounds it.
    """
    k = np.fmax(k_max, 0)
    return np.fmin(np.sqrt(k), k / a_min)
