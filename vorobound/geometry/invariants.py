"""Rational invariants of a weighted triangle, and the square-root stage that finishes them.

The quantities of Theorem 1 split into two stages:

1. *rational* ones (squared edges, dot products at the vertices, the squared doubled area,
   the numerator of k, the squared shifted orthoradius, the center offsets). They use
   ``+ - * /`` only, so the same code runs on float64, on ``numpy.longdouble`` and on object
   arrays of :class:`fractions.Fraction` (exact);
2. *radical* ones (edge lengths, radii, Theorem 1's difference), computed in floating point
   from correctly rounded rational inputs, with no subtraction of nearly equal numbers.

Vertex-free form of Theorem 1
-----------------------------
Number the vertices 0, 1, 2; let ``e_i`` be the edge opposite vertex i, ``d_i`` the dot product
of the two edge vectors leaving vertex i, and ``ω_i`` the weight of vertex i minus the minimum
weight (so the minimum-weight vertex A has ω = 0, eq. (6)). The numerator of eq. (31),
``k b² c²``, regroups as

    k b² c² = Σ_i ω_i (2 d_i − ω_i) e_i² + 2 Σ_{i<j} ω_i ω_j d_k      (k the third index),

whatever vertex is A, and since a = 2R sin θ, â = 2R̂ sin θ and 2 sin θ = 2·area2/(b c),

    R² − R̂² = (a² − â²)/(4 sin²θ) = k b² c² / (4 area2²),
    R − R̂  = k b² c² / (4 area2² (R + R̂))                 (eq. (29), cancellation-free).

Arrays hold vectors component-major, shape ``(d, n)``, and scalars per vertex as ``(3, n)``.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


class Invariants(NamedTuple):
    """Rational invariants of a batch of weighted triangles (batch on the last axis)."""

    edge_sq: np.ndarray  #: (3, n) squared edge opposite each vertex, eq. (7)–(9)
    dots: np.ndarray  #: (3, n) dot product of the edge vectors leaving each vertex
    area2_sq: np.ndarray  #: (n,) (2·area)²
    omega: np.ndarray  #: (3, n) weights minus the minimum weight, eq. (6)
    w_min: np.ndarray  #: (n,) the minimum weight, s''_i of eq. (32)
    k_num: np.ndarray  #: (n,) k·b²·c², eq. (31)
    rt_sq: np.ndarray  #: (n,) squared orthoradius of the shifted triangle, eq. (5)
    rt_sq_scale: np.ndarray  #: (n,) size of the terms that ``rt_sq`` is a difference of
    circ_offset: np.ndarray | None  #: (d, n) circumcenter − vertex 0
    ortho_shift: np.ndarray | None  #: (d, n) circumcenter − orthocenter


def _dot(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Row-wise dot product of vectors stored component-major, shape (d, n)."""
    total = x[0] * y[0]
    for i in range(1, x.shape[0]):
        total = total + x[i] * y[i]
    return total


def k_numerator(edge_sq, dots, omega):
    """Return k·b²·c² of eq. (31) in the vertex-free form of the module docstring.

    References
    ----------
    Eq. (28), (31).
    """
    e0, e1, e2 = edge_sq
    d0, d1, d2 = dots
    w0, w1, w2 = omega
    return (
        w0 * (2 * d0 - w0) * e0
        + w1 * (2 * d1 - w1) * e1
        + w2 * (2 * d2 - w2) * e2
        + 2 * (w1 * w2 * d0 + w0 * w2 * d1 + w0 * w1 * d2)
    )


def _shift(weights):
    w0, w1, w2 = weights
    w_min = np.minimum(np.minimum(w0, w1), w2) if weights.dtype != object else None
    if w_min is None:  # exact arithmetic: object arrays have no ufunc minimum
        w_min = np.array([min(t) for t in zip(w0, w1, w2, strict=True)], dtype=object)
    return w_min, np.stack([w0 - w_min, w1 - w_min, w2 - w_min])


