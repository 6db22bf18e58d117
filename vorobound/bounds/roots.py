"""The one root finder of the package: the largest ε at which a rising gap is still ≤ 0.

Every ε* is the last point of a bracket [lo, hi] with gap(lo) ≤ 0 < gap(hi) where the bound
still meets its target. :func:`bracketed_roots` finds it for many rows at once (sweeps);
:func:`largest_root` is the same iteration on one row (the chains' and the closed form's ε*,
and the tight optimizer's, whose gap costs an optimization per call). The answer is always
the low end of the final bracket, so the ε* printed meets its target where it is evaluated.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

ROOT_ITERATIONS = 100
"""Most Illinois (safeguarded regula falsi) steps per row; rows stop as soon as their bracket
is narrow enough (typically after 6 to 10 steps)."""
ROOT_SPACINGS = 4
"""A row's root is converged when its bracket is at most this many float spacings wide."""


def bracketed_roots(gap, lo, hi, f_lo, f_hi, index, rtol: float = 0.0) -> tuple[np.ndarray, int]:
    """Vectorized Illinois iteration: for each row, the largest ε with gap ≤ 0 in [lo, hi].

    ``gap(eps, index)`` evaluates the rows ``index``; on entry gap(lo) ≤ 0 < gap(hi). Each step
    takes the secant point of log(1 + gap) against log ε (the bounds behave like powers of ε,
    so this is nearly linear; the midpoint if the point is not strictly inside), keeps the
    sign change, and halves the retained end's value after two steps on the same side, which
    makes the convergence superlinear without losing the bracket. A row stops when its bracket
    is ``ROOT_SPACINGS`` float spacings or ``rtol``·hi wide. Returns the low ends and the
    number of steps taken.
    """
    lo, hi, f_lo, f_hi = (np.array(x, dtype=float) for x in (lo, hi, f_lo, f_hi))
    index = np.asarray(index)
    side = np.zeros(lo.shape, dtype=int)
    active = np.arange(lo.size)
    steps = 0
    for _ in range(ROOT_ITERATIONS):
        width = hi[active] - lo[active]
        tolerance = np.maximum(ROOT_SPACINGS * np.spacing(hi[active]), rtol * hi[active])
        active = active[width > tolerance]
        if not active.size:
            break
        steps += 1
        a, b = lo[active], hi[active]
        with np.errstate(all="ignore"):
            fa, fb = np.log1p(f_lo[active]), np.log1p(f_hi[active])
            x = np.exp(np.log(b) - fb * (np.log(b) - np.log(a)) / (fb - fa))
        # Keep the point a few float spacings inside the bracket: when the secant lands on an
        # end (its value there is already ~0), this step then closes the bracket.
        margin = ROOT_SPACINGS / 2 * np.spacing(b)
        x = np.where(np.isfinite(x), x, 0.5 * (a + b))
        x = np.clip(x, a + margin, b - margin)
        with np.errstate(invalid="ignore"):
            fx = np.asarray(gap(x, index[active]), dtype=float)
        above = fx > 0
        rows_above, rows_below = active[above], active[~above]
        hi[rows_above], f_hi[rows_above] = x[above], fx[above]
        lo[rows_below], f_lo[rows_below] = x[~above], fx[~above]
        # Illinois: a second step on the same side halves the other end's value.
        same_above = rows_above[side[rows_above] == 1]
        same_below = rows_below[side[rows_below] == -1]
        f_lo[same_above] *= 0.5
        f_hi[same_below] *= 0.5
        side[rows_above], side[rows_below] = 1, -1
    return lo, steps


def largest_root(
    gap: Callable[[float], float], lo: float, hi: float, rtol: float = 0.0
) -> tuple[float, int]:
    """The largest ε in [lo, hi] with gap(ε) ≤ 0 (gap(lo) ≤ 0 < gap(hi)), and the steps taken.

    ``gap`` takes one float. See :func:`bracketed_roots` for the iteration and ``rtol``.
    """
    f_lo, f_hi = float(gap(lo)), float(gap(hi))
    if not (f_lo <= 0 < f_hi):
        raise ValueError(f"no bracket: gap({lo!r}) = {f_lo!r}, gap({hi!r}) = {f_hi!r}")

    def rows(eps, _index):
        return np.array([float(gap(float(e))) for e in np.atleast_1d(eps)])

    roots, steps = bracketed_roots(rows, [lo], [hi], [f_lo], [f_hi], [0], rtol)
    return float(roots[0]), steps


def step_below(root: float, holds, steps: int = 64) -> float:
    """The largest of root, and up to ``steps`` floats below it, at which ``holds`` is true
    (the root itself if none is: rounding of the check, not of the root)."""
    x = root
    for _ in range(steps):
        if holds(x):
            return x
        x = math.nextafter(x, 0.0)
    return root
