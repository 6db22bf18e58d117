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

from ...geometry.threads import thread_count

NEAREST = 16
"""Pieces tried first per point and group (then four times as many, as long as needed)."""
PAIR_CHUNK = 2_000_000
"""(point, triangle) pairs evaluated together (bounds the temporaries to about 0.5 GB)."""
PLANE_RTOL = 1e-6
"""A triangle whose doubled area is below PLANE_RTOL·size² (size: the radius of its circle
about the centroid) is ruled out by that circle only, not by its plane."""
MEET_SLACK = 1e-9
"""Relative enlargement of the ball in the test that rules triangles out."""
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

    Balls tangent at one point in one direction are nested, so only triangles that meet the
    ball of radius ``limit`` can matter. Per group of triangles, a k-d tree of their centroids
    finds the candidates nearest first, NEAREST at a time and then four times as many, while
    more may lie in reach: around the ball's centre, within its radius plus the largest
    triangle's; or, for a group that lies within a thin slab (a flat patch), around the foot of
    the centre on the slab's plane, within the radius of the disk the ball cuts from the slab.
    Candidates that cannot meet the ball (:func:`_may_meet`) are not evaluated.

    Parameters
    ----------
    points, directions : ndarray (n, 3)
        Tangent points and unit directions into the ball.
    triangles : ndarray (t, 3, 3)
        Corner coordinates of the candidate triangles (small pieces).
    limit : ndarray (n,)
        Radii already known to bound the answer (e.g. half the thickness).
    """
    return TangentBalls(triangles, triangle_group, allowed)(points, directions, point_group, limit)


class TangentBalls:
    """:func:`largest_empty_radius` against one set of triangles, asked many times (the
    search structures of each group are built once, when first needed)."""

    def __init__(self, triangles: np.ndarray, triangle_group: np.ndarray, allowed: np.ndarray):
        self.triangles, self.triangle_group, self.allowed = triangles, triangle_group, allowed
        self._groups: dict[int, _TriangleGroup] = {}

    def __call__(self, points, directions, point_group, limit) -> np.ndarray:
        best = np.asarray(limit, dtype=float).copy()
        for group in np.unique(self.triangle_group):
            users = np.flatnonzero(self.allowed[point_group, group] & np.isfinite(best))
            if len(users):
                self._group(int(group)).shrink(points, directions, users, best)
        return best

    def _group(self, group: int) -> _TriangleGroup:
        if group not in self._groups:
            pieces = self.triangles[self.triangle_group == group]
            self._groups[group] = _TriangleGroup(pieces)
        return self._groups[group]


class _TriangleGroup:
    """The triangles of one group, with what the search needs: centroids in a k-d tree, the
    radius of each one's circle about its centroid, unit normals, and the group's plane."""

    def __init__(self, pieces: np.ndarray):
        from scipy.spatial import cKDTree

        self.pieces = pieces
        self.centroid = pieces.mean(axis=1)
        self.size = np.linalg.norm(pieces - self.centroid[:, None], axis=2).max(axis=1)
        normal = np.cross(pieces[:, 1] - pieces[:, 0], pieces[:, 2] - pieces[:, 0])
        length = np.linalg.norm(normal, axis=1)
        widest = int(np.argmax(length))
        # A sliver's plane is not known well enough to rule it out by its plane.
        normal = np.where((length > PLANE_RTOL * self.size**2)[:, None], normal, 0.0)
        self.normal = normal / np.where(length > 0, length, 1.0)[:, None]
        self.pad = float(self.size.max())
        self.tree = cKDTree(self.centroid)
        # The slab around the plane of the largest triangle that holds every corner.
        self.plane_normal, self.plane_point = self.normal[widest], pieces[widest, 0]
        self.slab = float(np.abs((pieces - self.plane_point) @ self.plane_normal).max())
        self.flat = bool(self.normal[widest].any()) and self.slab < self.pad

    def shrink(self, points, directions, users, best) -> None:
        """Lower ``best[users]`` to the largest ball tangent at each point that no triangle of
        the group enters (in place)."""
        k = NEAREST
        while len(users):
            centre = points[users] + best[users][:, None] * directions[users]
            around, reach = self._search_ball(centre, best[users])
            users, around, reach, centre = (
                users[reach > 0],
                around[reach > 0],
                reach[reach > 0],
                centre[reach > 0],
            )
            if not len(users):
                return
            k_eff = min(k, len(self.pieces))
            dist, index = self.tree.query(
                around, k=k_eff, distance_upper_bound=float(reach.max()), workers=thread_count()
            )
            dist, index = dist.reshape(len(users), -1), index.reshape(len(users), -1)
            valid = (index < len(self.pieces)) & (dist <= reach[:, None])
            row = np.repeat(np.arange(len(users)), valid.sum(axis=1))
            found = index[valid]
            meets = _may_meet(
                centre[row],
                best[users[row]],
                self.centroid[found],
                self.normal[found],
                self.size[found],
            )
            owner, found = users[row[meets]], found[meets]
            for lo in range(0, len(owner), PAIR_CHUNK):
                o, f = owner[lo : lo + PAIR_CHUNK], found[lo : lo + PAIR_CHUNK]
                tri = self.pieces[f]
                value = tangent_radius(points[o], directions[o], tri[:, 0], tri[:, 1], tri[:, 2])
                np.minimum.at(best, o, value)
            # More triangles may meet the ball only where all k were in reach; they are
            # searched again around the shrunk ball (every triangle that meets it met the
            # larger one), the first k again too (evaluating one twice changes nothing).
            more = (dist[:, -1] <= reach) & (index[:, -1] < len(self.pieces))
            if k_eff == len(self.pieces):
                return
            users, k = users[more], 4 * k

    def _search_ball(self, centre, radius):
        """Where to look for the centroids of triangles that may meet each ball, and how far
        (0: nowhere)."""
        radius = radius * (1 + MEET_SLACK)
        if not self.flat:
            return centre, radius + self.pad
        height = (centre - self.plane_point) @ self.plane_normal
        foot = centre - height[:, None] * self.plane_normal
        # Points of the slab in the ball project into this disk around the foot.
        gap = np.maximum(np.abs(height) - self.slab, 0)
        disk = np.sqrt(np.maximum(radius * radius - gap * gap, 0))
        return foot, np.where(gap < radius, disk + self.pad + self.slab, 0.0)


def _may_meet(centre, radius, centroid, normal, size) -> np.ndarray:
    """False where a triangle cannot meet the open ball (centre, radius): its plane is out of
    reach, or the disk the ball cuts from that plane misses the circle around the triangle's
    centroid (``size``) that contains it. A triangle that
    misses the ball of the current best radius cannot lower it (the balls are nested). A zero
    ``normal`` tests the circle alone. The ball is taken MEET_SLACK larger, so that a triangle
    left out would not have lowered the radius even by a rounding error."""
    radius = radius * (1 + MEET_SLACK)
    offset = centre - centroid
    distance = np.sqrt((offset * offset).sum(axis=1))
    height = (offset * normal).sum(axis=1)
    across = radius * radius - height * height  # squared radius of the disk
    in_plane = np.sqrt(np.maximum(distance * distance - height * height, 0))
    return (across > 0) & (in_plane < np.sqrt(np.maximum(across, 0)) + size)
