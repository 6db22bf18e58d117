"""Checking each inequality of the chain (33)–(53) against exact quantities, and counterexamples."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import constraints
from .chain import ChainBounds, chain_bounds
from .configurations import GuideTriangles
from .params import Mode, SamplingParams

AUDIT_RTOL = 1e-9
"""Relative excess over a bound that counts as a violation (rounding is far below this)."""
COUNTEREXAMPLE_SHRINK = 1e-9
"""The counterexample's angle is taken this much (relatively) inside the largest feasible one."""


@dataclass(frozen=True)
class InequalityAudit:
    """How one printed inequality fared on a batch of feasible configurations."""

    label: str
    """Equation label, e.g. ``"(49)"``."""
    statement: str
    checked: int
    violations: int
    worst_ratio: float
    """Largest value/bound in the violating direction, 1 + (excess / |bound|); > 1 violates."""


@dataclass(frozen=True)
class ExactQuantities:
    """The chain's quantities for actual configurations (arrays of one shape)."""

    a: np.ndarray
    """|p_j p_k|, eq. (7)."""
    b: np.ndarray
    """|p_i p_k|, eq. (8)."""
    c: np.ndarray
    """|p_i p_j|, eq. (9)."""
    w_b: np.ndarray
    """δ²(L_j² − L_i²), eq. (37)."""
    w_c: np.ndarray
    """δ²(L_k² − L_i²), eq. (37)."""
    k1: np.ndarray
    """Eq. (42)."""
    k2: np.ndarray
    """Eq. (43)."""
    k: np.ndarray
    """k1 + k2 cos θ, eq. (41)."""
    sin: np.ndarray
    """sin θ."""
    cos: np.ndarray
    """cos θ."""
    acute: np.ndarray
    """θ ≤ π/2."""
    lfs_j: np.ndarray
    lfs_k: np.ndarray
    radius_gap: np.ndarray
    """R − R̂ by Theorem 1 (the exact value the chain bounds), eq. (29)."""


def exact_quantities(tri: GuideTriangles, params: SamplingParams) -> ExactQuantities:
    """Edges, weights, k1, k2, k, θ and R − R̂ of actual configurations."""
    w_b, w_c = tri.weights(params)
    lfs_j, lfs_k = tri.lfs(params)
    b, c, cos_t = tri.b, tri.c, np.cos(tri.theta)
    k1 = 2 * (w_b + w_c) - (w_b / c) ** 2 - (w_c / b) ** 2
    k2 = -2 * (c * w_c / b + b * w_b / c - w_b * w_c / (b * c))
    return ExactQuantities(
        a=tri.a,
        b=b,
        c=c,
        w_b=w_b,
        w_c=w_c,
        k1=k1,
        k2=k2,
        k=k1 + k2 * cos_t,
        sin=np.sin(tri.theta),
        cos=cos_t,
        acute=tri.theta <= np.pi / 2,
        lfs_j=lfs_j,
        lfs_k=lfs_k,
        radius_gap=tri.radius_gap(params),
    )


