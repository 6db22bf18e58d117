"""The local thickness of a part along the normal, by ray casting (libigl's AABB tree).

From a point on the surface, the ray along the inward normal leaves the solid where it first
meets the surface again: that distance T_in is the thickness there, the "distance across the
part" the local feature size can never exceed. The ray along the outward normal first meets
the surface across a gap, T_out. A medial ball tangent at the point has radius at most T/2 on
either side (it must fit between the point and the surface it meets), so min(T_in, T_out)/2
bounds the medial-ball radius, hence the local feature size, from above (docs/lfs.md).

Which side is inward is decided by parity: a ray from a surface point into the solid crosses
the surface an odd number of times, one leaving it an even number (a closed mesh).

References
----------
libigl's ``AABB.intersect_ray`` (Jacobson, Panozzo et al., https://libigl.github.io).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

RAY_START_RTOL = 1e-9
"""Hits closer than this times the part's diagonal are the ray's own face (or its edge)."""
RAY_CHUNK = 100_000
"""Rays cast together."""
RAY_TILT = 1e-5
"""Each ray is tilted by about this angle (radians, fixed pseudo-random): the AABB test misses
a hit exactly on an edge or a vertex, which the aligned grids of CAD parts produce; the tilt
moves the hit off it and changes distances by about RAY_TILT²/2 relative."""


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

    def hits(self, origins: np.ndarray, directions: np.ndarray) -> list:
        """All hits (face, t, u, v) of each ray, in no particular order (rays tilted by
        RAY_TILT)."""
        tilt = np.random.default_rng(len(origins)).standard_normal(directions.shape)
        directions = directions + RAY_TILT * tilt
        directions = directions / np.linalg.norm(directions, axis=1)[:, None]
        out = []
        for first in range(0, len(origins), RAY_CHUNK):
            block = slice(first, first + RAY_CHUNK)
            out += self.tree.intersect_ray(
                self.points,
                self.faces,
                np.ascontiguousarray(origins[block]),
                np.ascontiguousarray(directions[block]),
            )
        return out

    def closest(self, queries: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(distance, face, closest point) of each query point to the mesh."""
        squared, face, point = self.tree.squared_distance(
            self.points, self.faces, np.ascontiguousarray(queries, dtype=float)
        )
        return np.sqrt(squared), face, point


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
    same = (face_group, origin_group)
    forward = _first_hits(caster, origins, normals, origin_face, lift, near, same)
    backward = _first_hits(caster, origins, -normals, origin_face, lift, near, same)
    inward = np.full(n, np.inf)
    outward = np.full(n, np.inf)
    known = np.zeros(n, dtype=bool)
    sign = np.zeros(n, dtype=np.int8)
    for k in range(n):
        f_hits, b_hits = forward[k], backward[k]
        f_odd, b_odd = len(f_hits) % 2 == 1, len(b_hits) % 2 == 1
        if f_odd == b_odd:  # open mesh, or a ray grazing an edge: no side is known
            both = f_hits + b_hits
            ok = [t for face, t in both if allowed[origin_group[k], face_group[face]]]
            outward[k] = min(ok, default=np.inf)
            continue
        known[k] = True
        sign[k] = 1 if f_odd else -1
        inner, outer = (f_hits, b_hits) if f_odd else (b_hits, f_hits)
        inward[k] = inner[0][1] if inner else np.inf
        ok = [t for face, t in outer if allowed[origin_group[k], face_group[face]]]
        outward[k] = ok[0] if ok else np.inf
    return Thickness(inward, outward, known, sign)


def _first_hits(
    caster: RayCaster, origins, directions, origin_face, lift, near, groups
) -> list[list]:
    """Per ray, its hits beyond the start distance as (face, t), skipping the own face, hits
    on the own patch nearer than ``near`` and repeated hits of one crossing (a ray through an
    edge hits both of its faces); with ``lift``, t of a hit on a curved face is the distance
    to its point on the smooth surface. A hit on another patch always counts (a thin part's
    other side may be nearer than a long triangle's size)."""
    face_group, origin_group = groups
    raw = caster.hits(origins, directions)
    out, lifted = [], []
    for k, hits in enumerate(raw):
        kept, last = [], -np.inf
        for face, t, u, v in sorted(hits, key=lambda hit: hit[1]):  # libigl does not sort
            if t <= caster.start or face == origin_face[k]:
                continue
            if t <= near[k] and face_group[face] == origin_group[k]:
                continue
            if t - last <= caster.start:  # the same crossing through an edge or a vertex
                continue
            kept.append([face, t])
            lifted.append((k, len(kept) - 1, face, u, v))
            last = t
        out.append(kept)
    if lift is not None and lifted:
        rows = np.array([(k, j) for k, j, *_ in lifted], dtype=np.int64)
        faces = np.array([f for _, _, f, _, _ in lifted], dtype=np.int64)
        uv = np.array([(u, v) for *_, u, v in lifted], dtype=float)
        bary = np.c_[1 - uv.sum(axis=1), uv]
        points, moved = lift(faces, bary)
        distance = np.linalg.norm(points - origins[rows[:, 0]], axis=1)
        for (k, j), d, m in zip(rows.tolist(), distance.tolist(), moved.tolist(), strict=True):
            if m:
                out[k][j][1] = d
    return [[(face, t) for face, t in kept] for kept in out]
