"""The largest empty ball tangent to the surface at a point, against a set of triangles.

A ball tangent at x with centre x + r·d (d a unit normal direction) meets a point q exactly
when r ≥ f(q) = |q − x|²/(2 d·(q − x)) (for d·(q − x) > 0; points behind the tangent plane
are never met). The largest ball tangent at x that contains no point of a triangle T therefore
has radius r_T = min over q in T of f(q). f is quasi-convex on the half-space d·(q − x) > 0
(its sublevel sets are balls), so the minimum over T is attained where the smallest such ball
touches T: in T's interior (the ball tangent to T's plane), or on an edge (the root of a
quadratic), or at a corner; all three are computed in closed form.

The radius is a medial-ball radius of the surface made of those triangles, so it bounds the
local feature size from above (docs/lfs.md). A ball of radius r tangent at x lies within 2r of
x, so once every triangle within 2r_best of x has been tried the answer is final.
"""

from __future__ import annotations

import numpy as np

NEAREST = 16
"""Pieces tried first per point and group (then four times as many, as long as needed)."""
PAIR_CHUNK = 2_000_000
"""(point, triangle) pairs evaluated together (bounds the temporaries to about 0.5 GB)."""
PARALLEL_RTOL = 1e-12
"""1 − |n_T·d| below this: the tangent plane and T's plane are parallel for the plane case."""


def tangent_radius(x, d, a, b, c) -> np.ndarray:
    """r_T for pairs: points x, unit directions d and triangles (a, b, c), all (p, 3)."""
    best = np.full(len(x), np.inf)
    # The ball tangent to T's plane, if it touches the plane inside T.
    normal = np.cross(b - a, c - a)
    length = np.linalg.norm(normal, axis=1)
    normal = normal / np.where(length > 0, length, 1.0)[:, None]
    height = ((x - a) * normal).sum(axis=1)  # signed distance of x to the plane
    k = (d * normal).sum(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        for root, side in ((height / (1 - k), 1.0), (-height / (1 + k), -1.0)):
            centre = x + root[:, None] * d
            along = ((centre - a) * normal).sum(axis=1)
            ok = (root > 0) & np.isfinite(root) & (np.sign(along) * side >= 0)
            touch = centre - along[:, None] * normal
            inside = _inside(touch, a, b, c, normal)
            best = np.where(ok & inside & (length > 0), np.minimum(best, root), best)
    for p, q in ((a, b), (b, c), (c, a)):
        best = np.minimum(best, _segment_radius(x, d, p, q))
    return best


def _inside(point, a, b, c, normal) -> np.ndarray:
    """True where ``point`` (in the plane of a, b, c) lies in the closed triangle."""
    signs = [
        ((np.cross(q - p, point - p)) * normal).sum(axis=1) for p, q in ((a, b), (b, c), (c, a))
    ]
    return (signs[0] >= 0) & (signs[1] >= 0) & (signs[2] >= 0)


def _segment_radius(x, d, p, q) -> np.ndarray:
    """min over s in [0, 1] of f(p + s(q − p)) (inf where the whole segment is behind)."""
    w, e = p - x, q - p
    a0, a1, a2 = (w * w).sum(axis=1), 2 * (w * e).sum(axis=1), (e * e).sum(axis=1)
    h0, h1 = (d * w).sum(axis=1), (d * e).sum(axis=1)
    # f = N/(2H), N = a2 s² + a1 s + a0, H = h1 s + h0; f' = 0 where
    # a2 h1 s² + 2 a2 h0 s + (a1 h0 − a0 h1) = 0.
    qa, qb, qc = a2 * h1, 2 * a2 * h0, a1 * h0 - a0 * h1
    with np.errstate(divide="ignore", invalid="ignore"):
        disc = np.sqrt(np.maximum(qb * qb - 4 * qa * qc, 0))
        linear = np.abs(qa) < 1e-300
        roots = [
            np.where(linear, -qc / qb, (-qb + disc) / (2 * qa)),
            np.where(linear, np.nan, (-qb - disc) / (2 * qa)),
        ]
    best = np.full(len(x), np.inf)
    for s in (np.zeros(len(x)), np.ones(len(x)), *roots):
        s = np.where(np.isfinite(s), s, -1.0)
        valid = (s >= 0) & (s <= 1)
        h = h1 * s + h0
        n = (a2 * s + a1) * s + a0
        with np.errstate(divide="ignore", invalid="ignore"):
            value = np.where(valid & (h > 0), n / (2 * h), np.inf)
        best = np.minimum(best, value)
    return best


def largest_empty_radius(
    points: np.ndarray,
    directions: np.ndarray,
    point_group: np.ndarray,
    triangles: np.ndarray,
    triangle_group: np.ndarray,
    allowed: np.ndarray,
    limit: np.ndarray,
) -> np.ndarray:
    """Per point, the largest ball tangent at it along ``directions`` containing no point of
    an allowed triangle (``allowed[point_group, triangle_group]``), capped at ``limit``.

    Balls tangent at one point in one direction are nested, so only pieces that meet the ball
    of radius ``limit`` can matter: those whose centroid is within limit + (largest piece
    radius) of its centre. They are tried nearest first, NEAREST at a time and then four
    times as many, while more may lie in reach.

    Parameters
    ----------
    points, directions : ndarray (n, 3)
        Tangent points and unit directions into the ball.
    triangles : ndarray (t, 3, 3)
        Corner coordinates of the candidate triangles (small pieces).
    limit : ndarray (n,)
        Radii already known to bound the answer (e.g. half the thickness).
    """
    from scipy.spatial import cKDTree

    best = np.asarray(limit, dtype=float).copy()
    for group in np.unique(triangle_group):
        mine = np.flatnonzero(triangle_group == group)
        users = np.flatnonzero(allowed[point_group, group] & np.isfinite(best))
        if not len(users) or not len(mine):
            continue
        pieces = triangles[mine]
        centroid = pieces.mean(axis=1)
        pad = float(np.linalg.norm(pieces - centroid[:, None], axis=2).max())
        tree = cKDTree(centroid)
        reach = best[users] + pad
        centre = points[users] + best[users][:, None] * directions[users]
        k, done = NEAREST, 0
        while len(users):
            k_eff = min(k, len(mine))
            dist, index = tree.query(
                centre, k=k_eff, distance_upper_bound=float(reach.max()), workers=-1
            )
            dist, index = dist.reshape(len(users), -1), index.reshape(len(users), -1)
            valid = (index < len(mine)) & (dist <= reach[:, None])
            valid[:, :done] = False  # tried in the previous pass
            owner = np.repeat(users, valid.sum(axis=1))
            found = index[valid]
            for lo in range(0, len(owner), PAIR_CHUNK):
                o, f = owner[lo : lo + PAIR_CHUNK], found[lo : lo + PAIR_CHUNK]
                tri = pieces[f]
                value = tangent_radius(points[o], directions[o], tri[:, 0], tri[:, 1], tri[:, 2])
                np.minimum.at(best, o, value)
            # More pieces may meet the ball only where all k were in reach.
            more = (dist[:, -1] <= reach) & (index[:, -1] < len(mine)) & (k_eff < len(mine))
            users = users[more]
            # The balls shrank: a smaller ball tangent at the same point lies inside the
            # larger one, so only pieces that meet the new one still matter.
            reach = best[users] + pad
            centre = points[users] + best[users][:, None] * directions[users]
            done, k = k_eff, 4 * k
    return best