def _checks(q: ExactQuantities, ch: ChainBounds, delta_ratio: float):
    """(label, statement, value, bound, 'upper'|'lower', mask) for every inequality."""
    acute, obtuse = q.acute, ~q.acute
    everywhere = np.ones_like(acute)
    weight = f"w ≤ (δ/ε)²·4ε³/(1−ε)²·L_i² (δ/ε = {delta_ratio:g})"
    return [
        ("(33)", "L_j ≤ (1+ε)/(1−ε) L_i", q.lfs_j, ch.lfs_j_max, "upper", everywhere),
        ("(33)", "L_k ≤ (1+ε)/(1−ε) L_i", q.lfs_k, ch.lfs_j_max, "upper", everywhere),
        ("(34)", "c ≥ σεL_i", q.c, ch.c_min, "lower", everywhere),
        ("(34)", "c ≤ 2ε/(1−ε) L_i", q.c, ch.c_max, "upper", everywhere),
        ("(35)", "b ≥ σεL_i", q.b, ch.b_min, "lower", everywhere),
        ("(35)", "b ≤ 2ε/(1−ε) L_i", q.b, ch.b_max, "upper", everywhere),
        ("(36)", "a ≥ σεL_i", q.a, ch.a_min, "lower", everywhere),
        ("(36)", "a ≤ 2ε(1+ε)/(1−ε)² L_i", q.a, ch.a_max, "upper", everywhere),
        ("(39)", weight.replace("w ", "w_B "), q.w_b, ch.weight_max, "upper", everywhere),
        ("(40)", weight.replace("w ", "w_C "), q.w_c, ch.weight_max, "upper", everywhere),
        ("(44)", "k1 ≤ UB(k1)", q.k1, ch.k1_max, "upper", everywhere),
        ("(45)", "k2 ≥ LB(k2)", q.k2, ch.k2_min, "lower", everywhere),
        ("(45)", "k2 ≤ UB(k2)", q.k2, ch.k2_max, "upper", everywhere),
        ("(46)", "θ ≤ π/2: k ≤ UB", q.k, ch.k_max_acute, "upper", acute),
        ("(46)", "θ > π/2: k ≤ UB", q.k, ch.k_max_obtuse, "upper", obtuse),
        ("(48)", "sin θ ≥ k_sin", q.sin, ch.k_sin, "lower", everywhere),
        ("(49)", "cos θ ≥ k_cos", q.cos, ch.k_cos, "lower", everywhere),
        ("(51)", "θ ≤ π/2: cos θ ≤ sqrt(1 − k_sin²)", q.cos, ch.cos_max_acute, "upper", acute),
        ("(52)", "θ > π/2: sin θ ≥ sqrt(1 − k_cos²)", q.sin, ch.sin_min_obtuse, "lower", obtuse),
        ("(53)", "θ > π/2: cos θ ≥ k_cos", q.cos, ch.k_cos, "lower", obtuse),
        ("bound", "R − R̂ ≤ final bound", q.radius_gap, ch.bound, "upper", everywhere),
    ]


def audit_chain(
    tri: GuideTriangles, params: SamplingParams, mode: Mode | str = Mode.paper
) -> list[InequalityAudit]:
    """Evaluate every inequality of the chain on the configurations ``tri``.

    Parameters
    ----------
    tri : GuideTriangles
        Feasible configurations (see :func:`vorobound.bounds.feasible.sample_feasible`).
    params : SamplingParams
        The parameters they were sampled for.
    mode : {"paper", "rigorous"}
        Which chain's bounds to audit.
    """
    q = exact_quantities(tri, params)
    ch = chain_bounds(params, mode)
    audits = []
    for label, statement, value, bound, kind, mask in _checks(q, ch, params.delta_ratio):
        value = np.asarray(value)[mask]
        bound = float(bound)
        excess = (value - bound) if kind == "upper" else (bound - value)
        scale = abs(bound) if bound != 0 else 1.0
        ratio = 1 + excess / scale
        worst = float(ratio.max()) if ratio.size else float("nan")
        audits.append(
            InequalityAudit(
                label, statement, int(value.size), int((ratio > 1 + AUDIT_RTOL).sum()), worst
            )
        )
    return audits


@dataclass(frozen=True)
class StepCounterexample:
    """A feasible guide triangle for which one printed step fails."""

    label: str
    statement: str
    triangle: GuideTriangles
    value: float
    bound: float


def printed_step_counterexamples(params: SamplingParams) -> list[StepCounterexample]:
    """Feasible configurations violating the invalid printed steps (49) and (52).

    The triangle: b = c = σεL_i (the shortest edges sparsity allows) and the largest angle at
    A that keeps R ≤ ε/(1−ε)·L_i, θ = 2·arccos(σ(1−ε)/2), shrunk by COUNTEREXAMPLE_SHRINK to stay
    inside. Then cos θ = 2k_sin² − 1 < k_cos as printed, and sin θ < sqrt(1 − k_cos²).
    """
    eps, lfs, sigma = params.eps, params.lfs, params.sigma
    edge = constraints.edge_min(eps, sigma) * lfs
    k_sin = constraints.k_sin(eps, sigma)
    if constraints.is_empty(eps, sigma):
        return []
    theta = 2 * np.arccos(k_sin) * (1 - COUNTEREXAMPLE_SHRINK)
    tri = GuideTriangles.of(edge, edge, theta, 0.0, 0.0)
    printed = chain_bounds(params, Mode.paper)
    found = []
    cos_t, sin_t = float(np.cos(theta)), float(np.sin(theta))
    if cos_t < float(printed.k_cos):
        found.append(StepCounterexample("(49)", "cos θ ≥ k_cos", tri, cos_t, float(printed.k_cos)))
    if sin_t < float(printed.sin_min_obtuse):
        found.append(
            StepCounterexample(
                "(52)",
                "θ > π/2: sin θ ≥ sqrt(1 − k_cos²)",
                tri,
                sin_t,
                float(printed.sin_min_obtuse),
            )
        )
    return found
