"""Circumradius and signed orthoradius of weighted simplices (triangles in 2-D, tetrahedra in
3-D), and each vertex's distance to its nearest neighbour in the simplex.

References
----------
Eq. (2)–(3) of the paper (orthoball and circumball), extended to full-dimensional simplices.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError


@dataclass(frozen=True)
class SimplexRadii:
    """Circumradius and signed squared orthoradius of a batch of full-dimensional simplices."""

    circumradius: np.ndarray
    """R: |p_i − z| for the center z equidistant from all vertices, eq. (3)."""
    orthoradius_sq: np.ndarray
    """R̂² = |p_i − ẑ|² − w_i for the center ẑ with equal power to all vertices, eq. (2)."""


def simplex_radii(points, weights) -> SimplexRadii:
    """Circumradius and signed squared orthoradius of weighted d-simplices in R^d, d ∈ {2, 3}.

    Subtracting vertex 0's center equation from vertex i's gives the linear system
    2 (p_i − p_0)·(c − p_0) = |p_i − p_0|² − (w_i − w_0), solved by Cramer's rule (cross
    products in 3-D). This avoids LAPACK, whose threads stall on many tiny systems when the
    machine is busy, and is as accurate as LU for 2×2 and 3×3 systems.

    Parameters
    ----------
    points : array_like, shape (..., d + 1, d)
        Vertex coordinates of full-dimensional simplices.
    weights : array_like, shape (..., d + 1)
        Vertex weights (squared ball radii).

    Returns
    -------
    SimplexRadii
        Degenerate simplices give non-finite values.

    References
    ----------
    Eq. (2)–(3).
    """
    p = np.asarray(points, dtype=np.float64)
    w = np.asarray(weights, dtype=np.float64)
    if p.ndim < 2 or p.shape[-1] not in (2, 3) or p.shape[-2] != p.shape[-1] + 1:
        raise InputError(f"points must have shape (..., 3, 2) or (..., 4, 3), got {p.shape}")
    if w.shape[-1:] != p.shape[-2:-1]:
        raise InputError(f"weights must have shape (..., {p.shape[-2]}), got {w.shape}")
    w = np.broadcast_to(w, p.shape[:-1])
    edges = p[..., 1:, :] - p[..., :1, :]
    half_sq = 0.5 * (edges * edges).sum(axis=-1)
    with np.errstate(all="ignore"):
        circ = _solve_small(edges, half_sq)
        ortho = _solve_small(edges, half_sq - 0.5 * (w[..., 1:] - w[..., :1]))
        return SimplexRadii(
            circumradius=np.sqrt((circ * circ).sum(axis=-1)),
            orthoradius_sq=(ortho * ortho).sum(axis=-1) - w[..., 0],
        )


def _solve_small(rows: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """x with rows·x = rhs for batches of 2×2 or 3×3 systems (Cramer's rule)."""
    if rows.shape[-1] == 2:
        (a, b), (c, d) = np.moveaxis(rows, (-2, -1), (0, 1))
        r0, r1 = np.moveaxis(rhs, -1, 0)
        return np.stack([d * r0 - b * r1, a * r1 - c * r0], axis=-1) / (a * d - b * c)[..., None]
    a0, a1, a2 = np.moveaxis(rows, -2, 0)
    c12, c20, c01 = _cross(a1, a2), _cross(a2, a0), _cross(a0, a1)
    det = (a0 * c12).sum(axis=-1)
    r0, r1, r2 = np.moveaxis(rhs[..., None], -2, 0)
    return (r0 * c12 + r1 * c20 + r2 * c01) / det[..., None]


def _cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """u × v over the last axis: numpy's formula (the same floats), without its set-up cost,
    which dominates on the small batches of a local search."""
    u0, u1, u2 = u[..., 0], u[..., 1], u[..., 2]
    v0, v1, v2 = v[..., 0], v[..., 1], v[..., 2]
    return np.stack([u1 * v2 - u2 * v1, u2 * v0 - u0 * v2, u0 * v1 - u1 * v0], axis=-1)


def nearest_vertex_distances(points) -> np.ndarray:
    """N(s): distance from each vertex to its nearest other vertex of the same simplex.

    Parameters
    ----------
    points : array_like, shape (..., n, d)

    Returns
    -------
    numpy.ndarray, shape (..., n)

    References
    ----------
    Section 1 (Cheng et al.'s weight condition).
    """
    p = np.asarray(points, dtype=np.float64)
    diff = p[..., :, None, :] - p[..., None, :, :]
    dist = np.sqrt((diff * diff).sum(axis=-1))
    n = p.shape[-2]
    dist[..., np.arange(n), np.arange(n)] = np.inf
    return dist.min(axis=-1)