def invariants_from_points(points: np.ndarray, weights: np.ndarray) -> Invariants:
    """Rational invariants from vertices ``(3, d, n)`` and weights ``(3, n)``.

    References
    ----------
    Eq. (2), (3), (5), (6), (31).
    """
    p0, p1, p2 = points
    u = p1 - p0
    v = p2 - p0
    e = p2 - p1
    edge_sq = np.stack([_dot(e, e), _dot(v, v), _dot(u, u)])
    dots = np.stack([_dot(u, v), -_dot(u, e), _dot(v, e)])
    if u.shape[0] == 3:
        normal = np.stack(
            [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
        )
        area2_sq = _dot(normal, normal)
    else:
        normal = u[0] * v[1] - u[1] * v[0]
        area2_sq = normal * normal
    w_min, omega = _shift(weights)
    k_num = k_numerator(edge_sq, dots, omega)
    # Circumcenter z = p0 + x with 2u·x = |u|², 2v·x = |v|²; orthocenter ẑ = z − y with
    # 2u·y = ω1 − ω0, 2v·y = ω2 − ω0 (subtract the power equations (2) from (3)).
    two_det = 2 * area2_sq
    g1 = omega[1] - omega[0]
    g2 = omega[2] - omega[0]
    circ_offset = (edge_sq[1] * dots[1] / two_det) * u + (edge_sq[2] * dots[2] / two_det) * v
    ortho_shift = ((edge_sq[1] * g1 - dots[0] * g2) / two_det) * u + (
        (edge_sq[2] * g2 - dots[0] * g1) / two_det
    ) * v
    xhat = circ_offset - ortho_shift
    xhat_sq = _dot(xhat, xhat)
    rt_sq = xhat_sq - omega[0]
    return Invariants(
        edge_sq,
        dots,
        area2_sq,
        omega,
        w_min,
        k_num,
        rt_sq,
        xhat_sq + omega[0],
        circ_offset,
        ortho_shift,
    )


def invariants_from_edges(edges: np.ndarray, weights: np.ndarray) -> Invariants:
    """Rational invariants from edge lengths ``(3, n)`` (edge i opposite vertex i) and weights.

    References
    ----------
    Eq. (7)–(9), (15), (31).
    """
    edge_sq = edges * edges
    e0, e1, e2 = edge_sq
    dots = np.stack([(e1 + e2 - e0) / 2, (e0 + e2 - e1) / 2, (e0 + e1 - e2) / 2])
    # (2·area)² = b²c² − (b c cos θ)², Heron's formula in product form.
    area2_sq = e1 * e2 - dots[0] * dots[0]
    w_min, omega = _shift(weights)
    k_num = k_numerator(edge_sq, dots, omega)
    r_sq = e0 * e1 * e2 / (4 * area2_sq)
    gap = k_num / (4 * area2_sq)
    rt_sq = r_sq - gap
    return Invariants(
        edge_sq, dots, area2_sq, omega, w_min, k_num, rt_sq, r_sq + abs(gap), None, None
    )


SQ_FLOOR = 2.0**-300
"""Smallest squared edge (in row-scale units) that float64 evaluation accepts.

Rows are scaled so that coordinates and sqrt|weights| are at most about 1. When the weights
set that scale and the triangle is tiny beside it, products of up to six lengths (the
circumradius, the numerator of k) fall below the normal float64 range and lose digits without
any cancellation the condition estimate would see. Below these floors a row is refined in
extended precision, whose exponent range is far wider.
"""
AREA_FLOOR = 2.0**-700
"""Smallest (2·area)² in row-scale units that float64 evaluation accepts (see ``SQ_FLOOR``)."""
K_FLOOR = 2.0**-990
"""Smallest nonzero |k·b²·c²| in row-scale units that float64 evaluation accepts."""


class Radicals(NamedTuple):
    """Finished quantities of a batch (float arrays, batch on the last axis)."""

    edges: np.ndarray  #: (3, n) edge opposite each vertex
    area2: np.ndarray  #: doubled area
    circumradius: np.ndarray  #: R, eq. (15)
    shifted_orthoradius: np.ndarray  #: R̂ of the shifted triangle, eq. (5)
    radius_gap: np.ndarray  #: R − R̂, eq. (29)


def finish(inv: Invariants) -> Radicals:
    """Square roots and quotients of Theorem 1 from (correctly rounded) invariants.

    References
    ----------
    Eq. (15), (29).
    """
    edges = np.sqrt(inv.edge_sq)
    with np.errstate(divide="ignore", invalid="ignore"):
        area2 = np.sqrt(inv.area2_sq)
        circumradius = edges[0] * edges[1] * edges[2] / (2 * area2)
        shifted = np.sqrt(np.maximum(inv.rt_sq, 0))
        radius_gap = inv.k_num / (4 * inv.area2_sq * (circumradius + shifted))
    return Radicals(edges, area2, circumradius, shifted, radius_gap)


def condition_estimate(inv: Invariants, rad: Radicals, from_edges: bool = False) -> np.ndarray:
    """Bound on how much rounding in the rational stage is amplified into ``radius_gap``, per row.

    Three things can cancel. The doubled area: ``|u×v|`` has relative error ~ eps/sin θ₀ from
    coordinates (θ₀ the angle at vertex 0), and ``b²c² − (b c cos θ₀)²`` ~ eps/sin²θ₀ from
    edges. The numerator of k: the ratio of the magnitudes of its terms (each dot product
    replaced by the edge product that bounds it) to ``|k_num|``. And the squared shifted
    orthoradius, a difference whose error enters through ``R + R̂``. A non-positive area
    gives ``inf`` so that exact arithmetic decides, and so (in float64) does a row whose
    intermediates come near underflow (``SQ_FLOOR``, ``AREA_FLOOR``, ``K_FLOOR``).
    """
    e0, e1, e2 = rad.edges
    adj0, adj1, adj2 = e1 * e2, e0 * e2, e0 * e1
    w0, w1, w2 = np.abs(inv.omega)
    sq0, sq1, sq2 = inv.edge_sq
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        inv_sin = np.where(inv.area2_sq > 0, adj0 / rad.area2, np.inf)
        cond_area = inv_sin * inv_sin if from_edges else inv_sin
        size = w0 * (2 * adj0 + w0) * sq0 + w1 * (2 * adj1 + w1) * sq1
        size += w2 * (2 * adj2 + w2) * sq2
        size += 2 * (w1 * w2 * adj0 + w0 * w2 * adj1 + w0 * w1 * adj2)
        cond_k = size / np.abs(inv.k_num)
        rt = rad.shifted_orthoradius
        cond_rt = inv.rt_sq_scale / (rt * (rad.circumradius + rt))
    # 0/0 (equal weights: k_num = 0 exactly) is harmless; NaN from bad input is not refined.
    cond_k[size == 0] = 1.0
    cond = np.fmax(np.fmax(cond_area, cond_k), cond_rt)
    if inv.area2_sq.dtype == np.float64:
        underflow = np.minimum(np.minimum(sq0, sq1), sq2) < SQ_FLOOR
        underflow |= inv.area2_sq < AREA_FLOOR
        underflow |= (np.abs(inv.k_num) < K_FLOOR) & (size > 0)
        cond[underflow] = np.inf
    return cond
