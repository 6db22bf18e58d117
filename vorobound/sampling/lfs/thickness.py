"""The local thickness of a part along the normal, by ray casting (libigl's AABB tree, or its
compiled port :mod:`.compiled_rays`: the same hits bit for bit).

From a point on the surface, the ray along the inward normal leaves the solid where it first
meets the surface again: that distance T_in is the thickness there, the "distance across the
part" the local feature size can never exceed. The ray along the outward normal first meets
the surface across a gap, T_out. A medial ball tangent at the point has radius at most T/2 on
either side (it must fit between the point and the surface it meets), so min(T_in, T_out)/2
bounds the medial-ball radius, hence the local feature size, from above (docs/lfs.md).

Which side is inward is decided by parity: a ray from a surface point into the solid crosses
the surface an odd number of times, one leaving it an even number (a closed mesh).

With numba the rays are cast and reduced in compiled code to the few hits :func:`thickness`
reads (the number kept, the first, the first on an allowed face): a ray across a gear's teeth
meets dozens of faces, and libigl returns every hit as a Python list. Rays whose side the
parity leaves unknown, and rays with two hits at the same t (libigl's order of them decides
which is kept), go through all their hits as without numba.

References
----------
libigl's ``AABB.intersect_ray`` (Jacobson, Panozzo et al., https://libigl.github.io).
"""

from __future__ import annotations

import functools
import itertools
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...geometry.kernels import load_kernel, pure_numpy
from ...geometry.threads import thread_count

RAY_START_RTOL = 1e-9
"""Hits closer than this times the part's diagonal are the ray's own face (or its edge)."""
RAY_CHUNK = 100_000
"""Rays cast together."""
PIECE_PAIRS = 1_000_000
"""(query, piece) distances measured together by :meth:`RayCaster.nearer_than`."""
RAY_TILT = 1e-5
"""Each ray is tilted by about this angle (radians, pseudo-random but fixed by the ray's
origin, so that a point gets the same rays in every round): the AABB test misses a hit exactly
on an edge or a vertex, which the aligned grids of CAD parts produce; the tilt moves the hit
off it and changes distances by about RAY_TILT²/2 relative."""


@dataclass(frozen=True)
class Thickness:
    """Distances along the normal line from surface points to the surface."""

    inward: np.ndarray
    """T_in: distance to the first hit on the inward side (any face); inf if none."""
    outward: np.ndarray
    """T_out: distance to the first hit on the outward side on an allowed face; inf if none."""
    inward_known: np.ndarray
    """False where the parity of the hits could not tell the sides apart (open mesh)."""
    inward_sign: np.ndarray
    """+1 where the given normal points into the solid, −1 where it points out, 0 unknown."""


FIELDS = ("inward", "outward", "inward_known", "inward_sign")
"""The fields of :class:`Thickness`, in order."""


@dataclass(frozen=True)
class Hits:
    """Ray hits as flat arrays, sorted by ray and, within a ray, by distance."""

    ray: np.ndarray
    face: np.ndarray
    t: np.ndarray
    """Distance along the ray."""
    uv: np.ndarray
    """(h, 2) barycentric coordinates of the hit on its face (weights of corners 1 and 2)."""

    def take(self, keep: np.ndarray) -> Hits:
        return Hits(self.ray[keep], self.face[keep], self.t[keep], self.uv[keep])


