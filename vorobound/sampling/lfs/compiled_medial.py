"""Compiled passes of the Voronoi poles of :func:`.medial.vertex_poles` (needs the optional numba).

The numpy path of :mod:`.medial` builds every (point, side, tetrahedron) entry as a row of
arrays and sorts them: about 16 tetrahedra a point on a sampled torus, 4 entries each, so tens
of millions of rows and several GB at 10⁶ vertices (issue 35: 149 CPU-s and the 12.5 GB peak of
``lfs`` on the 10⁶-vertex torus). Here the tetrahedra are walked once, in chunks, and the
entries of each point are read from a list of its tetrahedra (a counting sort) whenever they are
needed, never stored:

* :func:`tet_edges`: the edges, squared lengths and longest edge of each tetrahedron, the input
  of the determinants and solves that stay numpy's (LAPACK), so the circumcentres are the same
  numbers;
* :func:`tet_bounds`: the radius, emptiness bound, reliability and local emptiness of each
  tetrahedron (``_locally_empty``);
* :func:`group_farthest`: per (point, side) the farthest usable circumcentre, the one the
  numpy path finds at the end of its sorted group (ties: the highest tetrahedron index, the last
  of a stable sort by distance);
* :func:`drop_containing`: the consistency test's drops (``_drop_containing``).

Every quantity is computed with the numpy path's arithmetic, in its order (sums of three
squares left to right, as numpy's reductions over three elements add them; no fused
multiply-add): the results are the same bits (tested).

All compiled helpers stay in this one file: numba checks only the defining file's timestamp
before reusing cached machine code.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True, nogil=True, error_model="numpy")
def tet_edges(points, tets, lo, hi, origin, edges, squared, longest):
    """Rows ``lo:hi`` of the tetrahedra: first corner, the three edges from it, their squared
    lengths and the longest length (into the chunk arrays, row 0 for ``lo``)."""
    for i in range(lo, hi):
        r = i - lo
        a = tets[i, 0]
        for k in range(3):
            origin[r, k] = points[a, k]
        most = -np.inf
        for j in range(3):
            b = tets[i, j + 1]
            e0 = points[b, 0] - points[a, 0]
            e1 = points[b, 1] - points[a, 1]
            e2 = points[b, 2] - points[a, 2]
            edges[r, j, 0], edges[r, j, 1], edges[r, j, 2] = e0, e1, e2
            s = e0 * e0 + e1 * e1 + e2 * e2
            squared[r, j] = s
            if s > most:
                most = s
        longest[r] = math.sqrt(most)


@njit(cache=True, nogil=True, error_model="numpy")
def _radius(points, tets, i, c0, c1, c2):
    """Largest distance from (c0, c1, c2) to the corners of tetrahedron i (NaN if any is)."""
    most = -np.inf
    for k in range(4):
        p = tets[i, k]
        d0, d1, d2 = c0 - points[p, 0], c1 - points[p, 1], c2 - points[p, 2]
        d = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
        if math.isnan(d):
            return np.nan
        if d > most:
            most = d
    return most


@njit(cache=True, nogil=True, error_model="numpy")
def tet_bounds(
    points,
    tets,
    neighbours,
    centres,
    jitter,
    lo,
    hi,
    shift,
    noise,
    keep_rtol,
    atol,
    unreliable_rtol,
    bound,
    usable,
):
    """Rows ``lo:hi``: the emptiness bound ``keep_rtol·radius − atol·(largest corner jitter)``
    (NaN where the centre is, or where ``noise > 0`` and the centre's ``shift`` per unit of
    jitter times ``noise`` exceeds ``unreliable_rtol·radius``), and ``usable``: a finite bound
    and no far vertex of a neighbouring tetrahedron closer to the centre than the bound.
    ``shift`` is indexed from ``lo`` (the chunk's)."""
    for i in range(lo, hi):
        c0, c1, c2 = centres[i, 0], centres[i, 1], centres[i, 2]
        radius = _radius(points, tets, i, c0, c1, c2)
        moved_by = jitter[tets[i, 0]]
        for k in range(1, 4):
            j = jitter[tets[i, k]]
            if j > moved_by:
                moved_by = j
        b = keep_rtol * radius - atol * moved_by
        if noise > 0 and shift[i - lo] * (noise / moved_by) > unreliable_rtol * radius:
            b = np.nan
        bound[i] = b
        ok = not math.isnan(b) and not math.isinf(b)
        for face in range(4):
            if not ok:
                break
            other = neighbours[i, face]
            if other < 0:
                continue
            # The corner of the neighbour outside this tetrahedron (its first corner if none).
            far = tets[other, 0]
            for m in range(4):
                v = tets[other, m]
                if v != tets[i, 0] and v != tets[i, 1] and v != tets[i, 2] and v != tets[i, 3]:
                    far = v
                    break
            d0, d1, d2 = points[far, 0] - c0, points[far, 1] - c1, points[far, 2] - c2
            gap = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
            ok = gap >= b
        usable[i] = ok


@njit(cache=True, nogil=True, error_model="numpy")
def incidence(tets, usable, n):
    """The usable tetrahedra of each point, by increasing index: (start (n + 1), tetrahedra)."""
    count = np.zeros(n + 1, dtype=np.int64)
    for i in range(len(tets)):
        if usable[i]:
            for k in range(4):
                count[tets[i, k] + 1] += 1
    for v in range(n):
        count[v + 1] += count[v]
    start = count.copy()
    out = np.empty(start[n], dtype=np.int64)
    fill = count[:n].copy()
    for i in range(len(tets)):
        if usable[i]:
            for k in range(4):
                v = tets[i, k]
                out[fill[v]] = i
                fill[v] += 1
    return start, out


@njit(cache=True, nogil=True, error_model="numpy")
def _entry(points, normals, centres, tets, unbounded, labels, adjacent, use_labels, v, t):
    """(side, is a candidate, distance) of point v and tetrahedron t, as ``_pole_candidates``
    computes them: side 1 where the centre lies on the normal's positive side."""
    o0 = centres[t, 0] - points[v, 0]
    o1 = centres[t, 1] - points[v, 1]
    o2 = centres[t, 2] - points[v, 2]
    side = 1 if o0 * normals[v, 0] + o1 * normals[v, 1] + o2 * normals[v, 2] > 0 else 0
    keep = unbounded[v] != (1 if side == 1 else -1)
    if keep and use_labels:
        g = labels[v]
        for k in range(4):
            if adjacent[g, labels[tets[t, k]]]:
                keep = False
                break
    return side, keep, math.sqrt(o0 * o0 + o1 * o1 + o2 * o2)


@njit(cache=True, nogil=True, error_model="numpy")
def group_farthest(
    points,
    normals,
    centres,
    tets,
    unbounded,
    labels,
    adjacent,
    use_labels,
    start,
    members,
    usable,
    vertices,
    lo,
    hi,
    best,
):
    """For the points ``vertices[lo:hi]``: ``best[2v + side]``, the usable candidate tetrahedron
    of (v, side) farthest from v (of equally far ones the highest index), −1 if none."""
    for i in range(lo, hi):
        v = vertices[i]
        far0, far1 = -np.inf, -np.inf
        t0, t1 = -1, -1
        for m in range(start[v], start[v + 1]):
            t = members[m]
            if not usable[t]:
                continue
            side, keep, d = _entry(
                points, normals, centres, tets, unbounded, labels, adjacent, use_labels, v, t
            )
            if not keep:
                continue
            if side == 1:
                if t1 < 0 or d > far1 or (d == far1 and t > t1):
                    far1, t1 = d, t
            elif t0 < 0 or d > far0 or (d == far0 and t > t0):
                far0, t0 = d, t
        best[2 * v] = t0
        best[2 * v + 1] = t1


@njit(cache=True, nogil=True, error_model="numpy")
def drop_containing(
    points,
    normals,
    centres,
    bound,
    tets,
    unbounded,
    labels,
    adjacent,
    use_labels,
    start,
    members,
    groups,
    witness,
    usable,
):
    """Mark unusable every candidate of the group ``groups[k]`` (2·point + side) whose ball
    holds the sample ``witness[k]`` (closer to the centre than its bound)."""
    for k in range(len(groups)):
        v, want = groups[k] // 2, groups[k] % 2
        w = witness[k]
        for m in range(start[v], start[v + 1]):
            t = members[m]
            side, keep, _ = _entry(
                points, normals, centres, tets, unbounded, labels, adjacent, use_labels, v, t
            )
            if not keep or side != want:
                continue
            d0 = points[w, 0] - centres[t, 0]
            d1 = points[w, 1] - centres[t, 1]
            d2 = points[w, 2] - centres[t, 2]
            if math.sqrt(d0 * d0 + d1 * d1 + d2 * d2) < bound[t]:
                usable[t] = False
