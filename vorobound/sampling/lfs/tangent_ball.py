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

import functools
from typing import Any

import numpy as np

from ...geometry.kernels import load_kernel, pure_numpy
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
    ball of radius ``limit`` can matter. The triangles are cut into local pieces (longest-edge
    bisection, :func:`split_long`) whose union is the triangle, so the answer is unchanged;
    the pieces of all groups are binned by size (:data:`SIZE_CLASSES`), and per bin a k-d tree
    of their centroids finds the candidates nearest the ball's centre first, NEAREST at a time
    and then four times as many, while more may lie in reach (within the ball's radius plus
    the bin's largest piece). A query therefore reaches only as far as the pieces around it,
    not as far as the largest triangle of the mesh. Candidates of groups that are not allowed,
    or that cannot meet the ball (:func:`_may_meet`), are not evaluated.

    Parameters
    ----------
    points, directions : ndarray (n, 3)
        Tangent points and unit directions into the ball.
    triangles : ndarray (t, 3, 3)
        Corner coordinates of the candidate triangles.
    limit : ndarray (n,)
        Radii already known to bound the answer (e.g. half the thickness).
    """
    return TangentBalls(triangles, triangle_group, allowed)(points, directions, point_group, limit)


class TangentBalls:
    """:func:`largest_empty_radius` against one set of triangles, asked many times (the
    pieces and their trees are built once, when first needed)."""

    def __init__(self, triangles: np.ndarray, triangle_group: np.ndarray, allowed: np.ndarray):
        self.triangles, self.triangle_group, self.allowed = triangles, triangle_group, allowed
        self._groups: dict[int, list[_PieceBin]] = {}
        self._length: np.ndarray | None = None
        self._boxes: dict[int, np.ndarray] = {}
        self._compiled: Any = None  # None: not built yet; False: no numba

    def __call__(self, points, directions, point_group, limit) -> np.ndarray:
        tree = self._tree()
        if tree is not None:
            return tree.tangent_radii(
                points, directions, point_group, limit, self.allowed, MEET_SLACK
            )
        best = np.asarray(limit, dtype=float).copy()
        point_group = np.asarray(point_group)
        for group in np.unique(self.triangle_group):
            users = np.flatnonzero(self.allowed[point_group, group] & np.isfinite(best))
            if not len(users):
                continue
            # Only balls that reach the box around the group's triangles can meet them.
            low, high = self._box(int(group))
            centre = points[users] + best[users][:, None] * directions[users]
            gap = np.maximum(np.maximum(low - centre, centre - high), 0)
            reach = best[users] * (1 + MEET_SLACK)
            users = users[(gap * gap).sum(axis=1) <= reach * reach]
            for piece_bin in self._group(int(group)) if len(users) else ():
                piece_bin.shrink(points, directions, users, best)
        return best

    def _tree(self):
        """The compiled tree of all pieces (:mod:`.compiled_search`), or None without numba."""
        if self._compiled is None:
            self._compiled = False
            search = compiled_search()
            if search is not None and len(self.triangles):
                pieces, owner = split_long(self.triangles, piece_length(self.triangles))
                self._compiled = search.PieceTree(pieces, self.triangle_group[owner])
        return self._compiled or None

    def _box(self, group: int) -> np.ndarray:
        if group not in self._boxes:
            corners = self.triangles[self.triangle_group == group].reshape(-1, 3)
            self._boxes[group] = np.stack([corners.min(axis=0), corners.max(axis=0)])
        return self._boxes[group]

    def _group(self, group: int) -> list[_PieceBin]:
        if self._length is None:
            self._length = piece_length(self.triangles)
        if group not in self._groups:
            mine = self.triangle_group == group
            pieces, _ = split_long(self.triangles[mine], self._length[mine])
            size = _circle_radius(pieces)
            edges = [float(size.max()) / SIZE_RATIO**k for k in range(1, SIZE_CLASSES)]
            which = np.zeros(len(size), dtype=np.int64)
            for edge in edges:
                which += size <= edge
            self._groups[group] = [
                _PieceBin(pieces[which == k]) for k in range(SIZE_CLASSES) if (which == k).any()
            ]
        return self._groups[group]


@functools.cache
def _load_compiled_search():
    return load_kernel(f"{__package__}.compiled_search")


def compiled_search():
    """The compiled searches (:mod:`.compiled_search`), or None: numba is missing, or the
    environment variable ``VOROBOUND_PURE_NUMPY`` is set (then the numpy searches below run;
    both give the same answers up to ties)."""
    return None if pure_numpy() else _load_compiled_search()


SIZE_CLASSES = 4
"""Bins of pieces by size (each bin's search reaches as far as its largest piece)."""
SIZE_RATIO = 4.0
"""Ratio of the size limits of neighbouring bins (the last bin holds all smaller pieces)."""
PIECES_PER_FACE = 16
"""Long triangles are cut to the shortest length that makes at most this many pieces per
triangle on average (the memory bound, about 2 kB per triangle)."""


SLIVER_ASPECT = 4.0
"""Only triangles whose longest edge exceeds this many times their width (the height onto
it) are cut, and never into pieces of a smaller aspect: a fine mesh keeps its triangles."""


def piece_length(triangles: np.ndarray) -> np.ndarray:
    """Per triangle, the length to which it is cut: max(h, SLIVER_ASPECT·width), h the
    shortest that makes about PIECES_PER_FACE pieces per triangle on average (bisection makes
    up to 4·longest/length pieces of a sliver)."""
    if not len(triangles):
        return np.zeros(0)
    longest = np.linalg.norm(triangles - np.roll(triangles, -1, axis=1), axis=2).max(axis=1)
    doubled = np.linalg.norm(
        np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0]), axis=1
    )
    floor = SLIVER_ASPECT * doubled / np.where(longest > 0, longest, 1.0)

    def count(h):
        return np.maximum(1, 4 * longest / np.maximum(h, floor)).sum()

    # Smallest h with count(h) ≤ PIECES_PER_FACE·t, by bisection on h.
    low, high = 0.0, float(longest.max())
    budget = PIECES_PER_FACE * len(triangles)
    for _ in range(60):
        middle = 0.5 * (low + high)
        if count(middle) <= budget:
            high = middle
        else:
            low = middle
    return np.maximum(high, floor)


