"""Compiled fast path for :func:`vorobound.weighted_triangles` (needs the optional numba).

One pass per triangle computes everything the numpy path computes for a well-conditioned
row, with the same operations in the same order (so the results agree to the last bit), and
writes straight into the caller's output arrays. A row that the numpy path would refine in
higher precision (ill-conditioned, near underflow, or degenerate), or that is not finite or
overflows, is only flagged: the caller recomputes flagged rows with the numpy path, which stays
the reference implementation.

The loop bodies have no data-dependent branches: every row is computed in full (a flagged
row's numbers are overwritten later), and choices are selects. Measured single-threaded, that
is about a fifth faster per row than returning early from bad rows and calling ``frexp``.

The arithmetic mirrors, step by step:

* :func:`vorobound.geometry.triangle._row_scale` (power-of-two row scaling);
* :func:`vorobound.geometry.invariants.invariants_from_points` (eq. (2), (3), (5), (6), (31));
* :func:`vorobound.geometry.invariants.finish` (eq. (15), (29));
* :func:`vorobound.geometry.invariants.condition_estimate` (the refinement test);
* :func:`vorobound.geometry.triangle._complete_rows` (Section 3 labels, eq. (1), (32)).

Importing this module compiles nothing; the first call compiles (a few seconds) and caches
the machine code on disk for later processes. The kernels release the GIL and run on plain
threads (numba's own parallel loops would bring an OpenMP runtime, which aborts a process that
forks). The compiled helpers stay in this one file, longer than the project's usual modules,
on purpose: numba checks only the defining file's timestamp before reusing cached machine
code, so a compiled helper in another module could go stale.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit
from numba.core.errors import NumbaError

from .invariants import AREA_FLOOR, K_FLOOR, SQ_FLOOR
from .threads import chunk_bounds, run_in_threads

KERNEL_ERRORS = (NumbaError,)
"""Errors of numba itself (typing, lowering) that mean "use the numpy path instead"."""

FLAG_ASSUMPTION1 = 1
FLAG_NUMPY = 2  # not finite, out of the scalable range, or overflowing: the numpy path decides
FLAG_REFINE = 3  # ill-conditioned, near underflow or degenerate: the numpy path refines it

CHUNK_ROWS = 1 << 15
"""Rows per task handed to a worker thread; its only temporaries are row scales (25 B a row)."""

# Rows of the scalar block ``scalars[j, :]``.
SCALAR_FIELDS = (
    "circumradius",
    "orthoradius_sq",
    "shifted_orthoradius",
    "radius_gap",
    "radius_gap_unshifted",
    "paper_literal",
    "k",
    "sin_theta",
    "cos_theta",
    "radius_gap_direct",
)


@njit(inline="always")
def _fmax(x, y):
    """``numpy.fmax``: the larger of two numbers, ignoring a NaN."""
    return y if x != x else (x if y != y else (x if x >= y else y))


@njit(inline="always")
def _minimum(x, y):
    """``numpy.minimum`` for non-NaN numbers: on a tie (such as 0.0 and -0.0) the second."""
    return x if x < y else y


@njit(inline="always")
def _finite(x):
    """True for a finite float (NaN and ±inf give NaN when subtracted from themselves)."""
    return x - x == 0


@njit(inline="always")
def _row_scales(sizes, finite):
    """Power-of-two scales of ``triangle._row_scale`` for row sizes, with their reciprocals.

    ``frexp(size)`` has exponent e = (biased exponent of size) − 1022 for a normal size, so the
    scale 2^e and its reciprocal 2^−e are built from the exponent bits. A size that is zero,
    subnormal, not finite or within a factor 4 of overflow clears ``finite`` (the numpy path
    takes those rows).
    """
    scales = np.empty_like(sizes)
    inverses = np.empty_like(sizes)
    size_bits = sizes.view(np.int64)
    scale_bits = scales.view(np.int64)
    inverse_bits = inverses.view(np.int64)
    for k in range(sizes.shape[0]):
        biased = (size_bits[k] >> 52) & 0x7FF
        usable = (biased >= 1) & (biased <= 2044)
        finite[k] = finite[k] & usable
        biased = biased if usable else 1023
        scale_bits[k] = (biased + 1) << 52
        inverse_bits[k] = (2045 - biased) << 52
    return scales, inverses


@njit(inline="always")
def _scaled_vertex(points, i, j, inv_scale):
    """Vertex j of row i times the reciprocal row scale, as three components (z = 0 in 2-D).

    The scale is a power of two, so multiplying by its reciprocal rounds exactly as dividing
    by it does (the numpy path divides).
    """
    x = points[i, j, 0] * inv_scale
    y = points[i, j, 1] * inv_scale
    z = points[i, j, 2] * inv_scale if points.shape[2] == 3 else 0.0
    return x, y, z


@njit(inline="always")
def _dot(a0, a1, a2, b0, b1, b2, three):
    """a·b summed in the order of ``invariants._dot``. In 2-D the z term is left out: adding
    its +0 would turn a −0 sum into +0. (Sums of squares need no such care.)"""
    total = a0 * b0 + a1 * b1
    return total + a2 * b2 if three else total


@njit(inline="always")
def _dist_sq(points, i, j, m):
    """Squared distance between vertices j and m of row i, unscaled."""
    total = 0.0
    for axis in range(points.shape[2]):
        diff = points[i, j, axis] - points[i, m, axis]
        total += diff * diff
    return total


@njit(inline="always")
def _shifted_k(w0, w1, w2, d0, d1, d2, sq0, sq1, sq2):
    """Weights shifted by their minimum, eq. (6), and k·b²·c² of eq. (31) in the vertex-free
    form of ``invariants.k_numerator``; returns (w_min, ω0, ω1, ω2, k·b²·c²)."""
    w_min = _minimum(_minimum(w0, w1), w2)
    om0, om1, om2 = w0 - w_min, w1 - w_min, w2 - w_min
    k_num = (
        om0 * (2 * d0 - om0) * sq0
        + om1 * (2 * d1 - om1) * sq1
        + om2 * (2 * d2 - om2) * sq2
        + 2 * (om1 * om2 * d0 + om0 * om2 * d1 + om0 * om1 * d2)
    )
    return w_min, om0, om1, om2, k_num


@njit(inline="always")
def _finish_row(
    sq0, sq1, sq2, area2_sq, k_num, rt_sq, rt_sq_scale, om0, om1, om2, from_edges, error_scale,
    tolerance,
):  # fmt: skip
    """Square roots of eq. (15) and (29) and the refinement test of ``condition_estimate``.

    Returns (float64 is accurate enough, the three edges, 2·area, R, R̂ of the shifted
    triangle, R − R̂).
    """
    e0 = math.sqrt(sq0)
    e1 = math.sqrt(sq1)
    e2 = math.sqrt(sq2)
    area2 = math.sqrt(area2_sq)
    radius = e0 * e1 * e2 / (2 * area2)
    rt = math.sqrt(rt_sq) if rt_sq > 0 else 0.0
    radius_gap = k_num / (4 * area2_sq * (radius + rt))
    adj0, adj1, adj2 = e1 * e2, e0 * e2, e0 * e1
    a0, a1, a2 = abs(om0), abs(om1), abs(om2)
    inv_sin = adj0 / area2 if area2_sq > 0 else math.inf
    cond_area = inv_sin * inv_sin if from_edges else inv_sin
    size_k = a0 * (2 * adj0 + a0) * sq0 + a1 * (2 * adj1 + a1) * sq1
    size_k += a2 * (2 * adj2 + a2) * sq2
    size_k += 2 * (a1 * a2 * adj0 + a0 * a2 * adj1 + a0 * a1 * adj2)
    cond_k = 1.0 if size_k == 0 else size_k / abs(k_num)
    cond_rt = rt_sq_scale / (rt * (radius + rt))
    cond = _fmax(_fmax(cond_area, cond_k), cond_rt)
    underflow = (_minimum(_minimum(sq0, sq1), sq2) < SQ_FLOOR) | (area2_sq < AREA_FLOOR)
    underflow = underflow | ((abs(k_num) < K_FLOOR) & (size_k > 0))
    ok = (error_scale * cond <= tolerance) & (area2 > 0) & (not underflow)
    return ok, e0, e1, e2, area2, radius, rt, radius_gap


@njit(inline="always")
def _store_row(
    i, scale, e0, e1, e2, d0, d1, d2, area2, k_num, radius, rt, radius_gap, rt_sq, w_min, wa0, wa1,
    wa2, scalars, edges, first,
):  # fmt: skip
    """Write rows 0–8 of ``scalars``, the relabelled edges and the apex (``_complete_rows``).

    Section 3 labels: A is the minimum-weight vertex of the given weights ``wa``. Returns
    whether the outputs that can overflow when scaled back are finite.
    """
    orthoradius_sq = rt_sq - w_min
    apex = (0 if wa0 <= wa2 else 2) if wa0 <= wa1 else (1 if wa1 <= wa2 else 2)
    a = e0 if apex == 0 else (e1 if apex == 1 else e2)
    b = e1 if apex == 0 else (e2 if apex == 1 else e0)
    c = e2 if apex == 0 else (e0 if apex == 1 else e1)
    dot_a = d0 if apex == 0 else (d1 if apex == 1 else d2)
    bc = b * c
    # R − R̂_s = (R − R̂_t) + w_min/(R̂_t + R̂_s), eq. (5); not real when R̂_s² < 0.
    rs = math.sqrt(orthoradius_sq) if orthoradius_sq >= 0 else math.nan
    shift_gap = w_min / (rt + rs)
    shift_gap = shift_gap if rt + rs > 0 else (0.0 if orthoradius_sq >= 0 else math.nan)
    radius_out = radius * scale
    orthoradius_sq_out = orthoradius_sq * scale * scale
    literal_out = radius_gap * scale + _minimum(_minimum(wa0, wa1), wa2)
    k_out = k_num / (bc * bc) * scale * scale
    scalars[0, i] = radius_out
    scalars[1, i] = orthoradius_sq_out
    scalars[2, i] = rt * scale
    scalars[3, i] = radius_gap * scale
    scalars[4, i] = (radius_gap + shift_gap) * scale
    scalars[5, i] = literal_out
    scalars[6, i] = k_out
    scalars[7, i] = area2 / bc
    scalars[8, i] = dot_a / bc
    edges[i, 0] = a * scale
    edges[i, 1] = b * scale
    edges[i, 2] = c * scale
    first[i] = apex
    # What can overflow when scaled back (the numpy path then decides).
    return _finite(radius_out) & _finite(orthoradius_sq_out) & _finite(literal_out) & _finite(k_out)


@njit(inline="always")
def _finish_and_store(
    i, scale, sq0, sq1, sq2, d0, d1, d2, area2_sq, k_num, rt_sq, rt_sq_scale, om0, om1, om2,
    w_min, wa0, wa1, wa2, from_edges, error_scale, tolerance, scalars, edges, first,
):  # fmt: skip
    """``_finish_row`` then ``_store_row``; returns (float64 is enough, outputs are finite)."""
    ok, e0, e1, e2, area2, radius, rt, radius_gap = _finish_row(
        sq0, sq1, sq2, area2_sq, k_num, rt_sq, rt_sq_scale, om0, om1, om2, from_edges,
        error_scale, tolerance,
    )  # fmt: skip
    finite_out = _store_row(
        i, scale, e0, e1, e2, d0, d1, d2, area2, k_num, radius, rt, radius_gap, rt_sq, w_min, wa0,
        wa1, wa2, scalars, edges, first,
    )  # fmt: skip
    return ok, finite_out


@njit(inline="always")
def _row_flag(usable, ok, finite_out, wa0, wa1, wa2, pair0, pair1, pair2):
    """The row's flag, in this order: unusable input, ill-conditioned, overflow after scaling
    back, else whether eq. (1) holds (``pair`` are the squared edges opposite each vertex)."""
    holds = (abs(wa1 - wa2) <= pair0) & (abs(wa0 - wa2) <= pair1) & (abs(wa0 - wa1) <= pair2)
    plain = FLAG_ASSUMPTION1 if holds else 0
    checked = plain if finite_out else FLAG_NUMPY
    refined = checked if ok else FLAG_REFINE
    return refined if usable else FLAG_NUMPY


@njit(inline="always")
def _point_sizes(points, weights, start, stop):
    """Per row: max(|coordinate|, sqrt(max |weight|)) and whether all inputs are finite."""
    sizes = np.empty(stop - start)
    finite = np.empty(stop - start, dtype=np.bool_)
    dim = points.shape[2]
    for i in range(start, stop):
        size = 0.0
        ok = True
        for j in range(3):
            for m in range(dim):
                x = points[i, j, m]
                ok = ok & _finite(x)
                size = max(size, abs(x))
        wa0, wa1, wa2 = weights[i, 0], weights[i, 1], weights[i, 2]
        ok = ok & _finite(wa0) & _finite(wa1) & _finite(wa2)
        sizes[i - start] = max(size, math.sqrt(max(max(abs(wa0), abs(wa1)), abs(wa2))))
        finite[i - start] = ok
    return sizes, finite


@njit(cache=True, error_model="numpy", nogil=True)
def triangles_kernel(
    points, weights, start, stop, error_scale, tolerance, scalars, edges, circ, ortho, first, flags
):
    """Fill the outputs of rows ``start`` to ``stop`` from ``points[i]`` (3, d), ``weights[i]``.

    A row needs higher precision unless ``error_scale * condition <= tolerance``.
    ``flags[i]`` is 0, ``FLAG_ASSUMPTION1`` (a computed row for which eq. (1) holds),
    ``FLAG_NUMPY`` or ``FLAG_REFINE`` (rows left for the numpy path).
    """
    dim = points.shape[2]
    sizes, usable = _point_sizes(points, weights, start, stop)
    scales, inverses = _row_scales(sizes, usable)
    for i in range(start, stop):
        scale = scales[i - start]
        inv_scale = inverses[i - start]
        wa0, wa1, wa2 = weights[i, 0], weights[i, 1], weights[i, 2]
        w0 = wa0 * inv_scale * inv_scale
        w1 = wa1 * inv_scale * inv_scale
        w2 = wa2 * inv_scale * inv_scale
        # Eq. (1) uses the given coordinates. (All loads come before the first store: the
        # compiler cannot know that outputs and inputs do not overlap.)
        pair0 = _dist_sq(points, i, 1, 2)
        pair1 = _dist_sq(points, i, 0, 2)
        pair2 = _dist_sq(points, i, 0, 1)

        # Edge vectors u = p1 − p0, v = p2 − p0, e = p2 − p1 (a 2-D row has z = 0: +0 added
        # to a sum of squares changes no bit, and ``_dot`` leaves it out).
        q00, q01, q02 = _scaled_vertex(points, i, 0, inv_scale)
        q10, q11, q12 = _scaled_vertex(points, i, 1, inv_scale)
        q20, q21, q22 = _scaled_vertex(points, i, 2, inv_scale)
        u0, u1, u2 = q10 - q00, q11 - q01, q12 - q02
        v0, v1, v2 = q20 - q00, q21 - q01, q22 - q02
        f0, f1, f2 = q20 - q10, q21 - q11, q22 - q12
        sq0 = f0 * f0 + f1 * f1 + f2 * f2
        sq1 = v0 * v0 + v1 * v1 + v2 * v2
        sq2 = u0 * u0 + u1 * u1 + u2 * u2
        three = dim == 3
        d0 = _dot(u0, u1, u2, v0, v1, v2, three)
        d1 = -_dot(u0, u1, u2, f0, f1, f2, three)
        d2 = _dot(v0, v1, v2, f0, f1, f2, three)
        n0 = u1 * v2 - u2 * v1
        n1 = u2 * v0 - u0 * v2
        n2 = u0 * v1 - u1 * v0
        area2_sq = n0 * n0 + n1 * n1 + n2 * n2

        w_min, om0, om1, om2, k_num = _shifted_k(w0, w1, w2, d0, d1, d2, sq0, sq1, sq2)

        # Centers as offsets from p0, eq. (2)–(3).
        two_det = 2 * area2_sq
        g1 = om1 - om0
        g2 = om2 - om0
        cu = sq1 * d1 / two_det
        cv = sq2 * d2 / two_det
        su = (sq1 * g1 - d0 * g2) / two_det
        sv = (sq2 * g2 - d0 * g1) / two_det
        x0, x1, x2 = cu * u0 + cv * v0, cu * u1 + cv * v1, cu * u2 + cv * v2
        h0 = x0 - (su * u0 + sv * v0)
        h1 = x1 - (su * u1 + sv * v1)
        h2 = x2 - (su * u2 + sv * v2)
        xx = x0 * x0 + x1 * x1 + x2 * x2
        xhat_sq = h0 * h0 + h1 * h1 + h2 * h2
        circ[i, 0] = (q00 + x0) * scale
        circ[i, 1] = (q01 + x1) * scale
        ortho[i, 0] = (q00 + h0) * scale
        ortho[i, 1] = (q01 + h1) * scale
        if dim == 3:
            circ[i, 2] = (q02 + x2) * scale
            ortho[i, 2] = (q02 + h2) * scale
        rt_sq = xhat_sq - om0
        rt_sq_scale = xhat_sq + om0

        ok, finite_out = _finish_and_store(
            i, scale, sq0, sq1, sq2, d0, d1, d2, area2_sq, k_num, rt_sq, rt_sq_scale, om0, om1,
            om2, w_min, wa0, wa1, wa2, False, error_scale, tolerance, scalars, edges, first,
        )  # fmt: skip
        direct = (math.sqrt(xx) - math.sqrt(xhat_sq - om0)) * scale
        scalars[9, i] = direct
        flags[i] = _row_flag(
            usable[i - start], ok, finite_out & _finite(direct), wa0, wa1, wa2, pair0, pair1,
            pair2,
        )  # fmt: skip


@njit(inline="always")
def _edge_sizes(lengths, weights, start, stop):
    """Per row: max(edge, sqrt(max |weight|)) and whether the row is finite with edges > 0."""
    sizes = np.empty(stop - start)
    finite = np.empty(stop - start, dtype=np.bool_)
    for i in range(start, stop):
        la0, la1, la2 = lengths[i, 0], lengths[i, 1], lengths[i, 2]
        wa0, wa1, wa2 = weights[i, 0], weights[i, 1], weights[i, 2]
        ok = _finite(la0) & _finite(la1) & _finite(la2)
        ok = ok & _finite(wa0) & _finite(wa1) & _finite(wa2)
        ok = ok & (la0 > 0) & (la1 > 0) & (la2 > 0)
        size = max(max(la0, la1), la2)
        sizes[i - start] = max(size, math.sqrt(max(max(abs(wa0), abs(wa1)), abs(wa2))))
        finite[i - start] = ok
    return sizes, finite


@njit(cache=True, error_model="numpy", nogil=True)
def edges_kernel(
    lengths, weights, start, stop, error_scale, tolerance, scalars, edges, first, flags
):  # fmt: skip
    """Rows ``start`` to ``stop`` of Theorem 1 from edge lengths ``lengths[i]`` (edge j opposite
    vertex j) and ``weights[i]``; flags as in :func:`triangles_kernel`.
    """
    sizes, usable = _edge_sizes(lengths, weights, start, stop)
    scales, inverses = _row_scales(sizes, usable)
    for i in range(start, stop):
        scale = scales[i - start]
        inv_scale = inverses[i - start]
        la0, la1, la2 = lengths[i, 0], lengths[i, 1], lengths[i, 2]
        wa0, wa1, wa2 = weights[i, 0], weights[i, 1], weights[i, 2]
        l0, l1, l2 = la0 * inv_scale, la1 * inv_scale, la2 * inv_scale
        w0 = wa0 * inv_scale * inv_scale
        w1 = wa1 * inv_scale * inv_scale
        w2 = wa2 * inv_scale * inv_scale

        # ``invariants_from_edges``: eq. (7)–(9), (15), (31).
        sq0, sq1, sq2 = l0 * l0, l1 * l1, l2 * l2
        d0 = (sq1 + sq2 - sq0) / 2
        d1 = (sq0 + sq2 - sq1) / 2
        d2 = (sq0 + sq1 - sq2) / 2
        area2_sq = sq1 * sq2 - d0 * d0
        w_min, om0, om1, om2, k_num = _shifted_k(w0, w1, w2, d0, d1, d2, sq0, sq1, sq2)
        r_sq = sq0 * sq1 * sq2 / (4 * area2_sq)
        squares_gap = k_num / (4 * area2_sq)
        rt_sq = r_sq - squares_gap
        rt_sq_scale = r_sq + abs(squares_gap)

        ok, finite_out = _finish_and_store(
            i, scale, sq0, sq1, sq2, d0, d1, d2, area2_sq, k_num, rt_sq, rt_sq_scale, om0, om1,
            om2, w_min, wa0, wa1, wa2, True, error_scale, tolerance, scalars, edges, first,
        )  # fmt: skip
        flags[i] = _row_flag(
            usable[i - start], ok, finite_out, wa0, wa1, wa2, la0 * la0, la1 * la1, la2 * la2
        )


def run_compiled(
    points: np.ndarray, weights: np.ndarray, error_scale: float, tolerance: float
) -> tuple[dict[str, np.ndarray], np.ndarray, np.ndarray]:
    """Outputs (batch first) for ``points`` (n, 3, d) and ``weights`` (n, 3), both float64.

    Returns the fields of :class:`vorobound.WeightedTriangles` and the indices of the rows the
    kernel left for the numpy path (their entries in the fields are unset): those it could not
    compute, and the ill-conditioned ones that need extended precision.
    """
    if points.ndim != 3 or points.shape[1] != 3 or points.shape[2] not in (2, 3):
        raise ValueError(f"points must have shape (n, 3, 2) or (n, 3, 3), got {points.shape}")
    n, _, dim = points.shape
    points = _readonly(points)
    weights = _readonly(weights)
    scalars, edges, first, flags = _allocate(n, len(SCALAR_FIELDS))
    circ = np.empty((n, dim))
    ortho = np.empty((n, dim))
    run_in_threads(
        lambda chunk: triangles_kernel(
            points, weights, *chunk, error_scale, tolerance, scalars, edges, circ, ortho, first,
            flags,
        ),
        chunk_bounds(n, CHUNK_ROWS),
    )  # fmt: skip
    out, rest, refine = _collect(scalars, edges, first, flags)
    out.update(circumcenter=circ, orthocenter=ortho)
    return out, rest, refine


def run_compiled_edges(
    lengths: np.ndarray, weights: np.ndarray, error_scale: float, tolerance: float
) -> tuple[dict[str, np.ndarray], np.ndarray, np.ndarray]:
    """As :func:`run_compiled`, from edge lengths ``lengths`` (n, 3) instead of coordinates."""
    n = lengths.shape[0]
    lengths = _readonly(lengths)
    weights = _readonly(weights)
    scalars, edges, first, flags = _allocate(n, len(SCALAR_FIELDS) - 1)
    run_in_threads(
        lambda chunk: edges_kernel(
            lengths, weights, *chunk, error_scale, tolerance, scalars, edges, first, flags
        ),
        chunk_bounds(n, CHUNK_ROWS),
    )
    return _collect(scalars, edges, first, flags)


def _readonly(x: np.ndarray) -> np.ndarray:
    """A contiguous float64 read-only view (or copy) of an input.

    numba compiles one version per read-only/writable combination of the arguments; always
    passing read-only inputs keeps that to one compilation per kernel.
    """
    view = np.ascontiguousarray(x, dtype=np.float64).view()
    view.flags.writeable = False
    return view


def _allocate(n: int, n_scalars: int):
    return (
        np.empty((n_scalars, n)),
        np.empty((n, 3)),
        np.empty(n, dtype=np.int64),
        np.empty(n, dtype=np.uint8),
    )


def _collect(scalars, edges, first, flags):
    # From edges there are no centers, so no ``radius_gap_direct`` (the last scalar row).
    out = dict(zip(SCALAR_FIELDS, scalars, strict=False))
    out.update(
        edges=edges,
        min_weight_vertex=first,
        valid=(flags == 0) | (flags == FLAG_ASSUMPTION1),
        assumption1_holds=flags == FLAG_ASSUMPTION1,
    )
    return out, np.flatnonzero(flags == FLAG_NUMPY), np.flatnonzero(flags == FLAG_REFINE)
