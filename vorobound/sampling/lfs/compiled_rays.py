"""All hits of rays with a triangle mesh, compiled (needs the optional numba): the drop-in for
libigl's ``AABB.intersect_ray`` behind :meth:`.thickness.RayCaster.hits`, bit for bit.

libigl (2.6.3, the python bindings' pinned libigl 678e1ff) reports a face when the ray meets
the bounding box of every node above it and of the face itself (``ray_box_intersect``: the
slab test of Williams et al., made robust by Ize's two-ulp padding of 1/d, over t in
(0, inf)) and when Möller and Trumbore's test ``intersect_triangle1`` (``raytri.c``) finds a
hit with t > 0; it stores t, u, v as float (``ray_mesh_intersect.cpp``: ``static_cast<float>``).
This kernel walks its own tree (the Morton-ordered boxes of :func:`.compiled_search.
build_tree`) with the same box test: the test is monotone in the box (each slab bound is a
rounded product of a difference with the box's side, and rounding is monotone) as long as
1/d is finite, so every box holding a face's box passes where the face's box passes, and
the face's own box and triangle are then tested with libigl's operations in libigl's order.
The hits are the same set with the same (face, t, u, v) bits. Rays with a direction
component whose inverse is not finite (the slab test makes NaN there) are flagged for libigl.

Within a ray the hits come sorted by t; libigl lists them in the order of its own tree, which
the caller keeps for equal t (a stable sort): a ray with two equal t is flagged too, and the
caller asks libigl for those rays alone (float t makes such ties where a ray crosses an edge
of two faces).

The kernel releases the GIL and runs on the library's threads (:func:`vorobound.geometry.
threads.run_in_threads`). All compiled helpers stay in this one file: numba checks only the
defining file's timestamp before reusing cached machine code.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ...geometry.threads import chunk_bounds, run_in_threads

RAY_BLOCK = 2048
"""Rays handed to a worker thread at a time."""
EPSILON = 0.000001
"""``IGL_RAY_TRI_EPSILON`` of libigl's ``raytri.c``: |det| at most this is a miss."""


class RayTree:
    """The faces (f, 3) of a mesh (points (v, 3)) in a bounding-box tree (module docstring)."""

    def __init__(self, points: np.ndarray, faces: np.ndarray):
        from .compiled_search import build_tree, morton_order

        triangles = np.asarray(points, dtype=float)[np.asarray(faces)]
        order, codes = morton_order(triangles.mean(axis=1))
        self.order = order
        self.triangles = np.ascontiguousarray(triangles[order])
        low, high = self.triangles.min(axis=1), self.triangles.max(axis=1)
        _, (node_low, node_high, node_range, node_child) = build_tree(codes, low, high)
        self.arrays = (
            self.triangles,
            np.stack([low, high], axis=1),
            np.stack([node_low, node_high], axis=1),
            node_range,
            node_child,
        )
        """The tree as the kernel takes it (one tuple)."""

    def crossings(
        self,
        origins: np.ndarray,
        directions: np.ndarray,
        origin_face: np.ndarray,
        near: np.ndarray,
        origin_group: np.ndarray,
        face_group: np.ndarray,
        allowed: np.ndarray,
        start: float,
    ) -> Crossings:
        """Per ray, the hits :func:`.thickness._first_hits` keeps, reduced to what
        :func:`.thickness.thickness` reads: the number, the first, the first on an allowed
        face (flat t, u, v; no lift)."""
        origins, directions, inverse, padded, flagged = _rays(origins, directions)
        out = Crossings(len(origins))
        out.flagged[:] = flagged
        rays = (
            np.ascontiguousarray(origin_face, dtype=np.int64),
            np.ascontiguousarray(near, dtype=float),
            np.ascontiguousarray(origin_group, dtype=np.int64),
            self.order,
            np.ascontiguousarray(face_group, dtype=np.int64),
            np.ascontiguousarray(allowed, dtype=np.bool_),
            float(start),
        )
        fields = (out.count, out.first_face, out.first, out.open_face, out.open, out.flagged)
        if len(origins) and len(self.triangles):

            def task(bounds):
                lo, hi = bounds
                _crossings_kernel(
                    lo, hi, origins, directions, inverse, padded, rays, fields, self.arrays
                )

            run_in_threads(task, chunk_bounds(len(origins), RAY_BLOCK))
        return out

    def cast(self, origins: np.ndarray, directions: np.ndarray):
        """(ray, face, t, uv, flagged): every hit of each ray, sorted by ray and then by t
        (float t, u, v as libigl gives them), and per ray whether libigl must cast it again
        (equal t, or a direction component without a finite inverse)."""
        origins, directions, inverse, padded, flagged = _rays(origins, directions)
        n = len(origins)
        counts = np.zeros(n, dtype=np.int64)
        blocks: dict[int, tuple] = {}
        if n and len(self.triangles):

            def task(bounds):
                lo, hi = bounds
                blocks[lo] = _cast_kernel(
                    lo, hi, origins, directions, inverse, padded, counts, flagged, self.arrays
                )

            run_in_threads(task, chunk_bounds(n, RAY_BLOCK))
        parts = [blocks[lo] for lo in sorted(blocks)]
        face = np.concatenate([p[0] for p in parts]) if parts else np.zeros(0, np.int64)
        values = np.concatenate([p[1] for p in parts]) if parts else np.zeros((0, 3))
        ray = np.repeat(np.arange(n), counts)
        return ray, self.order[face], values[:, 0], values[:, 1:], flagged