def split_long(triangles: np.ndarray, length) -> tuple[np.ndarray, np.ndarray]:
    """Cut every sliver with an edge longer than ``length`` (one for all, or one per
    triangle) by longest-edge bisection until no piece is both (a piece whose longest edge is
    at most SLIVER_ASPECT times its width is kept); returns the pieces (their union is the
    triangle) and each one's triangle."""
    pieces = np.asarray(triangles, dtype=float)
    owner = np.arange(len(pieces))
    length = np.broadcast_to(np.asarray(length, dtype=float), len(pieces))
    done_pieces, done_owner = [], []
    while len(pieces):
        edge = np.linalg.norm(pieces - np.roll(pieces, -1, axis=1), axis=2)  # edge k: k → k+1
        longest = edge.argmax(axis=1)
        top = edge[np.arange(len(pieces)), longest]
        doubled = np.linalg.norm(
            np.cross(pieces[:, 1] - pieces[:, 0], pieces[:, 2] - pieces[:, 0]), axis=1
        )
        # Cut further only a piece that is too long and still a sliver.
        long = (top > length[owner]) & (top * top > SLIVER_ASPECT * doubled)
        done_pieces.append(pieces[~long])
        done_owner.append(owner[~long])
        pieces, owner, longest = pieces[long], owner[long], longest[long]
        if not len(pieces):
            break
        # Rotate the corners so that the longest edge is 0 → 1, then halve it.
        rows = np.arange(len(pieces))[:, None]
        turn = pieces[rows, (longest[:, None] + np.arange(3)) % 3]
        middle = 0.5 * (turn[:, 0] + turn[:, 1])
        first = np.stack([turn[:, 0], middle, turn[:, 2]], axis=1)
        second = np.stack([middle, turn[:, 1], turn[:, 2]], axis=1)
        pieces = np.concatenate([first, second])
        owner = np.concatenate([owner, owner])
    if not done_pieces:
        return np.zeros((0, 3, 3)), np.zeros(0, dtype=np.int64)
    return np.concatenate(done_pieces), np.concatenate(done_owner)


def _circle_radius(pieces: np.ndarray) -> np.ndarray:
    """Radius of each piece's circle about its centroid (it contains the piece)."""
    centroid = pieces.mean(axis=1)
    return np.linalg.norm(pieces - centroid[:, None], axis=2).max(axis=1)


class _PieceBin:
    """Pieces of one group and of similar size, with what the search needs: centroids in a
    k-d tree, the radius of each one's circle about its centroid, and unit normals."""

    def __init__(self, pieces: np.ndarray):
        from scipy.spatial import cKDTree

        self.pieces = pieces
        self.centroid = pieces.mean(axis=1)
        self.size = _circle_radius(pieces)
        normal = np.cross(pieces[:, 1] - pieces[:, 0], pieces[:, 2] - pieces[:, 0])
        length = np.linalg.norm(normal, axis=1)
        # A sliver's plane is not known well enough to rule it out by its plane.
        normal = np.where((length > PLANE_RTOL * self.size**2)[:, None], normal, 0.0)
        self.normal = normal / np.where(length > 0, length, 1.0)[:, None]
        self.pad = float(self.size.max())
        self.tree = cKDTree(self.centroid)

    def shrink(self, points, directions, users, best) -> None:
        """Lower ``best[users]`` to the largest ball tangent at each point that no piece of
        the bin enters (in place)."""
        k = NEAREST
        count = len(self.pieces)
        while len(users):
            k_eff = min(k, count)
            step = max(1, PAIR_CHUNK // k_eff)
            more = [
                self._search(points, directions, users[lo : lo + step], k_eff, best)
                for lo in range(0, len(users), step)
            ]
            if k_eff == count:
                return
            users, k = np.concatenate(more), 4 * k

    def _search(self, points, directions, users, k_eff, best) -> np.ndarray:
        """One pass over the k nearest pieces of each user; returns the users for whom more
        pieces may lie in reach."""
        count = len(self.pieces)
        radius = best[users] * (1 + MEET_SLACK)
        centre = points[users] + best[users][:, None] * directions[users]
        reach = radius + self.pad
        dist, index = self.tree.query(
            centre, k=k_eff, distance_upper_bound=float(reach.max()), workers=thread_count()
        )
        dist, index = dist.reshape(len(users), -1), index.reshape(len(users), -1)
        valid = (index < count) & (dist <= reach[:, None])
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
        # More pieces may meet the ball only where all k were in reach; they are searched
        # again around the shrunk ball (every piece that meets it met the larger one), the
        # first k again too (evaluating one twice changes nothing).
        return users[(dist[:, -1] <= reach) & (index[:, -1] < count)]


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
