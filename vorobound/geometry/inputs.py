"""Turning what callers pass (lists, arrays, masked arrays) into float64 arrays, or refusing it.

Complex numbers are refused rather than silently losing their imaginary part; masked entries
become NaN, so their rows come back invalid (NaN + ``valid == False``) like any bad row;
strings, dicts and other non-numeric input raise :class:`~vorobound.errors.InputError`.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError


def real_array(value, name: str) -> np.ndarray:
    """``value`` as a float64 array (masked entries as NaN); raise InputError if not numeric."""
    if isinstance(value, str | bytes | dict | set):
        raise InputError(f"{name} must be numbers (an array), got {type(value).__name__}")
    if np.ma.isMaskedArray(value):
        value = np.ma.filled(np.ma.asarray(value).astype(np.float64), np.nan)
    try:
        array = np.asarray(value)
    except (ValueError, TypeError) as exc:  # ragged nested lists and the like
        raise InputError(f"{name} must be a rectangular array of numbers: {exc}") from None
    if np.iscomplexobj(array):
        raise InputError(f"{name} must be real numbers, got complex values")
    if array.dtype.kind not in "biuf":
        try:
            array = array.astype(np.float64)
        except (ValueError, TypeError):
            raise InputError(f"{name} must be numbers, got {array.dtype} values") from None
    return np.asarray(array, dtype=np.float64)