def _rays(origins: np.ndarray, directions: np.ndarray):
    """(origins, directions, 1/d, 1/d padded by two ulps away from 0 as libigl pads it,
    whether 1/d is not finite)."""
    origins = np.ascontiguousarray(origins, dtype=float)
    directions = np.ascontiguousarray(directions, dtype=float)
    with np.errstate(divide="ignore", over="ignore"):
        inverse = 1.0 / directions
    away = np.where(np.signbit(inverse), -np.inf, np.inf)
    padded = np.nextafter(np.nextafter(inverse, away), away)  # libigl's increment_ulp(·, 2)
    return origins, directions, inverse, padded, ~np.isfinite(padded).all(axis=1)


@njit(inline="always", error_model="numpy")
def _cross(u0, u1, u2, v0, v1, v2):
    """``IGL_RAY_TRI_CROSS``."""
    return u1 * v2 - u2 * v1, u2 * v0 - u0 * v2, u0 * v1 - u1 * v0


@njit(inline="always", error_model="numpy")
def _meets_box(box, k, ray):
    """libigl's ``ray_box_intersect`` of a ray (``_ray`` of its origin, 1/d and padded 1/d)
    with box k (low, high) over t in (0, inf)."""
    o0, o1, o2, i0, i1, i2, p0, p1, p2, s0, s1, s2 = ray
    x0, x1 = (box[k, s0, 0] - o0) * i0, (box[k, 1 - s0, 0] - o0) * p0
    y0, y1 = (box[k, s1, 1] - o1) * i1, (box[k, 1 - s1, 1] - o1) * p1
    z0, z1 = (box[k, s2, 2] - o2) * i2, (box[k, 1 - s2, 2] - o2) * p2
    # libigl's early exits and NaN-safe max and min come to these comparisons for values
    # that are never NaN (1/d finite): each slab's entry before every other slab's exit, the
    # latest entry below inf, the earliest exit above 0 (one branch instead of six).
    return (
        (x0 <= y1)
        & (y0 <= x1)
        & (x0 <= z1)
        & (y0 <= z1)
        & (z0 <= x1)
        & (z0 <= y1)
        & (x0 < np.inf)
        & (y0 < np.inf)
        & (z0 < np.inf)
        & (x1 > 0.0)
        & (y1 > 0.0)
        & (z1 > 0.0)
    )


@njit(inline="always", error_model="numpy")
def _ray(o, inverse, padded):
    """The ray as :func:`_meets_box` takes it: origin, 1/d, padded 1/d, and per axis the
    side (0 low, 1 high) where the ray enters the slab (libigl: ``inv_dir < 0``)."""
    return (
        o[0],
        o[1],
        o[2],
        inverse[0],
        inverse[1],
        inverse[2],
        padded[0],
        padded[1],
        padded[2],
        1 if inverse[0] < 0 else 0,
        1 if inverse[1] < 0 else 0,
        1 if inverse[2] < 0 else 0,
    )


