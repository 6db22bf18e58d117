"""Compiled steps of M̂ (needs the optional numba): face neighbours, circumcentres, and the walk
around every in/out Delaunay edge.

:func:`vorobound.sampling.reconstruct.facets.inout_facets` calls these on CGAL's tetrahedra
where numba is installed; the numpy steps of that module give the same result everywhere else
(and the tests compare the two). Issue 35: on 1.3·10⁵ seeds the numpy steps (a sort of the 4·T
face keys for the neighbours, the circumcentres, the cycles and their orientation) took as long
as CGAL's triangulation itself.

* :func:`face_neighbours`: every face keyed by its smallest vertex, bucketed by that vertex
  (a counting sort, linear), each bucket sorted by the other two vertices (buckets hold a few
  dozen faces), equal neighbours paired. No global sort.
* :func:`circumcentres`: the formula of ``facets._circumcentres`` per tetrahedron.
* :func:`edge_cycles`: each in/out edge found at the first tetrahedron (in index order) that
  holds it, walked around through the face neighbours (from (a, b, c, d) across the face
  opposite c first, as the numpy walk does), its turn summed as in ``facets._oriented``; a
  second pass writes the cycles in the order of the edges' keys, reversed where the turn is
  negative.
* :func:`join_same_label`, :func:`join_pairs`, :func:`roots`: a union–find over the seeds, for
  the slabs' completeness certificate (:mod:`.slabs`).

Importing this module compiles nothing; the first call compiles and caches the machine code on
disk. The kernels live in their own file (numba checks only the defining file's timestamp
before reusing cached code) and use no compiled helper from another module.
"""

from __future__ import annotations

import numpy as np
from numba import njit

SMALL_BUCKET = 48
"""Buckets up to this many faces are sorted by insertion; larger ones by numpy's argsort."""
ROUNDING_FACTOR = 64.0
FLAT_RTOL = 1e-10
"""The same constants as :mod:`vorobound.sampling.reconstruct.facets` (which passes them in;
these are the defaults of the signatures only)."""
LOCAL_EDGES = np.array([[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]], dtype=np.int64)
"""The six edges of a tetrahedron as local corners (the order of ``facets.EDGE_PAIRS``)."""


