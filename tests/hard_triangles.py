"""Seeded families of weighted triangles, ordinary and numerically hard."""

from __future__ import annotations

import numpy as np


def _rotation(rng: np.random.Generator, dim: int) -> np.ndarray:
    q, r = np.linalg.qr(rng.standard_normal((dim, dim)))
    return q * np.sign(np.diag(r))


def _placed(rng, base: np.ndarray, count: int) -> np.ndarray:
    dim = base.shape[1]
    return np.stack(
        [
            base @ _rotation(rng, dim) * rng.uniform(0.5, 2.0) + rng.standard_normal(dim)
            for _ in range(count)
        ]
    )


def families(seed: int = 7, count: int = 40) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Name → (points (count, 3, d), weights (count, 3))."""
    rng = np.random.default_rng(seed)
    out = {}
    out["random_3d"] = (rng.standard_normal((count, 3, 3)), rng.random((count, 3)) * 0.3)
    out["random_2d_signed"] = (
        rng.standard_normal((count, 3, 2)),
        rng.uniform(-0.2, 0.2, (count, 3)),
    )
    out["tiny_weights"] = (rng.standard_normal((count, 3, 3)), rng.random((count, 3)) * 1e-12)
    flat = np.array([[0.0, 0, 0], [1, 0, 0], [0.3, 1e-6, 0]])
    out["flat_angle_1e-6"] = (_placed(rng, flat, count), rng.random((count, 3)) * 1e-2)
    needle = np.array([[0.0, 0, 0], [1, 0, 0], [1, 1e-6, 0]])
    out["needle_angle_1e-6"] = (_placed(rng, needle, count), rng.random((count, 3)) * 1e-4)
    theta = rng.uniform(2.2, 3.0, count)
    obtuse = np.stack([[[0.0, 0], [1, 0], [0.7 * np.cos(t), 0.7 * np.sin(t)]] for t in theta])
    out["obtuse"] = (obtuse, rng.random((count, 3)) * 0.05)
    # Weights (~1) that set the row scale, beside a triangle 2^-262 to 2^-270 as large: in
    # float64 its intermediates would fall below the normal range.
    tiny_scale = 2.0 ** -rng.integers(262, 271, (count, 1, 1))
    out["tiny_triangle_unit_weights"] = (
        rng.standard_normal((count, 3, 2)) * tiny_scale,
        rng.random((count, 3)),
    )
    out["far_from_origin"] = (
        rng.standard_normal((count, 3, 3)) + 1e6,
        rng.random((count, 3)) * 1e-2,
    )
    return out
