"""Checks of user-given values shared by every layer: real numbers in a range, seeds, counts.

Each returns the value in a plain Python type or raises :class:`~vorobound.errors.InputError`
with one line that names the value and the accepted range.
"""

from __future__ import annotations

import math
import numbers

from .errors import InputError

SEED_MAX = 2**63 - 1
"""Largest accepted random seed (seeds stay printable as int64 in outputs)."""
BRIEF_CHARS = 40
"""Longest value quoted whole in a message; longer ones (an integer of 400 digits) are cut."""


def brief(value) -> str:
    """``repr(value)`` for a one-line message, cut to about ``BRIEF_CHARS`` characters."""
    text = repr(value)
    if len(text) <= BRIEF_CHARS:
        return text
    size = (
        f"{len(text.lstrip('-'))} digits" if isinstance(value, int) else f"{len(text)} characters"
    )
    return f"{text[: BRIEF_CHARS - 10]}... ({size})"


# The supported ranges of the sampling parameters (README, "Supported parameter ranges"). They
# keep every product the bounds form (weights ~ (δ/ε)²ε³L², the allowance (ρ_f − 1)δL_i, ...)
# inside float64; every layer checks its inputs against these.
EPS_RANGE = (1e-12, 0.999)
"""Supported sampling densities ε (1 − ε ≥ 10⁻³ keeps every (1 − ε)⁻ᵏ of the chain small)."""
SIGMA_RANGE = (1e-6, 1e3)
"""Supported sparsity factors σ (σ ≥ 2 leaves no feasible guide triangle at small ε)."""
DELTA_RATIO_RANGE = (1e-6, 1e6)
"""Supported δ/ε (weights scale as (δ/ε)²)."""
RHO_F_MAX = 1e6
"""Largest supported quality constant ρ_f (ρ_f > 1 is required)."""
LFS_RANGE = (1e-50, 1e50)
"""Supported local feature sizes and lengths (the chain multiplies up to four lengths)."""
LIPSCHITZ_RANGE = (1e-12, 1e6)
"""Supported positive Lipschitz constants λ (λ = 0, constant L, is supported too)."""


def checked_number(value, name: str, low: float, high: float, *, open_low: bool = False) -> float:
    """``value`` as a float if it is a real number in [low, high] (or (low, high]); else raise."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise InputError(f"{name} must be a real number, got {brief(value)}")
    try:
        number = float(value)
    except OverflowError:  # an integer or fraction beyond float64 (10**400): out of any range
        number = math.inf
    inside = (low < number if open_low else low <= number) and number <= high
    if not (math.isfinite(number) and inside):
        bracket = "(" if open_low else "["
        raise InputError(
            f"{name} must lie in {bracket}{low:g}, {high:g}] (the supported range), "
            f"got {brief(value)}"
        )
    return number


def checked_lipschitz(value) -> float | None:
    """λ, the Lipschitz constant of L (|L(x) − L(y)| ≤ λ|x − y|), as a float: 0 allowed, None
    for "no Lipschitz condition"; else raise."""
    if value is None:
        return None
    if isinstance(value, numbers.Real) and not isinstance(value, bool) and value == 0:
        return 0.0
    return checked_number(value, "lipschitz", *LIPSCHITZ_RANGE)


def checked_length(value, name: str) -> float:
    """A length (radius, local feature size) in the supported range :data:`LFS_RANGE`."""
    return checked_number(value, name, *LFS_RANGE)


def checked_count(value, name: str, low: int, high: int) -> int:
    """``value`` as an int in [low, high]; else raise."""
    if (
        isinstance(value, bool)
        or not isinstance(value, numbers.Integral)
        or not low <= int(value) <= high
    ):
        raise InputError(f"{name} must be an integer in [{low}, {high}], got {brief(value)}")
    return int(value)


def checked_seed(seed) -> int:
    """``seed`` as an int in [0, 2⁶³ − 1]; raise InputError otherwise."""
    return checked_count(seed, "seed", 0, SEED_MAX)


MAX_RANGE_POINTS = 1_000_000
"""Most values one ``start:stop:num`` range may produce (checked before it is built)."""


def parse_values(text: str, flag: str, allow_none: bool = False) -> list[float | None]:
    """``start:stop:num`` (inclusive, evenly spaced) or a comma list, as floats.

    With ``allow_none``, the word ``none`` in a comma list stands for "no value" (the tight
    mode's "no Lipschitz condition").
    """
    text = text.strip()
    usage = f"{flag}: expected start:stop:num or a comma list of numbers, got {text!r}"
    if ":" in text:
        parts = text.split(":")
        try:
            start, stop, num = float(parts[0]), float(parts[1]), int(parts[2])
        except (ValueError, IndexError):
            raise InputError(usage) from None
        if len(parts) != 3 or not (math.isfinite(start) and math.isfinite(stop)):
            raise InputError(usage)
        if not 1 <= num <= MAX_RANGE_POINTS:
            raise InputError(f"{flag}: the number of points must be in [1, {MAX_RANGE_POINTS:,}]")
        import numpy as np

        values: list[float | None] = np.linspace(start, stop, num).tolist()
    else:
        values = []
        for item in text.split(","):
            item = item.strip()
            if allow_none and item.lower() == "none":
                values.append(None)
                continue
            try:
                values.append(float(item))
            except ValueError:
                raise InputError(usage) from None
    if not all(v is None or math.isfinite(v) for v in values):
        raise InputError(f"{flag}: values must be finite, got {text!r}")
    return values