@njit(cache=True, nogil=True, error_model="numpy")
def face_neighbours(tets, n_vertices):
    """The tetrahedron across the face opposite each corner of ``tets`` (t, 4; each row
    ascending, as a simplex tree gives them), −1 where none; ``ok`` False when a face is
    shared by more than two tetrahedra."""
    count = tets.shape[0]
    out = np.full((count, 4), -1, np.int64)
    start = np.zeros(n_vertices + 1, np.int64)
    for t in range(count):
        # The face opposite corner 0 starts at the row's second vertex, the others at its first.
        start[tets[t, 0] + 1] += 3
        start[tets[t, 1] + 1] += 1
    for v in range(n_vertices):
        start[v + 1] += start[v]
    fill = start[:-1].copy()
    keys = np.empty(4 * count, np.int64)
    refs = np.empty(4 * count, np.int64)
    for t in range(count):
        r0, r1, r2, r3 = tets[t, 0], tets[t, 1], tets[t, 2], tets[t, 3]
        spot = fill[r1]
        keys[spot], refs[spot] = r2 * n_vertices + r3, 4 * t
        fill[r1] = spot + 1
        spot = fill[r0]
        keys[spot], refs[spot] = r2 * n_vertices + r3, 4 * t + 1
        keys[spot + 1], refs[spot + 1] = r1 * n_vertices + r3, 4 * t + 2
        keys[spot + 2], refs[spot + 2] = r1 * n_vertices + r2, 4 * t + 3
        fill[r0] = spot + 3
    for v in range(n_vertices):
        low, high = start[v], start[v + 1]
        if high - low < 2:
            continue
        if high - low <= SMALL_BUCKET:
            for i in range(low + 1, high):
                key, ref = keys[i], refs[i]
                j = i - 1
                while j >= low and keys[j] > key:
                    keys[j + 1] = keys[j]
                    refs[j + 1] = refs[j]
                    j -= 1
                keys[j + 1] = key
                refs[j + 1] = ref
        else:
            order = np.argsort(keys[low:high])
            keys[low:high] = keys[low:high][order]
            refs[low:high] = refs[low:high][order]
        i = low
        while i < high - 1:
            if keys[i] == keys[i + 1]:
                if i + 2 < high and keys[i + 2] == keys[i]:
                    return out, False
                one, two = refs[i], refs[i + 1]
                out[one // 4, one % 4] = two // 4
                out[two // 4, two % 4] = one // 4
                i += 2
            else:
                i += 1
    return out, True


@njit(cache=True, nogil=True, error_model="numpy")
def circumcentres(points, tets, rounding_factor, flat_rtol):
    """Circumcentre (t, 3), rounding error (t,) and flatness (t,) of every tetrahedron (the
    formula of ``facets._circumcentres``)."""
    count = tets.shape[0]
    centres = np.empty((count, 3))
    error = np.empty(count)
    flat = np.empty(count, np.bool_)
    unit = np.finfo(np.float64).eps
    for t in range(count):
        o = points[tets[t, 0]]
        p1, p2, p3 = points[tets[t, 1]], points[tets[t, 2]], points[tets[t, 3]]
        ux, uy, uz = p1[0] - o[0], p1[1] - o[1], p1[2] - o[2]
        vx, vy, vz = p2[0] - o[0], p2[1] - o[1], p2[2] - o[2]
        wx, wy, wz = p3[0] - o[0], p3[1] - o[1], p3[2] - o[2]
        vw0, vw1, vw2 = vy * wz - vz * wy, vz * wx - vx * wz, vx * wy - vy * wx
        wu0, wu1, wu2 = wy * uz - wz * uy, wz * ux - wx * uz, wx * uy - wy * ux
        uv0, uv1, uv2 = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx
        det = ux * vw0 + uy * vw1 + uz * vw2
        uu = ux * ux + uy * uy + uz * uz
        vv = vx * vx + vy * vy + vz * vz
        ww = wx * wx + wy * wy + wz * wz
        scale = np.sqrt(uu) * np.sqrt(vv) * np.sqrt(ww)
        flat[t] = not (abs(det) > flat_rtol * scale)
        n0 = uu * vw0 + vv * wu0 + ww * uv0
        n1 = uu * vw1 + vv * wu1 + ww * uv1
        n2 = uu * vw2 + vv * wu2 + ww * uv2
        twice = 2.0 * det
        centres[t, 0] = o[0] + n0 / twice
        centres[t, 1] = o[1] + n1 / twice
        centres[t, 2] = o[2] + n2 / twice
        offset = np.sqrt(n0 * n0 + n1 * n1 + n2 * n2) / abs(twice)
        size = np.sqrt(o[0] * o[0] + o[1] * o[1] + o[2] * o[2])
        error[t] = rounding_factor * unit * (offset + size) * scale / abs(det)
    return centres, error, flat


@njit(inline="always")
def _slot(row, a, b):
    """The local corners of vertices a and b in ``row``, and the other two (ascending)."""
    p = q = -1
    for j in range(4):
        if row[j] == a:
            p = j
        elif row[j] == b:
            q = j
    first = second = -1
    for j in range(4):
        if j != p and j != q:
            if first < 0:
                first = j
            else:
                second = j
    return p, q, first, second


@njit(inline="always")
def _edge_bit(p, q):
    """Bit of the local edge {p, q} (0..5, the order of LOCAL_EDGES)."""
    low, high = min(p, q), max(p, q)
    if low == 0:
        return 1 << (high - 1)
    if low == 1:
        return 1 << (high + 1)
    return 1 << 5


@njit(inline="always")
def _next(tets, neighbors, previous, current, a, b):
    """One step of the walk around the edge ab, arriving in ``current`` from ``previous``:
    the next tetrahedron (−1 past the boundary), the vertex it shares with ``current``
    besides a and b, and the bit of the edge in ``current`` (:func:`_edge_bit`; 0 when
    ``current`` does not hold the edge)."""
    row = tets[current]
    p, q, c, d = _slot(row, a, b)
    bit = _edge_bit(p, q) if p >= 0 and q >= 0 else 0
    one, two = neighbors[current, c], neighbors[current, d]
    if one != previous:
        return one, row[d], bit
    return two, row[c], bit


@njit(inline="always")
def _turn(points, a, b, x, y):
    """det(b − a, x − a, y − a)."""
    ax, ay, az = points[a, 0], points[a, 1], points[a, 2]
    bx, by, bz = points[b, 0] - ax, points[b, 1] - ay, points[b, 2] - az
    xx, xy, xz = points[x, 0] - ax, points[x, 1] - ay, points[x, 2] - az
    yx, yy, yz = points[y, 0] - ax, points[y, 1] - ay, points[y, 2] - az
    return bx * (xy * yz - xz * yy) + by * (xz * yx - xx * yz) + bz * (xx * yy - xy * yx)


@njit(cache=True, nogil=True, error_model="numpy")
def find_edges(points, tets, neighbors, inside):
    """Every in/out edge once: its inside and outside seed, the first tetrahedron holding it,
    the length of its cycle (−1: unbounded, the walk met the hull) and its turn (the sum of
    ``facets._oriented``, added in the same order). ``ok`` False when a walk does not close
    (an inconsistent triangulation)."""
    count = tets.shape[0]
    seen = np.zeros(count, np.uint8)
    capacity = 1024
    first_tet = np.empty(capacity, np.int64)
    inner = np.empty(capacity, np.int64)
    outer = np.empty(capacity, np.int64)
    length = np.empty(capacity, np.int64)
    turn = np.empty(capacity, np.float64)
    exits = np.empty(64, np.int64)
    found = 0
    for t in range(count):
        for e in range(6):
            u, v = tets[t, LOCAL_EDGES[e, 0]], tets[t, LOCAL_EDGES[e, 1]]
            if inside[u] == inside[v] or seen[t] & (1 << e):
                continue
            a, b = (u, v) if inside[u] else (v, u)
            if found == capacity:
                capacity *= 2
                first_tet = _grown(first_tet, capacity)
                inner = _grown(inner, capacity)
                outer = _grown(outer, capacity)
                length = _grown(length, capacity)
                turn = _grown_float(turn, capacity)
            first_tet[found], inner[found], outer[found] = t, a, b
            # The walk of facets._edge_cycles: from t across the face opposite its first other
            # corner, never back. A tetrahedron's exit vertex is the one it shares with the
            # next besides a and b.
            _, _, c, d = _slot(tets[t], u, v)
            previous, current = neighbors[t, d], t
            steps = 0
            open_ = False
            while True:
                nxt, exit_, bit = _next(tets, neighbors, previous, current, u, v)
                if bit == 0 or seen[current] & bit:
                    return first_tet, inner, outer, length, turn, found, False
                seen[current] |= bit
                if steps == exits.shape[0]:
                    exits = _grown(exits, 2 * steps)
                exits[steps] = exit_
                steps += 1
                if nxt < 0:
                    open_ = True
                    break
                previous, current = current, nxt
                if current == t:
                    break
            if open_:
                # The rest of the fan, walked the other way from t, is marked as seen.
                previous, current = t, neighbors[t, d]
                while current >= 0 and current != t:
                    nxt, _, bit = _next(tets, neighbors, previous, current, u, v)
                    if bit == 0 or seen[current] & bit:
                        return first_tet, inner, outer, length, turn, found, False
                    seen[current] |= bit
                    previous, current = current, nxt
                length[found] = -1
                turn[found] = 0.0
            else:
                total = _turn(points, a, b, exits[steps - 1], exits[0])
                for k in range(1, steps):
                    total += _turn(points, a, b, exits[k - 1], exits[k])
                length[found] = steps
                turn[found] = total
            found += 1
    return first_tet, inner, outer, length, turn, found, True


@njit(cache=True, nogil=True, error_model="numpy")
def write_cycles(tets, neighbors, first_tet, inner, outer, reverse, offsets, out):
    """The tetrahedra around each bounded edge (in the order given) into ``out`` from
    ``offsets``, walked again as in :func:`find_edges` and reversed where asked."""
    for e in range(first_tet.shape[0]):
        t, a, b = first_tet[e], inner[e], outer[e]
        _, _, c, d = _slot(tets[t], a, b)
        previous, current = neighbors[t, d], t
        low, high = offsets[e], offsets[e + 1]
        for step in range(high - low):
            out[high - 1 - step if reverse[e] else low + step] = current
            previous, current = current, _next(tets, neighbors, previous, current, a, b)[0]


@njit(inline="always")
def _root(parent, v):
    """The representative of ``v``'s set (the path halved on the way)."""
    while parent[v] != v:
        parent[v] = parent[parent[v]]
        v = parent[v]
    return v


@njit(inline="always")
def _join(parent, a, b):
    ra, rb = _root(parent, a), _root(parent, b)
    if ra != rb:
        parent[max(ra, rb)] = min(ra, rb)


@njit(cache=True, nogil=True, error_model="numpy")
def join_same_label(parent, tets, certified, inside):
    """Join (union–find over ``parent``, (n,)) every two vertices of one label in each
    ``certified`` tetrahedron of ``tets`` (each vertex to the first of its label in the row:
    the same sets as all same-label edges)."""
    for t in range(tets.shape[0]):
        if not certified[t]:
            continue
        for p in range(1, 4):
            for q in range(p):
                if inside[tets[t, p]] == inside[tets[t, q]]:
                    _join(parent, tets[t, p], tets[t, q])
                    break


@njit(cache=True, nogil=True, error_model="numpy")
def join_pairs(parent, first, second):
    """Join ``first[i]`` and ``second[i]`` for every i (union–find over ``parent``)."""
    for i in range(first.shape[0]):
        _join(parent, first[i], second[i])


@njit(cache=True, nogil=True, error_model="numpy")
def roots(parent):
    """The representative of every element's set."""
    out = np.empty(parent.shape[0], np.int64)
    for v in range(parent.shape[0]):
        out[v] = _root(parent, v)
    return out


@njit(inline="always")
def _grown(array, capacity):
    bigger = np.empty(capacity, np.int64)
    bigger[: array.shape[0]] = array
    return bigger


@njit(inline="always")
def _grown_float(array, capacity):
    bigger = np.empty(capacity, np.float64)
    bigger[: array.shape[0]] = array
    return bigger
