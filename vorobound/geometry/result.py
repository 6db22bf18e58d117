"""The result record of the weighted-triangle batch functions."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class WeightedTriangles:
    """Circum- and ortho-geometry of a batch of weighted triangles.

    Every array has the batch shape ``...`` of the input (vectors add a trailing axis).
    Vertices are relabelled as in Section 3: A is the vertex of minimum weight, B and C
    follow it cyclically in the input order.
    """

    circumradius: np.ndarray
    """R, eq. (3) and (15)."""
    orthoradius_sq: np.ndarray
    """Signed squared orthoradius |p − ẑ|² − w for the given weights, eq. (2)."""
    shifted_orthoradius: np.ndarray
    """R̂ of the triangle with the minimum weight subtracted (eq. (5)–(6)); always ≥ 0."""
    radius_gap: np.ndarray
    """Theorem 1: R − R̂ for the shifted triangle, (a − â)/(2 sin θ), eq. (29).

    (Named ``delta`` in the command line's JSON; δ is also the paper's ball-radius factor.)"""
    radius_gap_unshifted: np.ndarray
    """R − sqrt(orthoradius_sq) for the given weights (NaN where orthoradius_sq < 0)."""
    paper_literal: np.ndarray
    """Eq. (32) exactly as printed, ``radius_gap + s''_i`` (dimensionally inconsistent)."""
    k: np.ndarray
    """k = a² − â², eq. (31)."""
    edges: np.ndarray
    """(a, b, c) = (|BC|, |CA|, |AB|) after relabelling, eq. (7)–(9)."""
    sin_theta: np.ndarray
    """sin θ, θ the angle at A, eq. (10)."""
    cos_theta: np.ndarray
    """cos θ."""
    min_weight_vertex: np.ndarray
    """Index (0, 1, 2) of A in the input order."""
    assumption1_holds: np.ndarray
    """|w_i − w_j| ≤ |p_i − p_j|² for all three pairs, eq. (1)."""
    valid: np.ndarray
    """False where the row could not be computed (its numbers are NaN)."""
    circumcenter: np.ndarray | None = None
    """z, eq. (3); None when only edge lengths were given."""
    orthocenter: np.ndarray | None = None
    """ẑ, eq. (2), in the plane of the triangle; None when only edge lengths were given."""
    radius_gap_direct: np.ndarray | None = None
    """R − R̂ the textbook way: |z − p| − sqrt(|ẑ − p|² − w) from the two explicit centers.
    An independent check on ``radius_gap`` that loses digits to cancellation when R̂ ≈ R.
    None when only edge lengths were given."""