@njit(inline="always", error_model="numpy")
def _triangle(o, d, tri):
    """libigl's ``intersect_triangle1`` (Möller–Trumbore, the sign of det tested before the
    division): (hit, t, u, v)."""
    e10, e11, e12 = tri[1, 0] - tri[0, 0], tri[1, 1] - tri[0, 1], tri[1, 2] - tri[0, 2]
    e20, e21, e22 = tri[2, 0] - tri[0, 0], tri[2, 1] - tri[0, 1], tri[2, 2] - tri[0, 2]
    p0, p1, p2 = _cross(d[0], d[1], d[2], e20, e21, e22)
    det = e10 * p0 + e11 * p1 + e12 * p2
    if det > EPSILON:
        s0, s1, s2 = o[0] - tri[0, 0], o[1] - tri[0, 1], o[2] - tri[0, 2]
        u = s0 * p0 + s1 * p1 + s2 * p2
        if u < 0.0 or u > det:
            return False, 0.0, 0.0, 0.0
        q0, q1, q2 = _cross(s0, s1, s2, e10, e11, e12)
        v = d[0] * q0 + d[1] * q1 + d[2] * q2
        if v < 0.0 or u + v > det:
            return False, 0.0, 0.0, 0.0
    elif det < -EPSILON:
        s0, s1, s2 = o[0] - tri[0, 0], o[1] - tri[0, 1], o[2] - tri[0, 2]
        u = s0 * p0 + s1 * p1 + s2 * p2
        if u > 0.0 or u < det:
            return False, 0.0, 0.0, 0.0
        q0, q1, q2 = _cross(s0, s1, s2, e10, e11, e12)
        v = d[0] * q0 + d[1] * q1 + d[2] * q2
        if v > 0.0 or u + v < det:
            return False, 0.0, 0.0, 0.0
    else:
        return False, 0.0, 0.0, 0.0
    inv_det = 1.0 / det
    t = (e20 * q0 + e21 * q1 + e22 * q2) * inv_det
    return True, t, u * inv_det, v * inv_det


@njit(inline="always", error_model="numpy")
def _ray_hits(o, d, inv, pad, tree, stack, face, values):
    """All hits of one ray, sorted by t, into (face, values) from row 0 (grown when full):
    (count, face, values, whether two hits have equal t)."""
    triangles, box, node_box, node_range, node_child = tree
    ray = _ray(o, inv, pad)
    used = 0
    top = 0
    stack[0] = 0
    while top >= 0:
        node = stack[top]
        top -= 1
        if not _meets_box(node_box, node, ray):
            continue
        if node_child[node, 0] >= 0:
            stack[top + 1], stack[top + 2] = node_child[node, 1], node_child[node, 0]
            top += 2
            continue
        for p in range(node_range[node, 0], node_range[node, 1]):
            if not _meets_box(box, p, ray):
                continue
            hit, t, u, v = _triangle(o, d, triangles[p])
            if not (hit and t > 0):
                continue
            if used == len(face):
                grown_face = np.empty(2 * used, dtype=np.int64)
                grown_face[:used] = face
                grown_values = np.empty((2 * used, 3))
                grown_values[:used] = values
                face, values = grown_face, grown_values
            face[used] = p
            values[used, 0] = np.float64(np.float32(t))  # libigl keeps them as float
            values[used, 1] = np.float64(np.float32(u))
            values[used, 2] = np.float64(np.float32(v))
            used += 1
    if used > 16:
        rank = np.argsort(values[:used, 0], kind="mergesort")
        face[:used] = face[:used][rank]
        values[:used] = values[:used][rank]
    else:  # insertion
        for a in range(1, used):
            f, t, u, v = face[a], values[a, 0], values[a, 1], values[a, 2]
            b = a - 1
            while b >= 0 and values[b, 0] > t:
                face[b + 1] = face[b]
                values[b + 1, 0], values[b + 1, 1] = values[b, 0], values[b, 1]
                values[b + 1, 2] = values[b, 2]
                b -= 1
            face[b + 1] = f
            values[b + 1, 0], values[b + 1, 1], values[b + 1, 2] = t, u, v
    tied = False
    for a in range(1, used):
        if values[a, 0] == values[a - 1, 0]:
            tied = True
    return used, face, values, tied


