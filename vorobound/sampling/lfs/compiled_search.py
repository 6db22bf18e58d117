"""Compiled searches of the estimate of L (needs the optional numba): a bounding-box tree of
the triangle pieces, and two queries bounded by each query's own ball.

* :func:`tangent_radii`: the largest ball tangent at a point along a direction that no allowed
  piece enters (:mod:`.tangent_ball`);
* :func:`nearest_within`: the nearest piece closer than a bound (:meth:`.thickness.RayCaster.
  nearer_than`).

The pieces (long triangles cut by :func:`.tangent_ball.split_long`) are sorted along a Morton
curve of their centroids; the tree splits each range of that order where the codes first
differ in their highest bit (an octree's cells; leaves of at most LEAF_SIZE pieces) and keeps the
box of each range. A query walks the tree nearest box first and drops
every box its ball misses, shrinking the ball as pieces are found (the balls are nested), so
it visits only the pieces around it, however long the triangles they were cut from. Each
(query, piece) value is computed with the same operations in the same order as the numpy
functions (:func:`.tangent_ball.tangent_radius`, :func:`.thickness.point_triangle_distance`),
so the answers agree with the numpy path up to ties.

The kernels release the GIL and run on the library's threads (:func:`vorobound.geometry.
threads.run_in_threads`). All compiled helpers stay in this one file: numba checks only the
defining file's timestamp before reusing cached machine code.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ...geometry.threads import chunk_bounds, run_in_threads

LEAF_SIZE = 8
"""Pieces per leaf of the tree (at most)."""
QUERY_CHUNK = 4096
"""Queries handed to a worker thread at a time."""
MORTON_BITS = 21
"""Bits per axis of the Morton code that orders the pieces."""


class PieceTree:
    """Pieces (t, 3, 3) with a group each, in a bounding-box tree (module docstring)."""

    def __init__(self, pieces: np.ndarray, group: np.ndarray | None = None):
        pieces = np.asarray(pieces, dtype=float)
        order, codes = morton_order(pieces.mean(axis=1))
        self.order = order
        self.pieces = np.ascontiguousarray(pieces[order])
        self.group = np.ascontiguousarray(
            np.zeros(len(order), np.int64) if group is None else np.asarray(group)[order],
            dtype=np.int64,
        )
        self.low = self.pieces.min(axis=1)
        self.high = self.pieces.max(axis=1)
        self.count, nodes = build_tree(codes, self.low, self.high)
        self.node_low, self.node_high, self.node_range, self.node_child = nodes
        self.arrays = (
            self.pieces,
            self.low,
            self.high,
            self.node_low,
            self.node_high,
            self.node_range,
            self.node_child,
        )
        """The tree as the compiled kernels take it (one tuple)."""

    def tangent_radii(
        self, points, directions, point_group, limit, allowed, slack: float
    ) -> np.ndarray:
        """Per point, min(limit, the smallest tangent radius of an allowed piece meeting the
        ball of radius limit); points with a limit that is not finite keep it."""
        points = np.ascontiguousarray(points, dtype=float)
        directions = np.ascontiguousarray(directions, dtype=float)
        point_group = np.ascontiguousarray(point_group, dtype=np.int64)
        allowed = np.ascontiguousarray(allowed, dtype=np.bool_)
        best = np.array(limit, dtype=float, copy=True)
        if not len(points) or not len(self.pieces):
            return best

        def task(bounds):
            lo, hi = bounds
            _tangent_kernel(
                lo,
                hi,
                points,
                directions,
                point_group,
                allowed,
                slack,
                best,
                self.group,
                self.arrays,
            )

        run_in_threads(task, chunk_bounds(len(points), QUERY_CHUNK))
        return best

    def nearest_within(self, queries, bound) -> tuple[np.ndarray, np.ndarray]:
        """(distance, piece index in the caller's order) of the nearest piece closer than
        ``bound`` to each query (inf and −1 where none is)."""
        queries = np.ascontiguousarray(queries, dtype=float)
        bound = np.ascontiguousarray(np.broadcast_to(bound, len(queries)), dtype=float)
        distance = np.full(len(queries), np.inf)
        found = np.full(len(queries), -1, dtype=np.int64)
        if not len(queries) or not len(self.pieces):
            return distance, found

        def task(bounds):
            lo, hi = bounds
            _nearest_kernel(lo, hi, queries, bound, distance, found, self.arrays)

        run_in_threads(task, chunk_bounds(len(queries), QUERY_CHUNK))
        hit = found >= 0
        found[hit] = self.order[found[hit]]
        return distance, found


def morton_order(centroid: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The order of the points along a Morton (Z-order) curve of their bounding box, and
    their Morton codes in that order."""
    if not len(centroid):
        return np.zeros(0, np.int64), np.zeros(0, np.uint64)
    low, span = centroid.min(axis=0), np.ptp(centroid, axis=0)
    scale = (2**MORTON_BITS - 1) / np.where(span > 0, span, 1.0)
    cells = ((centroid - low) * scale).astype(np.uint64)
    codes = _interleave(cells)
    order = np.argsort(codes, kind="stable")
    return order, codes[order]


def build_tree(codes: np.ndarray, low: np.ndarray, high: np.ndarray, leaf_size: int = LEAF_SIZE):
    """(node count, (node_low, node_high, node_range, node_child)) of the boxes (low, high)
    ordered by their Morton ``codes``: each range is split where its codes first differ in
    the highest bit (the cells of an octree: a node's box stays inside its cell, instead of
    spanning the jumps of the curve that halving the range by count cuts through; issue 35,
    the pole check on a torus: 3 160 against 1 630 nodes a query at 262 144 vertices), halved
    where all codes are equal, down to ``leaf_size`` boxes a leaf. Arrays trimmed to the node
    count."""
    n = len(low)
    nodes = max(1, 2 * n + 1)  # every split leaves both sides non-empty
    node_low, node_high = np.zeros((nodes, 3)), np.zeros((nodes, 3))
    node_range = np.zeros((nodes, 2), dtype=np.int64)
    node_child = np.full((nodes, 2), -1, dtype=np.int64)
    count = _build(codes, low, high, leaf_size, node_low, node_high, node_range, node_child)
    arrays = tuple(a[:count].copy() for a in (node_low, node_high, node_range, node_child))
    return count, arrays


@njit(cache=True, error_model="numpy")
def _interleave(cells):
    out = np.zeros(len(cells), dtype=np.uint64)
    for i in range(len(cells)):
        code = np.uint64(0)
        for bit in range(MORTON_BITS):
            for axis in range(3):
                if (cells[i, axis] >> np.uint64(bit)) & np.uint64(1):
                    code |= np.uint64(1) << np.uint64(3 * bit + axis)
        out[i] = code
    return out


@njit(cache=True, error_model="numpy")
def _build(codes, low, high, leaf_size, node_low, node_high, node_range, node_child):
    """Split ranges of the ordered pieces at the highest bit where their Morton codes differ
    (halve them where the codes are equal) down to ``leaf_size``; boxes bottom-up. Returns the
    number of nodes (node 0 is the root)."""
    n = len(low)
    stack = np.zeros(256, dtype=np.int64)
    node_range[0, 0], node_range[0, 1] = 0, n
    count = 1
    top = 0
    stack[0] = 0
    while top >= 0:
        node = stack[top]
        top -= 1
        start, end = node_range[node, 0], node_range[node, 1]
        if end - start > leaf_size:
            differ = codes[start] ^ codes[end - 1]
            if differ == 0:
                middle = (start + end) // 2
            else:
                bit = np.uint64(63)
                while not (differ >> bit) & np.uint64(1):
                    bit -= np.uint64(1)
                mask = np.uint64(1) << bit
                lo, hi = start, end - 1  # the first code with the bit set (codes ascending)
                while lo < hi:
                    mid = (lo + hi) // 2
                    if codes[mid] & mask:
                        hi = mid
                    else:
                        lo = mid + 1
                middle = lo
            for k, (s, e) in enumerate(((start, middle), (middle, end))):
                node_range[count, 0], node_range[count, 1] = s, e
                node_child[node, k] = count
                top += 1
                stack[top] = count
                count += 1
    # Children are created after their parent: boxes from the last node back to the root.
    for node in range(count - 1, -1, -1):
        left = node_child[node, 0]
        if left < 0:
            for axis in range(3):
                lo, hi = np.inf, -np.inf
                for p in range(node_range[node, 0], node_range[node, 1]):
                    lo = min(lo, low[p, axis])
                    hi = max(hi, high[p, axis])
                node_low[node, axis], node_high[node, axis] = lo, hi
        else:
            right = node_child[node, 1]
            for axis in range(3):
                node_low[node, axis] = min(node_low[left, axis], node_low[right, axis])
                node_high[node, axis] = max(node_high[left, axis], node_high[right, axis])
    return count


@njit(inline="always", error_model="numpy")
def _box_gap(low, high, node, c0, c1, c2):
    """Squared distance from a point to a box (0 inside)."""
    g = 0.0
    for axis, c in ((0, c0), (1, c1), (2, c2)):
        t = max(low[node, axis] - c, c - high[node, axis], 0.0)
        g += t * t
    return g


@njit(inline="always", error_model="numpy")
def _push_children(stack, top, node_low, node_high, node_child, node, c0, c1, c2):
    """Push the two children of an inner node, the one whose box is nearer to c on top (it
    is walked first); returns the new top of the stack."""
    left, right = node_child[node, 0], node_child[node, 1]
    near = _box_gap(node_low, node_high, left, c0, c1, c2)
    far = _box_gap(node_low, node_high, right, c0, c1, c2)
    if near <= far:
        stack[top + 1], stack[top + 2] = right, left
    else:
        stack[top + 1], stack[top + 2] = left, right
    return top + 2


@njit(inline="always", error_model="numpy")
def _segment(x0, x1, x2, d0, d1, d2, p0, p1, p2, q0, q1, q2):
    """:func:`.tangent_ball._segment_radius` for one pair."""
    w0, w1, w2 = p0 - x0, p1 - x1, p2 - x2
    e0, e1, e2 = q0 - p0, q1 - p1, q2 - p2
    a0 = w0 * w0 + w1 * w1 + w2 * w2
    a1 = 2 * (w0 * e0 + w1 * e1 + w2 * e2)
    a2 = e0 * e0 + e1 * e1 + e2 * e2
    h0 = d0 * w0 + d1 * w1 + d2 * w2
    h1 = d0 * e0 + d1 * e1 + d2 * e2
    qa, qb, qc = a2 * h1, 2 * a2 * h0, a1 * h0 - a0 * h1
    disc = math.sqrt(max(qb * qb - 4 * qa * qc, 0.0))
    if abs(qa) < 1e-300:
        r1 = -qc / qb if qb != 0 else math.nan
        r2 = math.nan
    else:
        r1 = (-qb + disc) / (2 * qa)
        r2 = (-qb - disc) / (2 * qa)
    best = np.inf
    for s in (0.0, 1.0, r1, r2):
        if not math.isfinite(s):
            s = -1.0
        if s >= 0 and s <= 1:
            h = h1 * s + h0
            if h > 0:
                value = ((a2 * s + a1) * s + a0) / (2 * h)
                if value < best:
                    best = value
    return best


@njit(inline="always", error_model="numpy")
def _cross(u0, u1, u2, v0, v1, v2):
    return u1 * v2 - u2 * v1, u2 * v0 - u0 * v2, u0 * v1 - u1 * v0


@njit(inline="always", error_model="numpy")
def _inside(t, n0, n1, n2, f0, f1, f2):
    """Whether f, a point in the plane of triangle t (3, 3), lies inside it or on its edges:
    each edge's cross product with the way to f points along the normal n (of any length)."""
    for i in range(3):
        p0, p1, p2 = t[i, 0], t[i, 1], t[i, 2]
        j = (i + 1) % 3
        q0, q1, q2 = t[j, 0], t[j, 1], t[j, 2]
        s0, s1, s2 = _cross(q0 - p0, q1 - p1, q2 - p2, f0 - p0, f1 - p1, f2 - p2)
        if not (s0 * n0 + s1 * n1 + s2 * n2 >= 0):
            return False
    return True


@njit(cache=True, error_model="numpy")
def _tangent_radius(x0, x1, x2, d0, d1, d2, t):
    """:func:`.tangent_ball.tangent_radius` for one point, direction and triangle t (3, 3)."""
    a0, a1, a2 = t[0, 0], t[0, 1], t[0, 2]
    b0, b1, b2 = t[1, 0], t[1, 1], t[1, 2]
    c0, c1, c2 = t[2, 0], t[2, 1], t[2, 2]
    best = np.inf
    n0, n1, n2 = _cross(b0 - a0, b1 - a1, b2 - a2, c0 - a0, c1 - a1, c2 - a2)
    length = math.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
    if length > 0:
        n0, n1, n2 = n0 / length, n1 / length, n2 / length
        height = (x0 - a0) * n0 + (x1 - a1) * n1 + (x2 - a2) * n2
        k = d0 * n0 + d1 * n1 + d2 * n2
        for side in (1.0, -1.0):
            root = height / (1 - k) if side > 0 else -height / (1 + k)
            if not (root > 0 and math.isfinite(root)):
                continue
            m0, m1, m2 = x0 + root * d0, x1 + root * d1, x2 + root * d2
            along = (m0 - a0) * n0 + (m1 - a1) * n1 + (m2 - a2) * n2
            if along * side < 0 or along != along:
                continue
            u0, u1, u2 = m0 - along * n0, m1 - along * n1, m2 - along * n2
            if root < best and _inside(t, n0, n1, n2, u0, u1, u2):
                best = root
    return min(
        best,
        _segment(x0, x1, x2, d0, d1, d2, a0, a1, a2, b0, b1, b2),
        _segment(x0, x1, x2, d0, d1, d2, b0, b1, b2, c0, c1, c2),
        _segment(x0, x1, x2, d0, d1, d2, c0, c1, c2, a0, a1, a2),
    )


@njit(cache=True, nogil=True, error_model="numpy")
def _tangent_kernel(lo, hi, points, directions, point_group, allowed, slack, best, group, tree):
    pieces, low, high, node_low, node_high, node_range, node_child = tree
    stack = np.zeros(256, dtype=np.int64)
    for i in range(lo, hi):
        r = best[i]
        if not math.isfinite(r):
            continue
        x0, x1, x2 = points[i, 0], points[i, 1], points[i, 2]
        d0, d1, d2 = directions[i, 0], directions[i, 1], directions[i, 2]
        g = point_group[i]
        top = 0
        stack[0] = 0
        while top >= 0:
            node = stack[top]
            top -= 1
            reach = r * (1 + slack)
            c0, c1, c2 = x0 + r * d0, x1 + r * d1, x2 + r * d2
            if _box_gap(node_low, node_high, node, c0, c1, c2) > reach * reach:
                continue
            if node_child[node, 0] < 0:  # a leaf
                for p in range(node_range[node, 0], node_range[node, 1]):
                    if not allowed[g, group[p]]:
                        continue
                    c0, c1, c2 = x0 + r * d0, x1 + r * d1, x2 + r * d2
                    reach = r * (1 + slack)
                    if _box_gap(low, high, p, c0, c1, c2) > reach * reach:
                        continue
                    value = _tangent_radius(x0, x1, x2, d0, d1, d2, pieces[p])
                    if value < r:
                        r = max(value, 0.0)  # rounding below 0: x lies on the piece
                continue
            top = _push_children(stack, top, node_low, node_high, node_child, node, c0, c1, c2)
        best[i] = r


@njit(cache=True, error_model="numpy")
def _point_triangle_distance(x0, x1, x2, t):
    """:func:`.thickness.point_triangle_distance` for one point and triangle t (3, 3)."""
    a0, a1, a2 = t[0, 0], t[0, 1], t[0, 2]
    b0, b1, b2 = t[1, 0], t[1, 1], t[1, 2]
    c0, c1, c2 = t[2, 0], t[2, 1], t[2, 2]
    n0, n1, n2 = _cross(b0 - a0, b1 - a1, b2 - a2, c0 - a0, c1 - a1, c2 - a2)
    length = math.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
    scale = length if length > 0 else 1.0
    u0, u1, u2 = n0 / scale, n1 / scale, n2 / scale
    height = (x0 - a0) * u0 + (x1 - a1) * u1 + (x2 - a2) * u2
    f0, f1, f2 = x0 - height * u0, x1 - height * u1, x2 - height * u2
    inside = length > 0 and _inside(t, n0, n1, n2, f0, f1, f2)
    best = abs(height) if inside else np.inf
    return min(
        best,
        _segment_distance(x0, x1, x2, a0, a1, a2, b0, b1, b2),
        _segment_distance(x0, x1, x2, b0, b1, b2, c0, c1, c2),
        _segment_distance(x0, x1, x2, c0, c1, c2, a0, a1, a2),
    )


@njit(inline="always", error_model="numpy")
def _segment_distance(x0, x1, x2, p0, p1, p2, q0, q1, q2):
    """Distance from x to the segment pq (a point where p = q)."""
    e0, e1, e2 = q0 - p0, q1 - p1, q2 - p2
    ee = e0 * e0 + e1 * e1 + e2 * e2
    s = ((x0 - p0) * e0 + (x1 - p1) * e1 + (x2 - p2) * e2) / ee if ee > 0 else 0.0
    if not math.isfinite(s):
        s = 0.0
    s = min(max(s, 0.0), 1.0)
    v0, v1, v2 = x0 - p0 - s * e0, x1 - p1 - s * e1, x2 - p2 - s * e2
    return math.sqrt(v0 * v0 + v1 * v1 + v2 * v2)


@njit(cache=True, nogil=True, error_model="numpy")
def _nearest_kernel(lo, hi, queries, bound, distance, found, tree):
    pieces, low, high, node_low, node_high, node_range, node_child = tree
    stack = np.zeros(256, dtype=np.int64)
    for i in range(lo, hi):
        r = bound[i]  # strictly nearer than r
        if not r > 0:
            continue
        x0, x1, x2 = queries[i, 0], queries[i, 1], queries[i, 2]
        best, which = np.inf, -1
        top = 0
        stack[0] = 0
        while top >= 0:
            node = stack[top]
            top -= 1
            if _box_gap(node_low, node_high, node, x0, x1, x2) >= r * r:
                continue
            if node_child[node, 0] < 0:  # a leaf
                for p in range(node_range[node, 0], node_range[node, 1]):
                    if _box_gap(low, high, p, x0, x1, x2) >= r * r:
                        continue
                    value = _point_triangle_distance(x0, x1, x2, pieces[p])
                    if value < r and value < best:
                        best, which = value, p
                        r = value
                continue
            top = _push_children(stack, top, node_low, node_high, node_child, node, x0, x1, x2)
        distance[i] = best
        found[i] = which
