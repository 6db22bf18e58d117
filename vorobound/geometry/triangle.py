"""Weighted-triangle geometry in batches: centers, radii and Theorem 1's R − R̂.

Every function takes a leading batch axis (any shape ``...``), works through it in chunks so
memory stays bounded, and marks rows it cannot compute (non-finite input, collinear or
coincident points, edges that violate the triangle inequality) with NaN and ``valid=False``
instead of failing the batch.

Accuracy: rows are first evaluated in float64. Rows whose rational stage is ill-conditioned
(thin triangles, near-cancelling weight terms; see
:func:`vorobound.geometry.invariants.condition_estimate`) are recomputed in extended precision
and, if still ill-conditioned, with exact rational arithmetic, so the relative error of
``radius_gap`` stays near the float64 rounding level.
"""

from __future__ import annotations

import functools
import warnings

import numpy as np

from ..errors import InputError, VoroboundWarning
from .inputs import real_array
from .invariants import invariants_from_edges, invariants_from_points
from .kernels import load_kernel, pure_numpy
from .precision import EPS64, ERROR_GROWTH, REFINE_TOLERANCE, tiered
from .result import WeightedTriangles
from .threads import chunk_bounds, run_in_threads, thread_count

CHUNK_ROWS = 1 << 16
"""Rows per chunk: about 40 temporaries of 512 kB each, per worker thread."""

_MIN_SPREAD_ROWS = 1 << 10  # below this, splitting a batch across threads costs more than it saves


def _min_weight_vertex(weights: np.ndarray) -> np.ndarray:
    """Index of the minimum-weight vertex (the first one on ties); ``weights`` is (3, n)."""
    w0, w1, w2 = weights
    return np.where(w0 <= w1, np.where(w0 <= w2, 0, 2), np.where(w1 <= w2, 1, 2))


def _apex_first(per_vertex: np.ndarray, apex: tuple[np.ndarray, ...]) -> tuple[np.ndarray, ...]:
    """Reorder a (3, n) per-vertex array cyclically so that row 0 is the minimum-weight vertex.

    ``apex[j]`` is True where vertex j is that vertex. A select, so every bit (the sign of a
    zero included) is kept.
    """
    r0, r1, r2 = per_vertex
    is0, is1, _ = apex
    return (
        np.where(is0, r0, np.where(is1, r1, r2)),
        np.where(is0, r1, np.where(is1, r2, r0)),
        np.where(is0, r2, np.where(is1, r0, r1)),
    )


_LENGTH_FIELDS = (
    "circumradius",
    "shifted_orthoradius",
    "radius_gap",
    "radius_gap_unshifted",
    "radius_gap_direct",
    "edges",
    "circumcenter",
    "orthocenter",
)
_AREA_FIELDS = ("orthoradius_sq", "k")


