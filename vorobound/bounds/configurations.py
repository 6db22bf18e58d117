"""Guide-triangle configurations allowed by the sampling conditions of Section 4.1.

A configuration is (b, c, θ, L_j, L_k) with L_i = ``params.lfs``: A = p_i at the origin,
B = p_j at distance c, C = p_k at distance b, θ the angle at A. Weights are δ²L², shifted by the
minimum δ²L_i² (so A has weight 0, eq. (6), (37)).

The *paper's constraint set*: edges (34)–(36), L bound (33), circumradius ≤ ε/(1−ε)·L_i
(property H3), and pairwise sparsity with the pair's smaller L. ``lipschitz=λ`` adds
|L_x − L_y| ≤ λ·|p_x − p_y| for each pair.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..geometry import weighted_triangles
from .params import SamplingParams

FEASIBILITY_RTOL = 1e-12
"""Relative slack when testing a constraint, so points on the boundary count as feasible."""


@dataclass(frozen=True)
class GuideTriangles:
    """A batch of guide-triangle configurations (arrays of equal shape)."""

    b: np.ndarray
    c: np.ndarray
    theta: np.ndarray
    lfs_j: np.ndarray
    lfs_k: np.ndarray

    @classmethod
    def of(cls, b, c, theta, lfs_j, lfs_k) -> GuideTriangles:
        arrays = np.broadcast_arrays(
            *(np.asarray(x, dtype=float) for x in (b, c, theta, lfs_j, lfs_k))
        )
        return cls(*(np.atleast_1d(x).copy() for x in arrays))

    def __len__(self) -> int:
        return self.b.shape[0]

    def take(self, index) -> GuideTriangles:
        return GuideTriangles(
            self.b[index], self.c[index], self.theta[index], self.lfs_j[index], self.lfs_k[index]
        )

    @property
    def a(self) -> np.ndarray:
        """|p_j p_k| by the law of cosines, as (b−c)² + 4bc sin²(θ/2) (no cancellation)."""
        half = np.sin(self.theta / 2)
        return np.sqrt((self.b - self.c) ** 2 + 4 * self.b * self.c * half * half)

    @property
    def circumradius(self) -> np.ndarray:
        return self.a / (2 * np.sin(self.theta))

    def weights(self, params: SamplingParams) -> tuple[np.ndarray, np.ndarray]:
        """(w_B, w_C) = δ²(L_j² − L_i²), δ²(L_k² − L_i²), eq. (37)."""
        d2 = params.delta**2
        lfs = params.lfs
        return d2 * (self.lfs_j - lfs) * (self.lfs_j + lfs), d2 * (self.lfs_k - lfs) * (
            self.lfs_k + lfs
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

    def delta(self, params: SamplingParams) -> np.ndarray:
        """Exact R − R̂ of the shifted triangle (Theorem 1), via the geometry core."""
        w_b, w_c = self.weights(params)
        weights = np.stack([np.zeros_like(w_b), w_b, w_c], axis=-1)
        return weighted_triangles(self.points(), weights).delta


def feasible_mask(
    tri: GuideTriangles, params: SamplingParams, lipschitz: float | None = None
) -> np.ndarray:
    """True where a configuration satisfies the constraint set (see the module docstring)."""
    eps, lfs, sigma = params.eps, params.lfs, params.sigma
    slack = 1 + FEASIBILITY_RTOL
    edge_min = sigma * eps * lfs / slack
    edge_max = 2 * eps / (1 - eps) * lfs * slack
    a = tri.a
    ok = (tri.b >= edge_min) & (tri.b <= edge_max) & (tri.c >= edge_min) & (tri.c <= edge_max)
    ok &= (tri.theta > 0) & (tri.theta < np.pi)
    ok &= a <= 2 * eps * (1 + eps) / (1 - eps) ** 2 * lfs * slack
    ok &= a >= sigma * eps * np.minimum(tri.lfs_j, tri.lfs_k) / slack
    ok &= tri.circumradius <= eps / (1 - eps) * lfs * slack
    lfs_max = (1 + eps) / (1 - eps) * lfs * slack
    for lfs_x in (tri.lfs_j, tri.lfs_k):
        ok &= (lfs_x >= lfs / slack) & (lfs_x <= lfs_max)
    if lipschitz is not None:
        tol = FEASIBILITY_RTOL * lfs
        ok &= np.abs(tri.lfs_j - lfs) <= lipschitz * tri.c + tol
        ok &= np.abs(tri.lfs_k - lfs) <= lipschitz * tri.b + tol
        ok &= np.abs(tri.lfs_j - tri.lfs_k) <= lipschitz * a + tol
    return ok


def _candidates(params: SamplingParams, n: int, rng: np.random.Generator, biased: bool):
    eps, lfs = params.eps, params.lfs
    lo, hi = params.sigma * eps * lfs, 2 * eps / (1 - eps) * lfs
    lfs_hi = (1 + eps) / (1 - eps) * lfs
    b = rng.uniform(lo, hi, n)
    c = rng.uniform(lo, hi, n)
    theta = rng.uniform(0, np.pi, n)
    lfs_j = rng.uniform(lfs, lfs_hi, n)
    lfs_k = rng.uniform(lfs, lfs_hi, n)
    if biased:
        # Push each coordinate to an end of its range with probability 1/2 (either end), and
        # aim θ at the largest angle a short-edged triangle can have (the cases (49) misses).
        for arr, low, high in (
            (b, lo, hi),
            (c, lo, hi),
            (lfs_j, lfs, lfs_hi),
            (lfs_k, lfs, lfs_hi),
        ):
            pick = rng.random(n)
            arr[pick < 0.25] = low
            arr[(pick >= 0.25) & (pick < 0.5)] = high
        k_sin = np.clip(params.sigma * (1 - eps) / 2, 0, 1)
        theta_far = np.pi - 2 * np.arcsin(k_sin)
        steer = rng.random(n) < 0.5
        theta[steer] = theta_far * (1 - np.abs(rng.normal(0, 1e-3, steer.sum())))
    return GuideTriangles.of(b, c, theta, lfs_j, lfs_k)


def sample_feasible(
    params: SamplingParams,
    count: int,
    rng: np.random.Generator,
    lipschitz: float | None = None,
    biased_fraction: float = 0.5,
    max_rounds: int = 200,
) -> GuideTriangles:
    """``count`` feasible configurations by rejection: uniform, and biased to the boundaries."""
    kept: list[GuideTriangles] = []
    total = 0
    for _ in range(max_rounds):
        if total >= count:
            break
        batch = max(4 * (count - total), 1024)
        biased = rng.random() < biased_fraction
        cand = _candidates(params, batch, rng, biased)
        good = cand.take(feasible_mask(cand, params, lipschitz))
        kept.append(good)
        total += len(good)
    if not kept or total == 0:
        return GuideTriangles.of([], [], [], [], [])
    merged = GuideTriangles(
        *(
            np.concatenate([getattr(k, f) for k in kept])[:count]
            for f in ("b", "c", "theta", "lfs_j", "lfs_k")
        )
    )
    return merged
