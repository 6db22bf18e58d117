"""Precision tiers for the rational stage: float64, then extended precision, then exact.

A row is evaluated in float64 first. When the condition estimate
(:func:`vorobound.geometry.invariants.condition_estimate`) says its rounding could cost more
than ``REFINE_TOLERANCE`` in relative error, it is recomputed in ``numpy.longdouble`` (where
that type is wider than float64) and, if that is still not enough, with exact rational
arithmetic (:class:`fractions.Fraction`). Only the finished quantities are rounded to float64.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from .invariants import Invariants, Radicals, condition_estimate, finish

REFINE_TOLERANCE = 1e-13
"""A row is recomputed in higher precision when its estimated relative error exceeds this."""

ERROR_GROWTH = 4.0  # roundings along the longest chain of dependent operations
EPS64 = float(np.finfo(np.float64).epsneg)
_EPS_LONG = float(np.finfo(np.longdouble).epsneg)
_HAS_LONGDOUBLE = _EPS_LONG < EPS64 / 16


def _as_float64(x) -> np.ndarray:
    """Round to float64; exact rationals too large for it become ±inf instead of raising."""
    x = np.asarray(x)
    if x.dtype != object:
        return x.astype(np.float64)
    return np.array([_fraction_to_float(v) for v in x.ravel()], dtype=np.float64).reshape(x.shape)


def _fraction_to_float(value) -> float:
    try:
        return float(value)
    except OverflowError:
        return math.inf if value > 0 else -math.inf


def _to_fractions(x: np.ndarray) -> np.ndarray:
    flat = [Fraction(float(v)) for v in x.ravel()]
    return np.array(flat, dtype=object).reshape(x.shape)


def _finished_rows(inv: Invariants) -> tuple[dict[str, np.ndarray], Radicals]:
    """Float64 fields (batch on the last axis) from invariants of any precision.

    Rational combinations are formed in the invariants' own arithmetic (exact for
    ``Fraction``) before anything is rounded to float64. Also returns the radicals in the
    working precision, for the condition estimate.
    """
    orthoradius_sq = inv.rt_sq - inv.w_min
    if inv.k_num.dtype == object:
        inv = Invariants._make(None if f is None else _as_float64(f) for f in inv)
    rad = finish(inv)
    fields = {
        "edges": rad.edges,
        "area2": rad.area2,
        "circumradius": rad.circumradius,
        "shifted_orthoradius": rad.shifted_orthoradius,
        "radius_gap": rad.radius_gap,
        "k_num": inv.k_num,
        "dots": inv.dots,
        "w_min": inv.w_min,
        "omega0": inv.omega[0],
        "orthoradius_sq": orthoradius_sq,
    }
    if inv.circ_offset is not None:
        fields["circ_offset"] = inv.circ_offset
        fields["ortho_shift"] = inv.ortho_shift
    return {key: _as_float64(value) for key, value in fields.items()}, rad


def _exact_rows(builder, arrays: tuple[np.ndarray, ...]) -> tuple[dict, np.ndarray]:
    """Exact rational evaluation of all rows at once, or row by row if one is degenerate.

    Each numpy operation on an object array costs about the same for one row as for a few, so
    the batch goes first; a degenerate row (zero area: a division by zero) sends the batch to
    the row-by-row loop, where it fails alone.
    """
    n = arrays[0].shape[-1]
    try:
        inv = builder(*(_to_fractions(x) for x in arrays))
    except ZeroDivisionError:
        inv = None
    if inv is not None and all(area > 0 for area in inv.area2_sq):
        return _finished_rows(inv)[0], np.ones(n, dtype=bool)
    rows, ok = [], np.zeros(n, dtype=bool)
    for i in range(n):
        try:
            inv = builder(*(_to_fractions(x[..., i : i + 1]) for x in arrays))
            if inv.area2_sq[0] <= 0:
                continue
            rows.append((i, _finished_rows(inv)[0]))
        except ZeroDivisionError:
            continue
        ok[i] = True
    merged = {}
    if rows:
        index = np.array([i for i, _ in rows])
        for key, first in rows[0][1].items():
            merged[key] = np.full(first.shape[:-1] + (n,), np.nan)
            merged[key][..., index] = np.concatenate([r[key] for _, r in rows], axis=-1)
    return merged, ok


def tiered(
    builder,
    arrays: tuple[np.ndarray, ...],
    finite: np.ndarray,
    from_edges: bool,
    extended: bool = False,
) -> tuple[dict, np.ndarray]:
    """Evaluate ``builder`` in float64, refining ill-conditioned rows; return fields and validity.

    ``arrays`` hold the batch on their last axis. With ``extended``, every row starts in
    extended precision (for rows already known to fail the float64 test): the results are
    the same as refining them after a float64 pass.
    """
    if extended and _HAS_LONGDOUBLE:
        out, pending = _extended_stage(builder, arrays, from_edges)
        return _exact_tier(builder, arrays, finite, out, finite & pending)
    with np.errstate(all="ignore"):
        inv = builder(*arrays)
        out, rad = _finished_rows(inv)
        cond = condition_estimate(inv, rad, from_edges)
    pending = finite & ~(ERROR_GROWTH * EPS64 * cond <= REFINE_TOLERANCE)
    if _HAS_LONGDOUBLE and pending.any():
        idx = np.flatnonzero(pending)
        refined, still_pending = _extended_stage(
            builder, tuple(x[..., idx] for x in arrays), from_edges
        )
        for key, value in refined.items():
            out[key][..., idx] = value
        pending[:] = False
        pending[idx[still_pending]] = True
    return _exact_tier(builder, arrays, finite, out, pending)


def _extended_stage(builder, arrays, from_edges: bool) -> tuple[dict, np.ndarray]:
    """Float64 fields computed in ``numpy.longdouble``, and which rows still need exactness."""
    with np.errstate(all="ignore"):
        inv = builder(*(x.astype(np.longdouble) for x in arrays))
        out, rad = _finished_rows(inv)
        cond = condition_estimate(inv, rad, from_edges).astype(np.float64)
    return out, ~(ERROR_GROWTH * _EPS_LONG * cond <= REFINE_TOLERANCE)


def _exact_tier(builder, arrays, finite, out, pending) -> tuple[dict, np.ndarray]:
    """Redo the ``pending`` rows exactly and mark what could not be computed."""
    valid = finite.copy()
    if pending.any():
        idx = np.flatnonzero(pending)
        exact, ok = _exact_rows(builder, tuple(x[..., idx] for x in arrays))
        for key in out:
            out[key][..., idx] = exact[key] if key in exact else np.nan
        valid[idx] = ok
    # Also rejects results that overflow float64 (extended precision may not).
    valid &= np.isfinite(out["radius_gap"]) & (out["area2"] > 0) & np.isfinite(out["circumradius"])
    valid &= np.isfinite(out["edges"]).all(axis=0) & np.isfinite(out["orthoradius_sq"])
    return out, valid
