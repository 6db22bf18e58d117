"""The constraint set of a VoroCrust guide triangle (Section 4.1), stated once.

Every bound mode, the tight optimizer, the Monte Carlo audit, the interval certifier and the
checker of real samples use these definitions.

Setting. A guide triangle has vertices p_i, p_j, p_k with local feature sizes L_i ≤ L_j, L_k
(p_i, the minimum, is A of eq. (6)); c = |p_i p_j|, b = |p_i p_k|, a = |p_j p_k|, θ the angle
at p_i. The constraints are stated on a :class:`ScaledConfiguration`: lengths in units of
ε·L_i and the excess of L over L_i in units of ε·L_i. In these units every limit is of order one
and none divides by ε, so the same expressions evaluate on numpy arrays, on floats and on
interval boxes whose ε reaches down to 0 (the certifier).

The constraints (each reads ``small ≤ large``):

* (33) with the ordering of Section 4.1: L_i ≤ L_j, L_k ≤ (1+ε)/(1−ε)·L_i;
* (34), (35): σεL_i ≤ c, b ≤ 2ε/(1−ε)·L_i (sparsity of p_i with p_j, p_k, whose smaller L is
  L_i; the upper end is twice H3's circumradius);
* (36): σε·min(L_j, L_k) ≤ a ≤ 2ε(1+ε)/(1−ε)²·L_i (sparsity of p_j with p_k uses their own
  smaller L, which is at least the paper's σεL_i);
* H3: R ≤ ε/(1−ε)·L_i, written as a ≤ 2 sin θ·ε/(1−ε)·L_i (a = 2R sin θ);
* with a Lipschitz constant λ (optional): |L_x − L_y| ≤ λ|p_x − p_y| for the three pairs.

Arithmetic only (+, −, ×, ÷) plus the two functions ``minimum`` and ``absolute`` of a backend
``xp`` (numpy by default; the certifier passes an interval backend).

References
----------
Eq. (33)–(40), (48); property H3 and the sampling conditions of Section 4.1.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from types import ModuleType
from typing import Any

import numpy as np

from ..errors import EmptyConstraintSet

FEASIBILITY_RTOL = 1e-12
"""A numeric constraint counts as met when ``large − small ≥ −FEASIBILITY_RTOL·(|large| +
|small|)``: points on the boundary, up to rounding, are feasible."""


SQRT3 = 3**0.5

# --- Limits of the constraint set, in units of L_i (floats, arrays or intervals) -------------


def lfs_max(eps):
    """Largest L_j, L_k over L_i: (1+ε)/(1−ε), eq. (33)."""
    return (1 + eps) / (1 - eps)


def edge_min(eps, sigma):
    """Shortest edge over L_i: σε, the sparsity condition in eq. (34)–(36)."""
    return sigma * eps


def edge_max(eps):
    """Longest edge at p_i over L_i: 2ε/(1−ε), eq. (34)–(35) (twice H3's circumradius)."""
    return 2 * eps / (1 - eps)


def opposite_edge_max(eps):
    """Longest edge a = |p_j p_k| over L_i as printed: 2ε(1+ε)/(1−ε)², eq. (36)."""
    return 2 * eps * (1 + eps) / (1 - eps) ** 2


def circumradius_max(eps):
    """Largest circumradius over L_i: ε/(1−ε), property H3."""
    return eps / (1 - eps)


def weight_max(eps, delta_ratio):
    """Largest shifted weight δ²(L_j² − L_i²) over L_i²: (δ/ε)²ε²·4ε/(1−ε)², eq. (38)–(40)."""
    return (delta_ratio * eps) ** 2 * 4 * eps / (1 - eps) ** 2


def k_sin(eps, sigma):
    """Lower bound σ(1−ε)/2 on the sine of every angle of a feasible triangle, eq. (48).

    Each angle's opposite edge is at least σεL_i and 2R ≤ 2ε/(1−ε)·L_i, and sin = edge/(2R).
    """
    return sigma * (1 - eps) / 2


def is_empty(eps, sigma) -> bool:
    """True when no guide triangle satisfies the constraint set: σ(1−ε) > √3.

    Every triangle has an angle of at most 60°; its opposite edge is at most 2R·sin 60° =
    √3·R ≤ √3·ε/(1−ε)·L_i (H3), while every edge is at least σεL_i ((34)–(36)). Equivalently
    k_sin > √3/2, which no angle of a triangle can exceed at all three vertices.
    """
    return bool(sigma * (1 - eps) > SQRT3)


def require_guide_triangles(eps, sigma) -> None:
    """Raise :class:`~vorobound.errors.EmptyConstraintSet` when :func:`is_empty` holds: the one
    place that says so, for every bound, solver and sampler of feasible triangles."""
    if is_empty(eps, sigma):
        raise EmptyConstraintSet(
            f"no feasible guide triangle at eps = {float(eps):g}, sigma = {float(sigma):g}: "
            "sparsity (34)-(36) and H3 need sigma*(1 - eps) <= sqrt(3) (every edge is at least "
            "sigma*eps*L_i and the shortest at most sqrt(3) R), so every bound is vacuous there"
        )


def empty_below(sigma) -> float:
    """The ε below which the constraint set is empty: 1 − √3/σ for σ > √3, else 0.

    :func:`is_empty` holds exactly for ε < this value. Below it every bound is met vacuously,
    so an ε* search starts there (the answer is not "no ε*").
    """
    return max(0.0, 1 - SQRT3 / float(sigma))


def angle_max(eps, sigma):
    """Largest angle of a feasible triangle: π − 2·arcsin(k_sin).

    Every angle has sine ≥ k_sin (eq. (48)), so the other two angles are each at least
    arcsin(k_sin) and their sum at most π minus the angle. A consequence of the constraints
    that only narrows search boxes (numpy floats or arrays).
    """
    return np.pi - 2 * np.arcsin(np.clip(k_sin(eps, sigma), 0, 1))


def edge_cap(eps, sigma):
    """Longest edge of a feasible triangle over εL_i: 2R·sin(opposite angle) with
    R ≤ ε/(1−ε)·L_i (H3), the sine at most sin(angle_max) once that angle is acute."""
    largest = np.minimum(angle_max(eps, sigma), np.pi / 2)
    return 2 / (1 - eps) * np.sin(largest)


def cos_min(eps, sigma):
    """Valid lower bound 2·k_sin² − 1 on cos θ (docs/errata.md E4; replaces eq. (49)).

    An obtuse θ leaves two acute angles, each at least arcsin(k_sin), so θ ≤ π − 2 arcsin k_sin.
    """
    return 2 * k_sin(eps, sigma) ** 2 - 1


# --- The constraints themselves ----------------------------------------------------------


@dataclass(frozen=True)
class ScaledConfiguration:
    """A guide triangle in the units of the constraints (fields broadcast together).

    ``edge_*`` are lengths over ε·L_i; ``excess_*`` are (L/L_i − 1)/ε; ``sin_theta`` is the sine
    of the angle θ at p_i. Fields may be numpy arrays, floats or intervals.
    """

    edge_b: Any
    """b/(εL_i), b = |p_i p_k|, eq. (8)."""
    edge_c: Any
    """c/(εL_i), c = |p_i p_j|, eq. (9)."""
    edge_a: Any
    """a/(εL_i), a = |p_j p_k|, eq. (7)."""
    sin_theta: Any
    """sin θ, θ the angle at p_i, eq. (10)."""
    excess_j: Any
    """(L_j/L_i − 1)/ε."""
    excess_k: Any
    """(L_k/L_i − 1)/ε."""
    excess_resolution: Any = 0.0
    """Rounding error of ``excess_*`` when they were computed from absolute L values (L − L_i
    cancels when ε is small); numeric feasibility tests allow it on the L conditions."""


@dataclass(frozen=True)
class ConstraintParams:
    """What the constraint set depends on: ε, σ and the optional Lipschitz constant λ."""

    eps: Any
    """A float, an array or an interval (the checkers evaluate the constraints in each)."""
    sigma: Any
    lipschitz: Any = None


Sides = Callable[[ScaledConfiguration, ConstraintParams, ModuleType], tuple]


@dataclass(frozen=True)
class Constraint:
    """One condition ``small ≤ large`` of the constraint set."""

    name: str
    """Identifier used in reports and certificates."""
    equation: str
    """Where it comes from: an equation number of the paper, H3 or the sampling conditions."""
    statement: str
    """The condition in the paper's symbols."""
    sides: Sides
    """(config, params, xp) ↦ (small, large)."""
    lipschitz: bool = False
    """True for the conditions that exist only when a Lipschitz constant λ is given."""
    involves_lfs: bool = False
    """True for the conditions on L (their numeric test allows ``excess_resolution``)."""


def _upper_lfs(cfg, p, xp):
    return 2 / (1 - p.eps)


CONSTRAINTS: tuple[Constraint, ...] = (
    Constraint(
        "lfs_j_min", "(33)", "L_i ≤ L_j", lambda cfg, p, xp: (0, cfg.excess_j), involves_lfs=True
    ),
    Constraint(
        "lfs_j_max",
        "(33)",
        "L_j ≤ (1+ε)/(1−ε)·L_i",
        lambda cfg, p, xp: (cfg.excess_j, _upper_lfs(cfg, p, xp)),
        involves_lfs=True,
    ),
    Constraint(
        "lfs_k_min", "(33)", "L_i ≤ L_k", lambda cfg, p, xp: (0, cfg.excess_k), involves_lfs=True
    ),
    Constraint(
        "lfs_k_max",
        "(33)",
        "L_k ≤ (1+ε)/(1−ε)·L_i",
        lambda cfg, p, xp: (cfg.excess_k, _upper_lfs(cfg, p, xp)),
        involves_lfs=True,
    ),
    Constraint("c_min", "(34)", "c ≥ σεL_i", lambda cfg, p, xp: (p.sigma, cfg.edge_c)),
    Constraint(
        "c_max", "(34)", "c ≤ 2ε/(1−ε)·L_i", lambda cfg, p, xp: (cfg.edge_c, 2 / (1 - p.eps))
    ),
    Constraint("b_min", "(35)", "b ≥ σεL_i", lambda cfg, p, xp: (p.sigma, cfg.edge_b)),
    Constraint(
        "b_max", "(35)", "b ≤ 2ε/(1−ε)·L_i", lambda cfg, p, xp: (cfg.edge_b, 2 / (1 - p.eps))
    ),
    Constraint(
        "a_min",
        "(36)",
        "a ≥ σε·min(L_j, L_k)",
        lambda cfg, p, xp: (
            p.sigma * (1 + p.eps * xp.minimum(cfg.excess_j, cfg.excess_k)),
            cfg.edge_a,
        ),
        involves_lfs=True,
    ),
    Constraint(
        "a_max",
        "(36)",
        "a ≤ 2ε(1+ε)/(1−ε)²·L_i",
        lambda cfg, p, xp: (cfg.edge_a, 2 * (1 + p.eps) / (1 - p.eps) ** 2),
    ),
    Constraint(
        "circumradius_max",
        "H3",
        "R ≤ ε/(1−ε)·L_i",
        lambda cfg, p, xp: (cfg.edge_a, 2 * cfg.sin_theta / (1 - p.eps)),
    ),
    Constraint(
        "lipschitz_ij",
        "Lipschitz",
        "L_j − L_i ≤ λc",
        lambda cfg, p, xp: (cfg.excess_j, p.lipschitz * cfg.edge_c),
        lipschitz=True,
        involves_lfs=True,
    ),
    Constraint(
        "lipschitz_ik",
        "Lipschitz",
        "L_k − L_i ≤ λb",
        lambda cfg, p, xp: (cfg.excess_k, p.lipschitz * cfg.edge_b),
        lipschitz=True,
        involves_lfs=True,
    ),
    Constraint(
        "lipschitz_jk",
        "Lipschitz",
        "|L_j − L_k| ≤ λa",
        lambda cfg, p, xp: (xp.absolute(cfg.excess_j - cfg.excess_k), p.lipschitz * cfg.edge_a),
        lipschitz=True,
        involves_lfs=True,
    ),
)
"""The constraint set in a fixed order (certificates refer to constraints by name)."""

BY_NAME = {c.name: c for c in CONSTRAINTS}


def active_constraints(params: ConstraintParams) -> tuple[Constraint, ...]:
    """The constraints that apply: the Lipschitz ones only when λ is given."""
    return tuple(c for c in CONSTRAINTS if params.lipschitz is not None or not c.lipschitz)


def slacks(cfg: ScaledConfiguration, params: ConstraintParams, xp: ModuleType = np) -> dict:
    """``large − small`` for every applicable constraint (≥ 0 where it holds), by name."""
    out = {}
    for constraint in active_constraints(params):
        small, large = constraint.sides(cfg, params, xp)
        out[constraint.name] = large - small
    return out


def violations(
    cfg: ScaledConfiguration, params: ConstraintParams, rtol: float = FEASIBILITY_RTOL
) -> dict[str, np.ndarray]:
    """Boolean arrays, by constraint name: True where the constraint fails beyond ``rtol``."""
    out = {}
    with np.errstate(invalid="ignore"):
        for constraint in active_constraints(params):
            small, large = (np.asarray(s, dtype=float) for s in constraint.sides(cfg, params, np))
            tol = rtol * (np.abs(small) + np.abs(large))
            if constraint.involves_lfs:
                tol = tol + 2 * np.asarray(cfg.excess_resolution, dtype=float)
            out[constraint.name] = ~(large - small >= -tol)
    return out


def feasible(
    cfg: ScaledConfiguration, params: ConstraintParams, rtol: float = FEASIBILITY_RTOL
) -> np.ndarray:
    """True where every applicable constraint holds (NaN counts as a violation)."""
    failed = violations(cfg, params, rtol)
    ok = (np.asarray(cfg.sin_theta, dtype=float) > 0) & (np.asarray(cfg.edge_a) >= 0)
    for mask in failed.values():
        ok = ok & ~mask
    return ok


LFS_ROUNDING = 2 * np.finfo(float).eps
"""Relative rounding error allowed for one absolute L value (and one difference of two)."""


def scale_configuration(b, c, a, sin_theta, lfs_i, lfs_j, lfs_k, eps) -> ScaledConfiguration:
    """A :class:`ScaledConfiguration` from absolute edge lengths and local feature sizes.

    (L − L_i)/(εL_i) loses digits when ε is small: its rounding error, about
    LFS_ROUNDING·max(L)/(εL_i), is recorded as ``excess_resolution``.
    """
    unit = np.multiply(eps, lfs_i)
    largest = np.maximum(np.maximum(np.abs(lfs_i), np.abs(lfs_j)), np.abs(lfs_k))
    return ScaledConfiguration(
        edge_b=np.divide(b, unit),
        edge_c=np.divide(c, unit),
        edge_a=np.divide(a, unit),
        sin_theta=np.asarray(sin_theta, dtype=float),
        excess_j=np.divide(np.subtract(lfs_j, lfs_i), unit),
        excess_k=np.divide(np.subtract(lfs_k, lfs_i), unit),
        excess_resolution=LFS_ROUNDING * largest / np.abs(unit),
    )
