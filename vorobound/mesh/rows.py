"""Distinct rows of an integer table, fast.

``np.unique(rows, axis=0)`` views each row as one opaque record and sorts the records by bytes,
several times slower than sorting integers: on a 10⁶-vertex mesh the five tables of (vertex,
label) pairs and edges behind the estimate of L took about 20 CPU-s that way. When the
columns' ranges allow it, :func:`unique_rows` packs each row into one int64 (mixed radix: the
first column most significant, so the keys sort as the rows do), runs the one-dimensional
``np.unique`` on the keys and unpacks them. The results are the same arrays as numpy's, in
the same order; tables whose ranges do not fit fall back to numpy's call.
"""

from __future__ import annotations

from typing import Any

import numpy as np

KEY_LIMIT = 1 << 62
"""Packed keys stay below this (int64 with room to spare)."""


def unique_rows(
    rows: np.ndarray,
    return_index: bool = False,
    return_inverse: bool = False,
    return_counts: bool = False,
):
    """``np.unique(rows, axis=0, ...)`` for a 2-D integer array (module docstring).

    Returns the distinct rows in lexicographic order, followed by the optional arrays in
    numpy's order: the index of each distinct row's first occurrence, the (n,) inverse, the
    counts. The result is a tuple exactly when an option is asked for.
    """
    rows = np.asarray(rows)
    options: dict[str, Any] = dict(
        return_index=return_index, return_inverse=return_inverse, return_counts=return_counts
    )
    packed = _packed(rows)
    if packed is None:
        found = np.unique(rows, axis=0, **options)
        if return_inverse:
            found = list(found)
            found[1 + return_index] = np.asarray(found[1 + return_index]).reshape(-1)
            return tuple(found)
        return found
    keys, low, spans = packed
    if not any(options.values()):
        # Sorted keys and a mask of changes: numpy's one-dimensional unique without options
        # takes a hashing path that is several times slower on millions of distinct keys.
        keys = np.sort(keys)
        return _unpacked(keys[np.r_[True, keys[1:] != keys[:-1]]], low, spans, rows.dtype)
    found = np.unique(keys, **options)
    found = list(found)
    found[0] = _unpacked(found[0], low, spans, rows.dtype)
    if return_inverse:
        found[1 + return_index] = found[1 + return_index].reshape(-1)
    return tuple(found)


def row_keys(rows: np.ndarray) -> np.ndarray | None:
    """One int64 per row of an integer table, in the rows' lexicographic order (equal rows,
    equal keys), or None when the columns' ranges do not fit one key."""
    packed = _packed(rows)
    return None if packed is None else packed[0]


def _packed(rows: np.ndarray) -> tuple[np.ndarray, list[int], list[int]] | None:
    """(one int64 key per row, ordered as the rows are; each column's least value and span),
    or None when the rows do not fit."""
    if rows.ndim != 2 or not np.issubdtype(rows.dtype, np.integer) or not rows.size:
        return None
    low = [int(v) for v in rows.min(axis=0)]
    spans = [int(h) - lo + 1 for lo, h in zip(low, rows.max(axis=0), strict=True)]
    total = 1
    for span in spans:
        total *= span
    if total >= KEY_LIMIT:
        return None
    keys = np.zeros(len(rows), dtype=np.int64)
    for column, span in enumerate(spans):
        keys *= span
        keys += rows[:, column].astype(np.int64) - low[column]
    return keys, low, spans


def _unpacked(keys: np.ndarray, low: list[int], spans: list[int], dtype) -> np.ndarray:
    """The rows of packed ``keys`` (the inverse of :func:`_packed`)."""
    out = np.empty((len(keys), len(spans)), dtype=dtype)
    rest = keys
    for column in range(len(spans) - 1, -1, -1):
        rest, digit = np.divmod(rest, spans[column])
        out[:, column] = digit + low[column]
    return out
