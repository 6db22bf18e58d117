"""Guide-triangle configurations, and random feasible ones for audits and optimizer starts.

A configuration is (b, c, θ, L_j, L_k) with L_i = ``params.lfs``: A = p_i at the origin,
B = p_j at distance c, C = p_k at distance b, θ the angle at A. Weights are δ²L², shifted by the
minimum δ²L_i² (so A has weight 0, eq. (6), (37)). Feasibility is decided by the one constraint
set of :mod:`vorobound.bounds.constraints` (with ``lipschitz=λ`` adding its Lipschitz conditions).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..geometry import weighted_triangles
from . import constraints
from .params import SamplingParams

BOUNDARY_SHARE = 0.25
"""In a biased batch, the share of each coordinate pushed to its lower end (and, again, to its
upper end) of the range: the extremes of the constraint set are where bounds are attained."""
STEER_SHARE = 0.5
"""In a biased batch, the share of angles aimed at the largest feasible angle (where the
printed eq. (49) fails, docs/errata.md E4)."""
STEER_SPREAD = 1e-3
"""Relative spread of the steered angles below that largest angle."""


@dataclass(frozen=True)
class GuideTriangles:
    """A batch of guide-triangle configurations (arrays of equal shape).

    L_j and L_k are stored relative to L_i, as ``excess = L/L_i − 1``: forming L_j − L_i from
    absolute values would lose the digits of a tiny excess (small ε or small λ), and the
    weights δ²L_i²·e(2 + e), eq. (37), need exactly those digits.
    """

    b: np.ndarray
    c: np.ndarray
    theta: np.ndarray
    excess_j: np.ndarray
    """L_j/L_i − 1 ≥ 0."""
    excess_k: np.ndarray
    """L_k/L_i − 1 ≥ 0."""

    @classmethod
    def of(cls, b, c, theta, excess_j, excess_k) -> GuideTriangles:
        arrays = np.broadcast_arrays(
            *(np.asarray(x, dtype=float) for x in (b, c, theta, excess_j, excess_k))
        )
        return cls(*(np.atleast_1d(x).copy() for x in arrays))

    def __len__(self) -> int:
        return self.b.shape[0]

    def take(self, index) -> GuideTriangles:
        return GuideTriangles(
            self.b[index],
            self.c[index],
            self.theta[index],
            self.excess_j[index],
            self.excess_k[index],
        )

    @property
    def a(self) -> np.ndarray:
        """|p_j p_k| by the law of cosines, as (b−c)² + 4bc sin²(θ/2) (no cancellation)."""
        half = np.sin(self.theta / 2)
        return np.sqrt((self.b - self.c) ** 2 + 4 * self.b * self.c * half * half)

    @property
    def circumradius(self) -> np.ndarray:
        return self.a / (2 * np.sin(self.theta))

    def lfs(self, params: SamplingParams) -> tuple[np.ndarray, np.ndarray]:
        """(L_j, L_k) in absolute units."""
        return params.lfs * (1 + self.excess_j), params.lfs * (1 + self.excess_k)

    def weights(self, params: SamplingParams) -> tuple[np.ndarray, np.ndarray]:
        """(w_B, w_C) = δ²(L_j² − L_i²), δ²(L_k² − L_i²) = δ²L_i²·e(2 + e), eq. (37)."""
        scale = (params.delta * params.lfs) ** 2
        return (
            scale * self.excess_j * (2 + self.excess_j),
            scale * self.excess_k * (2 + self.excess_k),
        )

    def points(self) -> np.ndarray:
        """Planar vertices (n, 3, 2): A at the origin, B on the x axis."""
        zeros = np.zeros_like(self.b)
        return np.stack(
            [
                np.stack([zeros, zeros], -1),
                np.stack([self.c, zeros], -1),
                np.stack([self.b * np.cos(self.theta), self.b * np.sin(self.theta)], -1),
            ],
            axis=1,
        )

    def radius_gap(self, params: SamplingParams) -> np.ndarray:
        """Exact R − R̂ of the shifted triangle (Theorem 1), via the geometry core."""
        w_b, w_c = self.weights(params)
        weights = np.stack([np.zeros_like(w_b), w_b, w_c], axis=-1)
        return weighted_triangles(self.points(), weights).radius_gap

    def scaled(self, params: SamplingParams) -> constraints.ScaledConfiguration:
        """The configurations in the units of the constraint set (lengths over εL_i)."""
        unit = params.eps * params.lfs
        return constraints.ScaledConfiguration(
            edge_b=self.b / unit,
            edge_c=self.c / unit,
            edge_a=self.a / unit,
            sin_theta=np.sin(self.theta),
            excess_j=self.excess_j / params.eps,
            excess_k=self.excess_k / params.eps,
        )


@dataclass(frozen=True)
class GuideConfiguration:
    """One guide triangle of the constraint set, in absolute units (L_i = ``params.lfs``)."""

    b: float
    """|p_i p_k|, eq. (8)."""
    c: float
    """|p_i p_j|, eq. (9)."""
    theta: float
    """Angle at p_i, eq. (10)."""
    lfs_j: float
    """L_j."""
    lfs_k: float
    """L_k."""
    excess_j: float
    """L_j/L_i − 1 (exact; L_j alone may round it away)."""
    excess_k: float
    """L_k/L_i − 1."""
    a: float
    """|p_j p_k|, eq. (7)."""
    circumradius: float
    """R, eq. (15)."""
    w_b: float
    """Shifted weight δ²(L_j² − L_i²) of p_j, eq. (37)."""
    w_c: float
    """Shifted weight δ²(L_k² − L_i²) of p_k, eq. (37)."""

    @classmethod
    def of(cls, tri: GuideTriangles, params: SamplingParams, index: int = 0) -> GuideConfiguration:
        """Row ``index`` of a batch of configurations."""
        w_b, w_c = tri.weights(params)
        lfs_j, lfs_k = tri.lfs(params)
        return cls(
            b=float(tri.b[index]),
            c=float(tri.c[index]),
            theta=float(tri.theta[index]),
            lfs_j=float(lfs_j[index]),
            lfs_k=float(lfs_k[index]),
            excess_j=float(tri.excess_j[index]),
            excess_k=float(tri.excess_k[index]),
            a=float(tri.a[index]),
            circumradius=float(tri.circumradius[index]),
            w_b=float(w_b[index]),
            w_c=float(w_c[index]),
        )

    def triangles(self) -> GuideTriangles:
        """This configuration as a batch of one."""
        return GuideTriangles.of(self.b, self.c, self.theta, self.excess_j, self.excess_k)


def feasible_mask(tri: GuideTriangles, params: SamplingParams) -> np.ndarray:
    """True where a configuration satisfies the constraint set with ``params.lipschitz``
    (boundary points included)."""
    limits = constraints.ConstraintParams(params.eps, params.sigma, params.lipschitz)
    inside = (tri.theta > 0) & (tri.theta < np.pi)
    return inside & constraints.feasible(tri.scaled(params), limits)


def _candidates(
    params: SamplingParams,
    n: int,
    rng: np.random.Generator,
    biased: bool,
):
    eps, lfs, lipschitz = params.eps, params.lfs, params.lipschitz
    lo = constraints.edge_min(eps, params.sigma) * lfs
    hi = constraints.edge_cap(eps, params.sigma) * eps * lfs
    b = rng.uniform(lo, hi, n)
    c = rng.uniform(lo, hi, n)
    theta_lo = np.arcsin(np.clip(constraints.k_sin(eps, params.sigma), 0, 1))
    theta = rng.uniform(theta_lo, constraints.angle_max(eps, params.sigma), n)
    # L_j, L_k between L_i and their cap: (33), or the Lipschitz cap L_i + λ·edge when lower
    # (drawing below the cap keeps rejection efficient even for a tiny λ).
    excess_hi = 2 * eps / (1 - eps)  # (33): (1+ε)/(1−ε) − 1
    cap_j, cap_k = np.full(n, excess_hi), np.full(n, excess_hi)
    if lipschitz is not None:
        cap_j = np.minimum(cap_j, lipschitz * c / lfs)
        cap_k = np.minimum(cap_k, lipschitz * b / lfs)
    excess_j = cap_j * rng.random(n)
    excess_k = cap_k * rng.random(n)
    if biased:
        # Push each coordinate to an end of its range with probability 1/2 (either end), and
        # aim θ at the largest angle a short-edged triangle can have (the cases (49) misses).
        for arr, low, high in (
            (b, lo, hi),
            (c, lo, hi),
            (excess_j, 0.0, cap_j),
            (excess_k, 0.0, cap_k),
        ):
            high = np.broadcast_to(high, arr.shape)
            pick = rng.random(n)
            arr[pick < BOUNDARY_SHARE] = low
            upper = (pick >= BOUNDARY_SHARE) & (pick < 2 * BOUNDARY_SHARE)
            arr[upper] = high[upper]
        k_sin = np.clip(constraints.k_sin(eps, params.sigma), 0, 1)
        theta_far = np.pi - 2 * np.arcsin(k_sin)
        steer = rng.random(n) < STEER_SHARE
        theta[steer] = theta_far * (1 - np.abs(rng.normal(0, STEER_SPREAD, steer.sum())))
    return GuideTriangles.of(b, c, theta, excess_j, excess_k)


def sample_feasible(
    params: SamplingParams,
    count: int,
    rng: np.random.Generator,
    biased_fraction: float = 0.5,
    max_rounds: int = 200,
) -> GuideTriangles:
    """``count`` feasible configurations (the constraint set with ``params.lipschitz``) by
    rejection: uniform, and biased to the boundaries.

    Raises EmptyConstraintSet when the constraint set is empty at ``params`` (σ(1−ε) > √3).
    """
    constraints.require_guide_triangles(params.eps, params.sigma)
    kept: list[GuideTriangles] = []
    total = 0
    for _ in range(max_rounds):
        if total >= count:
            break
        batch = max(4 * (count - total), 1024)
        biased = rng.random() < biased_fraction
        cand = _candidates(params, batch, rng, biased)
        good = cand.take(feasible_mask(cand, params))
        kept.append(good)
        total += len(good)
    if not kept or total == 0:
        return GuideTriangles.of([], [], [], [], [])
    merged = GuideTriangles(
        *(
            np.concatenate([getattr(k, f) for k in kept])[:count]
            for f in ("b", "c", "theta", "excess_j", "excess_k")
        )
    )
    return merged
