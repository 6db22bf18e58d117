"""Directed rounding of printed numbers that a guarantee rests on: the one formatting rule.

A printed admissible ε is a promise that every ε up to it keeps the guarantee, so it is
rounded *down*; a printed bound on R/R̂ or on R − R̂ is a promise that nothing exceeds it, so
it is rounded *up*. Rounding to nearest (``f"{x:.5g}"``) can do either: the exact tight ε* of
the ratio target is 0.00949769106…, which ``.5g`` prints as 0.0094977, an ε at which a feasible
guide triangle has R/R̂ = 1.38000050 > ρ_f.

The rounding is done in exact decimal arithmetic on the float's binary value, so the printed
decimal is on the safe side of the float itself, and reading it back (``float(text)``) gives a
float on the same side.
"""

from __future__ import annotations

import math
from decimal import ROUND_CEILING, ROUND_FLOOR, Decimal

DIGITS = 5
"""Significant digits of a printed ε* or bound in tables and text."""


def _directed(value: float, digits: int, rounding: str) -> Decimal:
    if digits < 1:
        raise ValueError("digits must be at least 1")
    exact = Decimal(value)
    if exact == 0:
        return exact
    quantum = Decimal(1).scaleb(exact.adjusted() - digits + 1)
    return exact.quantize(quantum, rounding=rounding)


def _text(number: Decimal, digits: int) -> str:
    """``number`` (already at most ``digits`` significant digits) the way ``%g`` writes it."""
    if number == 0:
        return "0"
    number = number.normalize()
    exponent = number.adjusted()
    if -5 <= exponent < digits:
        return format(number, "f")
    sign, coefficient, _ = number.as_tuple()
    mantissa = "".join(map(str, coefficient))
    mantissa = mantissa[0] + ("." + mantissa[1:] if len(mantissa) > 1 else "")
    return f"{'-' if sign else ''}{mantissa}e{exponent:+03d}"


def round_down(value: float, digits: int = DIGITS) -> float:
    """``value`` rounded toward −∞ to ``digits`` significant digits (never above ``value``)."""
    if not math.isfinite(value):
        return value
    return float(_directed(value, digits, ROUND_FLOOR))


def round_up(value: float, digits: int = DIGITS) -> float:
    """``value`` rounded toward +∞ to ``digits`` significant digits (never below ``value``)."""
    if not math.isfinite(value):
        return value
    return float(_directed(value, digits, ROUND_CEILING))


def format_down(value: float | None, digits: int = DIGITS) -> str:
    """An admissible ε (or any lower bound) for people: at most ``digits`` significant digits,
    never above ``value``; "n/a" for None or NaN, "∞"/"−∞" for infinities."""
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "n/a"
    if math.isinf(value):
        return "∞" if value > 0 else "−∞"
    return _text(_directed(float(value), digits, ROUND_FLOOR), digits)


def format_up(value: float | None, digits: int = DIGITS) -> str:
    """A bound (on R/R̂, R − R̂, a sample count's upper end) for people: at most ``digits``
    significant digits, never below ``value``; "n/a" for None or NaN, "∞" for infinity."""
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "n/a"
    if math.isinf(value):
        return "∞" if value > 0 else "−∞"
    return _text(_directed(float(value), digits, ROUND_CEILING), digits)


DOWN = "down"
"""Direction of an admissible ε, a certified ε, and anything that grows with them."""
UP = "up"
"""Direction of a bound on R/R̂ or R − R̂, and of a cost."""


def format_toward(value: float | None, direction: str | None, digits: int = DIGITS) -> str:
    """``value`` rounded toward safety: :data:`DOWN`, :data:`UP`, or None for a number no
    guarantee rests on (an input parameter, a measurement), rounded to nearest as ``%g``."""
    if direction == DOWN:
        return format_down(value, digits)
    if direction == UP:
        return format_up(value, digits)
    if direction is not None:
        raise ValueError(f"unknown rounding direction {direction!r}")
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "n/a"
    if isinstance(value, float) and math.isinf(value):
        return "∞" if value > 0 else "−∞"
    return f"{value:.{digits}g}" if isinstance(value, float) else str(value)