class RayCaster:
    """An AABB tree of a triangle mesh (libigl) with ray and distance queries."""

    def __init__(self, points: np.ndarray, faces: np.ndarray):
        import igl

        self.points = np.ascontiguousarray(points, dtype=float)
        self.faces = np.ascontiguousarray(faces, dtype=np.int64)
        self.tree = igl.AABB()
        self.tree.init(self.points, self.faces)
        diagonal = float(np.linalg.norm(self.points.max(axis=0) - self.points.min(axis=0)))
        self.start = RAY_START_RTOL * diagonal
        self._bins: list[tuple[Any, np.ndarray, np.ndarray, float]] | None = None
        self._tree: Any = None
        self._rays: Any = None

    def hits(self, origins: np.ndarray, directions: np.ndarray) -> Hits:
        """All hits of each ray (rays tilted by RAY_TILT), sorted by ray and then by t (equal
        t in libigl's order)."""
        directions = _tilted(origins, directions)
        tree = self._ray_tree()
        if tree is None:
            return self._libigl_hits(origins, directions)
        ray, face, t, uv, again = tree.cast(origins, directions)
        again = np.flatnonzero(again)
        if len(again):
            # Equal t (a ray across an edge): libigl's order of the two hits is its tree's.
            redo = self._libigl_hits(origins[again], directions[again])
            ray = np.concatenate([ray, again[redo.ray]])
            order = np.argsort(ray, kind="stable")
            ray = ray[order]
            face = np.concatenate([face, redo.face])[order]
            t = np.concatenate([t, redo.t])[order]
            uv = np.concatenate([uv, redo.uv])[order]
        return Hits(ray, face, t, uv)

    def _ray_tree(self):
        """The compiled ray tree of the faces (:mod:`.compiled_rays`), or None without numba."""
        if self._rays is None:
            self._rays = False
            rays = compiled_rays()
            if rays is not None and len(self.faces):
                self._rays = rays.RayTree(self.points, self.faces)
        return self._rays or None

    def _libigl_hits(self, origins: np.ndarray, directions: np.ndarray) -> Hits:
        """All hits of each ray by libigl (rays as given), sorted by ray and then by t."""
        count_blocks: list[np.ndarray] = []
        value_blocks: list[np.ndarray] = []
        for first in range(0, len(origins), RAY_CHUNK):
            block = slice(first, first + RAY_CHUNK)
            found = self.tree.intersect_ray(
                self.points,
                self.faces,
                np.ascontiguousarray(origins[block]),
                np.ascontiguousarray(directions[block]),
            )
            count_blocks.append(np.fromiter(map(len, found), dtype=np.int64, count=len(found)))
            flat = itertools.chain.from_iterable(itertools.chain.from_iterable(found))
            value_blocks.append(np.fromiter(flat, dtype=float).reshape(-1, 4))
        counts = np.concatenate(count_blocks) if count_blocks else np.zeros(0, dtype=np.int64)
        values = np.concatenate(value_blocks) if value_blocks else np.zeros((0, 4))
        ray = np.repeat(np.arange(len(origins)), counts)
        order = np.lexsort((values[:, 1], ray))  # libigl does not sort
        values = values[order]
        return Hits(ray[order], values[:, 0].astype(np.int64), values[:, 1], values[:, 2:])

    def nearer_than(self, queries: np.ndarray, bound: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(distance, face) of each query to the nearest face closer than ``bound`` (inf and
        −1 where none is).

        Unlike :meth:`closest`, the search is bounded by the query's own ball: the faces, cut
        into local pieces (:func:`.tangent_ball.split_long`) and binned by size, are found
        through k-d trees of their centroids within ``bound`` plus the bin's largest piece. A
        point equally far from many faces (the centre of a sphere, a point on a torus's core
        circle) costs nothing when that distance is above ``bound``."""
        queries = np.asarray(queries, dtype=float)
        bound = np.broadcast_to(np.asarray(bound, dtype=float), len(queries))
        compiled = self._piece_tree()
        if compiled is not None:
            tree, owner = compiled
            # Queries in the order of the tree's Morton curve: neighbouring queries walk the
            # same boxes (cache), each answer unchanged (the queries are independent).
            from .compiled_search import morton_order

            order = morton_order(queries)[0]
            distance, piece = np.full(len(queries), np.inf), np.full(len(queries), -1)
            distance[order], piece[order] = tree.nearest_within(queries[order], bound[order])
            return distance, np.where(piece >= 0, owner[np.maximum(piece, 0)], -1)
        distance = np.full(len(queries), np.inf)
        face = np.full(len(queries), -1, dtype=np.int64)
        for tree, pieces, owner, pad in self._piece_bins():
            count = tree.query_ball_point(
                queries, bound + pad, return_length=True, workers=thread_count()
            )
            rows = np.flatnonzero(count > 0)
            if not len(rows):
                continue
            found = tree.query_ball_point(queries[rows], bound[rows] + pad, workers=thread_count())
            sizes = np.fromiter(map(len, found), dtype=np.int64, count=len(found))
            row = np.repeat(rows, sizes)
            piece = np.fromiter(itertools.chain.from_iterable(found), np.int64, int(sizes.sum()))
            for lo in range(0, len(row), PIECE_PAIRS):
                r, q = row[lo : lo + PIECE_PAIRS], piece[lo : lo + PIECE_PAIRS]
                tri = pieces[q]
                d = point_triangle_distance(queries[r], tri[:, 0], tri[:, 1], tri[:, 2])
                near = d < np.minimum(bound[r], distance[r])
                r, d, q = r[near], d[near], q[near]
                order = np.lexsort((d, r))
                r, d, q = r[order], d[order], q[order]
                first = np.r_[True, r[1:] != r[:-1]] if len(r) else np.zeros(0, bool)
                better = d[first] < distance[r[first]]
                distance[r[first][better]] = d[first][better]
                face[r[first][better]] = owner[q[first][better]]
        return distance, face

    def _piece_tree(self):
        """(the compiled tree of the pieces, their faces), or None without numba."""
        from .tangent_ball import compiled_search, piece_length, split_long

        if self._tree is None:
            self._tree = False
            search = compiled_search()
            if search is not None and len(self.faces):
                triangles = self.points[self.faces]
                pieces, owner = split_long(triangles, piece_length(triangles))
                self._tree = (search.PieceTree(pieces), owner)
        return self._tree or None

    def _piece_bins(self):
        """(k-d tree of centroids, pieces, their faces, largest circle radius) per size bin."""
        if self._bins is None:
            from scipy.spatial import cKDTree

            from .tangent_ball import SIZE_CLASSES, SIZE_RATIO, piece_length, split_long

            triangles = self.points[self.faces]
            pieces, owner = split_long(triangles, piece_length(triangles))
            centroid = pieces.mean(axis=1)
            size = np.linalg.norm(pieces - centroid[:, None], axis=2).max(axis=1)
            which = np.zeros(len(size), dtype=np.int64)
            for k in range(1, SIZE_CLASSES):
                which += size <= float(size.max()) / SIZE_RATIO**k
            self._bins = [
                (
                    cKDTree(centroid[which == k]),
                    pieces[which == k],
                    owner[which == k],
                    float(size[which == k].max()),
                )
                for k in range(SIZE_CLASSES)
                if (which == k).any()
            ]
        return self._bins

    def closest(self, queries: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(distance, face, closest point) of each query point to the mesh."""
        squared, face, point = self.tree.squared_distance(
            self.points, self.faces, np.ascontiguousarray(queries, dtype=float)
        )
        return np.sqrt(squared), face, point


@functools.cache
def _load_compiled_rays():
    return load_kernel(f"{__package__}.compiled_rays")


def compiled_rays():
    """:mod:`.compiled_rays`, or None without numba or with ``VOROBOUND_PURE_NUMPY`` set (then
    libigl casts the rays; both give the same hits bit for bit)."""
    return None if pure_numpy() else _load_compiled_rays()


def point_triangle_distance(x, a, b, c) -> np.ndarray:
    """Distance from points x to triangles (a, b, c), all (p, 3): to the plane where the foot
    lies inside, else to the nearest edge."""
    normal = np.cross(b - a, c - a)
    length = np.linalg.norm(normal, axis=1)
    unit = normal / np.where(length > 0, length, 1.0)[:, None]
    height = ((x - a) * unit).sum(axis=1)
    foot = x - height[:, None] * unit
    inside = length > 0
    for p, q in ((a, b), (b, c), (c, a)):
        inside &= (np.cross(q - p, foot - p) * normal).sum(axis=1) >= 0
    best = np.where(inside, np.abs(height), np.inf)
    for p, q in ((a, b), (b, c), (c, a)):
        e = q - p
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.clip(((x - p) * e).sum(axis=1) / (e * e).sum(axis=1), 0, 1)
        t = np.where(np.isfinite(t), t, 0.0)
        best = np.minimum(best, np.linalg.norm(x - p - t[:, None] * e, axis=1))
    return best


def _tilted(origins: np.ndarray, directions: np.ndarray) -> np.ndarray:
    """The rays' directions tilted by RAY_TILT (a function of the origin) and normalised."""
    directions = directions + RAY_TILT * _tilt(origins)
    return directions / np.linalg.norm(directions, axis=1)[:, None]


def _tilt(origins: np.ndarray) -> np.ndarray:
    """(n, 3) pseudo-random numbers in [−1, 1), a function of each origin's coordinates (their
    bits hashed by the splitmix64 finalizer)."""
    bits = np.ascontiguousarray(origins, dtype=float).view(np.uint64).reshape(-1, 3)
    golden = np.uint64(0x9E3779B97F4A7C15)
    state = np.full(len(bits), golden)
    for column in range(3):
        state = _mix(state ^ bits[:, column])
    out = np.empty(bits.shape)
    for column in range(3):
        state = _mix(state + golden)
        out[:, column] = (state >> np.uint64(11)) * 2.0**-52 - 1.0
    return out


def _mix(state: np.ndarray) -> np.ndarray:
    """The splitmix64 finalizer (uint64 arithmetic wraps)."""
    state = (state ^ (state >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    state = (state ^ (state >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    return state ^ (state >> np.uint64(31))


def thickness(
    caster: RayCaster,
    origins: np.ndarray,
    normals: np.ndarray,
    origin_face: np.ndarray,
    allowed: np.ndarray,
    face_group: np.ndarray,
    origin_group: np.ndarray,
    lift=None,
    near: np.ndarray | None = None,
) -> Thickness:
    """T_in and T_out at surface points (see the module docstring).

    ``lift(faces, bary)``, if given, maps hits on faces of curved patches to the smooth
    surface (PN triangles): a flat facet lies inside a convex surface by up to h²/(8L), which
    would shorten every distance across a curved part by that much. Hits on the point's own
    patch closer than ``near`` (per point: a fraction of the local mesh spacing) are the
    neighbouring faces of a bumpy mesh, not the other side of the part, and are skipped.

    Parameters
    ----------
    caster : RayCaster
        The mesh.
    origins, normals : ndarray (n, 3)
        Points on the surface and their normal lines (the sign does not matter).
    origin_face : ndarray (n,)
        The face each point lies on (its hit is skipped).
    allowed : ndarray (g, g) of bool
        allowed[a, b]: a hit on a face of group b counts for an outward ray from group a.
    face_group, origin_group : ndarray
        Group (patch) of each face and of each point.
    """
    n = len(origins)
    near = np.zeros(n) if near is None else np.asarray(near, dtype=float)
    if n > RAY_CHUNK:
        # Each ray's values depend on its own hits alone: chunks bound the memory by the
        # hits of RAY_CHUNK rays (a CAD part's two million sites made 3.8 GB of hits at once).
        parts = [
            thickness(
                caster,
                origins[lo : lo + RAY_CHUNK],
                normals[lo : lo + RAY_CHUNK],
                origin_face[lo : lo + RAY_CHUNK],
                allowed,
                face_group,
                origin_group[lo : lo + RAY_CHUNK],
                lift,
                near[lo : lo + RAY_CHUNK],
            )
            for lo in range(0, n, RAY_CHUNK)
        ]
        return Thickness(
            *(np.concatenate([getattr(part, name) for part in parts]) for name in FIELDS)
        )
    tree = caster._ray_tree()
    if tree is None:
        return _thickness_of_hits(
            caster, origins, normals, origin_face, allowed, face_group, origin_group, lift, near
        )
    # Compiled: per ray only the hits the numpy path reads (the number of kept hits, the
    # first, the first on an allowed face), the same values bit for bit.
    found = [
        tree.crossings(
            origins,
            _tilted(origins, directions),
            origin_face,
            near,
            origin_group,
            face_group,
            allowed,
            caster.start,
        )
        for directions in (normals, -normals)
    ]
    f_odd, b_odd = found[0].count % 2 == 1, found[1].count % 2 == 1
    known = f_odd != b_odd
    sign = np.where(known, np.where(f_odd, 1, -1), 0).astype(np.int8)
    inward = np.full(n, np.inf)
    outward = np.full(n, np.inf)
    for side, inner in zip(found, (f_odd, b_odd), strict=True):
        rows = np.flatnonzero(known & inner)
        inward[rows] = _lifted(side.first_face[rows], side.first[rows], origins[rows], lift)
        rows = np.flatnonzero(known & ~inner & (side.open_face >= 0))
        outward[rows] = _lifted(side.open_face[rows], side.open[rows], origins[rows], lift)
    # Rays of unknown side (the nearest allowed hit either way reads them all) and rays with
    # equal t (libigl's order decides which hit counts) take the numpy path.
    slow = np.flatnonzero(~known | found[0].flagged | found[1].flagged)
    if len(slow):
        part = _thickness_of_hits(
            caster,
            origins[slow],
            normals[slow],
            origin_face[slow],
            allowed,
            face_group,
            origin_group[slow],
            lift,
            near[slow],
        )
        inward[slow], outward[slow] = part.inward, part.outward
        known[slow], sign[slow] = part.inward_known, part.inward_sign
    return Thickness(inward, outward, known, sign)


def _thickness_of_hits(
    caster, origins, normals, origin_face, allowed, face_group, origin_group, lift, near
) -> Thickness:
    """:func:`thickness` from all the hits of the rays (:meth:`RayCaster.hits`)."""
    n = len(origins)
    same = (face_group, origin_group)
    forward = _first_hits(caster, origins, normals, origin_face, lift, near, same)
    backward = _first_hits(caster, origins, -normals, origin_face, lift, near, same)
    f_count = np.bincount(forward.ray, minlength=n)
    b_count = np.bincount(backward.ray, minlength=n)
    f_odd, b_odd = f_count % 2 == 1, b_count % 2 == 1
    known = f_odd != b_odd  # else an open mesh, or a ray grazing an edge: no side is known
    sign = np.where(known, np.where(f_odd, 1, -1), 0).astype(np.int8)
    inward = np.full(n, np.inf)
    outward = np.full(n, np.inf)
    for hits, inner in ((forward, f_odd), (backward, b_odd)):
        ok = allowed[origin_group[hits.ray], face_group[hits.face]]
        # Known side: the first hit inward (any face), the first allowed one outward.
        first = _first_per_ray(hits.ray)
        rows = hits.ray[first]
        inside = known[rows] & inner[rows]
        inward[rows[inside]] = hits.t[first[inside]]
        first = _first_per_ray(hits.ray, ok)
        rows = hits.ray[first]
        outside = known[rows] & ~inner[rows]
        outward[rows[outside]] = hits.t[first[outside]]
        # Unknown side: the nearest allowed hit either way.
        unknown = ~known[hits.ray] & ok
        np.minimum.at(outward, hits.ray[unknown], hits.t[unknown])
    return Thickness(inward, outward, known, sign)


def _lifted(face: np.ndarray, tuv: np.ndarray, origins: np.ndarray, lift) -> np.ndarray:
    """t of hits (t, u, v) on faces, where ``lift`` moves the hit to the smooth surface the
    distance from the ray's origin to the moved point."""
    if lift is None or not len(face):
        return tuv[:, 0]
    uv = tuv[:, 1:]
    bary = np.c_[1 - uv.sum(axis=1), uv]
    points, moved = lift(face, bary)
    distance = np.linalg.norm(points - origins, axis=1)
    return np.where(moved, distance, tuv[:, 0])


def _first_per_ray(ray: np.ndarray, keep: np.ndarray | None = None) -> np.ndarray:
    """Index of the first entry of each ray (among ``keep``) in arrays sorted by ray."""
    index = np.arange(len(ray)) if keep is None else np.flatnonzero(keep)
    if not len(index):
        return index
    starts = np.r_[True, ray[index[1:]] != ray[index[:-1]]]
    return index[starts]


def _first_hits(caster: RayCaster, origins, directions, origin_face, lift, near, groups) -> Hits:
    """Per ray, its hits beyond the start distance, skipping the own face, hits on the own
    patch nearer than ``near`` and repeated hits of one crossing (a ray through an edge hits
    both of its faces), in order; with ``lift``, t of a hit on a curved face is the distance
    to its point on the smooth surface (the order stays that of the flat hits). A hit on
    another patch always counts (a thin part's other side may be nearer than a long
    triangle's size)."""
    face_group, origin_group = groups
    hits = caster.hits(origins, directions)
    own = (hits.t <= caster.start) | (hits.face == origin_face[hits.ray])
    own |= (hits.t <= near[hits.ray]) & (face_group[hits.face] == origin_group[hits.ray])
    hits = hits.take(~own)
    hits = hits.take(_distinct_crossings(hits.ray, hits.t, caster.start))
    if lift is not None and len(hits.t):
        t = _lifted(hits.face, np.c_[hits.t, hits.uv], origins[hits.ray], lift)
        hits = Hits(hits.ray, hits.face, t, hits.uv)
    return hits


def _distinct_crossings(ray: np.ndarray, t: np.ndarray, gap: float) -> np.ndarray:
    """Which hits to keep (sorted by ray and t): each one more than ``gap`` beyond the last
    kept hit of its ray."""
    new_ray = np.r_[True, ray[1:] != ray[:-1]] if len(ray) else np.zeros(0, dtype=bool)
    close = ~new_ray & (np.diff(t, prepend=-np.inf) <= gap)
    keep = ~close
    # Where two close steps follow each other the last kept hit is not the previous one:
    # walk those rays one hit at a time (rare: a ray through a vertex).
    chained = close[1:] & close[:-1]
    for r in np.unique(ray[1:][chained]):
        last = -np.inf
        for row in range(np.searchsorted(ray, r), np.searchsorted(ray, r, side="right")):
            keep[row] = t[row] - last > gap
            if keep[row]:
                last = t[row]
    return keep