@njit(cache=True, nogil=True, error_model="numpy")
def _cast_kernel(lo, hi, origins, directions, inverse, padded, counts, flagged, tree):
    """Hits of rays lo..hi: (faces in the tree's order, (t, u, v) as float); fills counts and
    flags equal t."""
    size = 64 * (hi - lo) + 64
    face = np.empty(size, dtype=np.int64)
    values = np.empty((size, 3))
    ray_face = np.empty(64, dtype=np.int64)
    ray_values = np.empty((64, 3))
    stack = np.zeros(256, dtype=np.int64)
    used = 0
    for i in range(lo, hi):
        if flagged[i]:
            continue
        k, ray_face, ray_values, tied = _ray_hits(
            origins[i], directions[i], inverse[i], padded[i], tree, stack, ray_face, ray_values
        )
        if tied:
            flagged[i] = True
            continue
        if used + k > size:
            size = 2 * (used + k)
            grown_face = np.empty(size, dtype=np.int64)
            grown_face[:used] = face[:used]
            grown_values = np.empty((size, 3))
            grown_values[:used] = values[:used]
            face, values = grown_face, grown_values
        face[used : used + k] = ray_face[:k]
        values[used : used + k] = ray_values[:k]
        used += k
        counts[i] = k
    return face[:used].copy(), values[:used].copy()


@njit(cache=True, nogil=True, error_model="numpy")
def _crossings_kernel(lo, hi, origins, directions, inverse, padded, rays, out, tree):
    """:meth:`RayTree.crossings` for rays lo..hi."""
    origin_face, near, origin_group, face_id, face_group, allowed, start = rays
    count, first_face, first_values, open_face, open_values, flagged = out
    ray_face = np.empty(64, dtype=np.int64)
    ray_values = np.empty((64, 3))
    stack = np.zeros(256, dtype=np.int64)
    for i in range(lo, hi):
        if flagged[i]:
            continue
        k, ray_face, ray_values, tied = _ray_hits(
            origins[i], directions[i], inverse[i], padded[i], tree, stack, ray_face, ray_values
        )
        if tied:
            flagged[i] = True
            continue
        g = origin_group[i]
        last = -np.inf
        kept = 0
        for a in range(k):
            f = face_id[ray_face[a]]
            t = ray_values[a, 0]
            # .thickness._first_hits: the own face, the start, the own patch nearer than near
            if t <= start or f == origin_face[i] or (t <= near[i] and face_group[f] == g):
                continue
            # .thickness._distinct_crossings: more than the gap beyond the last kept hit
            if not t - last > start:
                continue
            last = t
            if kept == 0:
                first_face[i] = f
                first_values[i, :] = ray_values[a, :]
            if open_face[i] < 0 and allowed[g, face_group[f]]:
                open_face[i] = f
                open_values[i, :] = ray_values[a, :]
            kept += 1
        count[i] = kept


class Crossings:
    """Per ray, the hits :func:`.thickness.thickness` keeps (module docstring of
    :mod:`.compiled_rays`): their number, the first and the first on an allowed face."""

    def __init__(self, n: int):
        self.count = np.zeros(n, dtype=np.int64)
        self.first_face = np.full(n, -1, dtype=np.int64)
        self.first = np.zeros((n, 3))
        """(t, u, v) of the first kept hit."""
        self.open_face = np.full(n, -1, dtype=np.int64)
        self.open = np.zeros((n, 3))
        """(t, u, v) of the first kept hit on an allowed face."""
        self.flagged = np.zeros(n, dtype=bool)
        """Rays left to the caller (equal t, or a direction without a finite inverse)."""