def _row_scale(lengths: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """A power of two per row near max(|lengths|, sqrt|weights|).

    Dividing lengths by it (and weights by its square) is exact and keeps every intermediate
    of the kernel far from overflow and underflow; all outputs scale back exactly.
    """
    axes = tuple(range(lengths.ndim - 1))
    size = np.maximum(np.abs(lengths).max(axis=axes), np.sqrt(np.abs(weights).max(axis=0)))
    _, exponent = np.frexp(np.where(np.isfinite(size) & (size > 0), size, 1.0))
    with np.errstate(over="ignore"):  # a row at the float64 limit: inf scale, rejected later
        return np.ldexp(1.0, exponent)


def _complete(
    out: dict, valid: np.ndarray, weights: np.ndarray, scale: np.ndarray
) -> dict[str, np.ndarray]:
    """Apex-dependent fields (Section 3 labels), eq. (1), eq. (32) and the validity mask.

    ``out`` was computed on the scaled problem; ``weights`` are the given (unscaled) ones.
    """
    with np.errstate(all="ignore"):
        return _complete_rows(out, valid, weights, scale)


def _complete_rows(out, valid, weights, scale):
    first = _min_weight_vertex(weights)
    apex = tuple(first == j for j in range(3))
    a, b, c = _apex_first(out.pop("edges"), apex)
    dots = out.pop("dots")
    dot_a = np.where(apex[0], dots[0], np.where(apex[1], dots[1], dots[2]))
    w_min = out.pop("w_min")
    area2 = out.pop("area2")
    k_num = out.pop("k_num")
    out.pop("omega0")
    rs_sq = out["orthoradius_sq"]
    rt = out["shifted_orthoradius"]
    bc = b * c
    out["k"] = k_num / (bc * bc)
    out["sin_theta"] = area2 / bc
    out["cos_theta"] = dot_a / bc
    rs = np.sqrt(np.where(rs_sq >= 0, rs_sq, np.nan))
    # R − R̂_s = (R − R̂_t) + (R̂_t − R̂_s) and R̂_t² − R̂_s² = w_min (eq. (5)); R̂_s is not
    # real when its square is negative, and then neither is the difference.
    gap = np.where(rt + rs > 0, w_min / (rt + rs), np.where(rs_sq >= 0, 0.0, np.nan))
    out["radius_gap_unshifted"] = out["radius_gap"] + gap
    out["edges"] = np.stack([a, b, c])
    for key in _LENGTH_FIELDS:
        if key in out:
            out[key] = out[key] * scale
    for key in _AREA_FIELDS:
        out[key] = out[key] * scale * scale
    w0, w1, w2 = weights
    out["paper_literal"] = out["radius_gap"] + np.minimum(np.minimum(w0, w1), w2)
    valid = valid & np.isfinite(out["circumradius"]) & np.isfinite(out["orthoradius_sq"])
    for value in out.values():
        if value.dtype.kind == "f":
            value[..., ~valid] = np.nan
    out["valid"] = valid
    out["min_weight_vertex"] = first
    return out


def _points_chunk(
    points: np.ndarray, weights: np.ndarray, extended: bool = False
) -> dict[str, np.ndarray]:
    """One chunk: ``points`` (3, d, n), ``weights`` (3, n), both batch-last.

    ``extended`` starts every row in extended precision (see
    :func:`vorobound.geometry.precision.tiered`).
    """
    finite = np.isfinite(points).all(axis=(0, 1)) & np.isfinite(weights).all(axis=0)
    scale = _row_scale(points, weights)
    p = points / scale
    w = weights / scale / scale
    out, valid = tiered(invariants_from_points, (p, w), finite, False, extended)
    x = out.pop("circ_offset")
    y = out.pop("ortho_shift")
    out["circumcenter"] = p[0] + x
    out["orthocenter"] = p[0] + (x - y)
    with np.errstate(all="ignore"):
        xy = x - y
        # The textbook route: two radii from two explicit centers, then their difference.
        radius = np.sqrt((x * x).sum(axis=0))
        shifted = np.sqrt((xy * xy).sum(axis=0) - out["omega0"])
        out["radius_gap_direct"] = radius - shifted
    pair_sq = np.stack(
        [
            _dist_sq(points[1], points[2]),
            _dist_sq(points[0], points[2]),
            _dist_sq(points[0], points[1]),
        ]
    )
    out = _complete(out, valid, weights, scale)
    out["assumption1_holds"] = _assumption1(weights, pair_sq) & out["valid"]
    return out


def _dist_sq(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    with np.errstate(all="ignore"):
        d = x - y
        return (d * d).sum(axis=0)


def _assumption1(weights: np.ndarray, pair_sq: np.ndarray) -> np.ndarray:
    """Eq. (1): |w_i − w_j| ≤ |p_i − p_j|²; ``pair_sq[i]`` is the squared edge opposite i."""
    w0, w1, w2 = weights
    with np.errstate(all="ignore"):
        return (
            (np.abs(w1 - w2) <= pair_sq[0])
            & (np.abs(w0 - w2) <= pair_sq[1])
            & (np.abs(w0 - w1) <= pair_sq[2])
        )


def _edges_chunk(
    edges: np.ndarray, weights: np.ndarray, extended: bool = False
) -> dict[str, np.ndarray]:
    """One chunk: ``edges`` (3, n), edge i opposite vertex i; ``weights`` (3, n).

    ``extended`` starts every row in extended precision (see
    :func:`vorobound.geometry.precision.tiered`).
    """
    finite = np.isfinite(edges).all(axis=0) & np.isfinite(weights).all(axis=0)
    finite &= (edges > 0).all(axis=0)
    scale = _row_scale(edges, weights)
    out, valid = tiered(
        invariants_from_edges, (edges / scale, weights / scale / scale), finite, True, extended
    )
    with np.errstate(all="ignore"):
        pair_sq = edges * edges
    out = _complete(out, valid, weights, scale)
    out["assumption1_holds"] = _assumption1(weights, pair_sq) & out["valid"]
    return out


def _run_chunked(
    chunk_fn, first: np.ndarray, second: np.ndarray, spread: bool = False
) -> dict[str, np.ndarray]:
    """Run ``chunk_fn`` on batch-last slices of ``first``/``second``; outputs batch-first.

    Outputs are allocated once and each chunk writes its rows into them, so the memory beyond
    inputs and outputs is a few chunks' worth of temporaries whatever the batch size. With
    ``spread``, a batch smaller than ``CHUNK_ROWS`` is still split across the worker threads
    (worth it for rows that are slow, such as those refined in extended precision).
    """
    n = first.shape[-1]
    rows = CHUNK_ROWS
    if spread:
        rows = min(rows, max(_MIN_SPREAD_ROWS, -(-n // thread_count())))
    bounds = chunk_bounds(n, rows) or [(0, 0)]

    def compute(b):
        part = chunk_fn(
            np.ascontiguousarray(first[..., b[0] : b[1]]),
            np.ascontiguousarray(second[..., b[0] : b[1]]),
        )
        return {key: np.moveaxis(value, -1, 0) for key, value in part.items()}

    head = compute(bounds[0])
    if len(bounds) == 1:
        return head
    out = {key: np.empty((n,) + v.shape[1:], dtype=v.dtype) for key, v in head.items()}

    def store(b, part):
        for key, value in part.items():
            out[key][b[0] : b[1]] = value

    store(bounds[0], head)
    run_in_threads(lambda b: store(b, compute(b)), bounds[1:])
    return out


def _batch_shapes(lead_a: tuple, lead_b: tuple) -> tuple[int, ...]:
    try:
        return np.broadcast_shapes(lead_a, lead_b)
    except ValueError as exc:
        raise InputError(f"batch shapes {lead_a} and {lead_b} do not broadcast") from exc


def _pack(out: dict[str, np.ndarray], lead: tuple[int, ...]) -> WeightedTriangles:
    shaped = {key: value.reshape(lead + value.shape[1:]) for key, value in out.items()}
    return WeightedTriangles(**shaped)


def weighted_triangles(points, weights) -> WeightedTriangles:
    """Circumcenters, orthocenters, radii and Theorem 1's R − R̂ for weighted triangles.

    Parameters
    ----------
    points : array_like, shape (..., 3, d), d in {2, 3}
        Vertex coordinates.
    weights : array_like, shape (..., 3)
        Vertex weights (squared ball radii; may be negative). Broadcasts against the batch.

    Returns
    -------
    WeightedTriangles
        Rows that cannot be computed carry NaN and ``valid == False``.

    References
    ----------
    Eq. (1)–(3), (5)–(6), (15), (29), (31), (32).
    """
    p = real_array(points, "points")
    w = real_array(weights, "weights")
    if p.ndim < 2 or p.shape[-2] != 3 or p.shape[-1] not in (2, 3):
        raise InputError(f"points must have shape (..., 3, 2) or (..., 3, 3), got {p.shape}")
    if w.ndim < 1 or w.shape[-1] != 3:
        raise InputError(f"weights must have shape (..., 3), got {w.shape}")
    lead = _batch_shapes(p.shape[:-2], w.shape[:-1])
    p = np.broadcast_to(p, lead + p.shape[-2:]).reshape(-1, 3, p.shape[-1])
    w = np.broadcast_to(w, lead + (3,)).reshape(-1, 3)
    return _pack(_evaluate("run_compiled", _points_chunk, p, w), lead)


def _evaluate(kernel_name: str, chunk_fn, data: np.ndarray, weights: np.ndarray) -> dict:
    """Fields for ``data`` (n, ...) and ``weights`` (n, 3), batch first, by the fastest path.

    With the compiled kernel, the numpy path (``chunk_fn``) finishes the rows the kernel left:
    non-finite, out-of-range or overflowing ones as they are, and ill-conditioned, near-underflow
    or degenerate ones starting in extended precision. Both paths give the same bits.
    """
    kernel = _compiled_kernel(data.shape[0], kernel_name)
    if kernel is not None:
        try:
            out, rest, refine = kernel(data, weights, ERROR_GROWTH * EPS64, REFINE_TOLERANCE)
        except _load_compiled().KERNEL_ERRORS as exc:  # a numba that cannot compile the kernel
            message = f"the compiled kernel failed ({exc}); using the numpy path"
            warnings.warn(message, VoroboundWarning, stacklevel=3)
            kernel = None
    if kernel is None:
        return _run_chunked(chunk_fn, np.moveaxis(data, 0, -1), weights.T)
    for index, extended in ((rest, False), (refine, True)):
        if index.size:
            fixed = _run_chunked(
                functools.partial(chunk_fn, extended=extended),
                np.moveaxis(data[index], 0, -1),
                weights[index].T,
                spread=True,
            )
            for key, value in fixed.items():
                out[key][index] = value
    return out


COMPILED_MIN_ROWS = 1 << 17
"""Batches at least this large use the compiled kernel when numba is installed.

Loading numba and the cached kernel costs a process 0.6–0.8 s once, which the numpy path spends
on one to two million triangles; below this size (the bounds solvers' batches, a
single triangle from the CLI) the numpy path is used and numba is never imported."""


def _compiled_kernel(n_rows: int, name: str):
    """The compiled batch function ``name``, or None for small batches or when it cannot run.

    Small batches stay on the numpy path (see ``COMPILED_MIN_ROWS``).
    """
    if n_rows < COMPILED_MIN_ROWS or not compiled_available():
        return None
    return getattr(_load_compiled(), name)


def compiled_available() -> bool:
    """True when the compiled kernel can run: numba is installed and not switched off.

    Setting the environment variable ``VOROBOUND_PURE_NUMPY`` to a non-empty value forces
    the numpy path.
    """
    return not pure_numpy() and _load_compiled() is not None


@functools.cache
def _load_compiled():
    return load_kernel(f"{__package__}.compiled", "the compiled kernel", "the numpy path")


def theorem1_from_edges(edges, weights) -> WeightedTriangles:
    """Theorem 1 from edge lengths and weights alone, without coordinates.

    Parameters
    ----------
    edges : array_like, shape (..., 3)
        (a, b, c) with a = |BC|, b = |CA|, c = |AB| for vertices (A, B, C) in input order.
    weights : array_like, shape (..., 3)
        Weights of A, B, C. The minimum-weight vertex is found and the triangle relabelled.

    Returns
    -------
    WeightedTriangles
        Centers and ``radius_gap_direct`` are None. Rows violating the triangle inequality or with a
        non-positive edge are invalid (NaN).

    References
    ----------
    Eq. (7)–(9), (28)–(32).
    """
    e = real_array(edges, "edges")
    w = real_array(weights, "weights")
    if e.ndim < 1 or e.shape[-1] != 3:
        raise InputError(f"edges must have shape (..., 3), got {e.shape}")
    if w.ndim < 1 or w.shape[-1] != 3:
        raise InputError(f"weights must have shape (..., 3), got {w.shape}")
    lead = _batch_shapes(e.shape[:-1], w.shape[:-1])
    e = np.broadcast_to(e, lead + (3,)).reshape(-1, 3)
    w = np.broadcast_to(w, lead + (3,)).reshape(-1, 3)
    return _pack(_evaluate("run_compiled_edges", _edges_chunk, e, w), lead)
