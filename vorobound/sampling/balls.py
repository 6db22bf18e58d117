"""Balls on sample points (VoroCrust's weighted points), checked once for what every later stage
assumes: finite centers, positive finite radii, distinct centers, at least four balls."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError

MIN_BALLS = 4
"""Fewer balls have no regular triangulation in space (and no guide triangle to measure)."""
LENGTH_RANGE = (1e-50, 1e50)
"""Supported radii and coordinate magnitudes (the range of local feature sizes L = r/δ that
the bounds support, :data:`vorobound.bounds.params.LFS_RANGE`): outside it, squared lengths and
the seeds' tolerances leave float64."""


@dataclass(frozen=True)
class Balls:
    """Ball centers (n, 3) and radii (n,); the weight of ball i is radii[i]²."""

    centers: np.ndarray
    radii: np.ndarray

    def __len__(self) -> int:
        return len(self.radii)

    @property
    def weights(self) -> np.ndarray:
        """Weights r², the squared radii of the weighted points."""
        return self.radii * self.radii


def make_balls(centers, radii, what: str = "balls", lines=None) -> Balls:
    """Validated :class:`Balls`; ``what`` names the input in error messages.

    ``lines`` (optional) is the file line of each ball, counted from 1, for messages about a
    row of a text file; without it a row is named by its 0-based index, as in the arrays.

    Raises
    ------
    InputError
        Wrong shapes, NaN or infinite values, radii ≤ 0, duplicate centers, fewer than
        ``MIN_BALLS`` balls.
    """
    centers, radii = checked_rows(centers, radii, what, lines=lines)
    if len(radii) < MIN_BALLS:
        raise InputError(f"{what}: need at least {MIN_BALLS} balls, got {len(radii)}")
    order = np.lexsort(centers.T[::-1])
    same = np.flatnonzero((np.diff(centers[order], axis=0) == 0).all(axis=1))
    if len(same):
        first, second = sorted((int(order[same[0]]), int(order[same[0] + 1])))
        raise InputError(
            f"{_rows_named(what, lines, 0, first, second)}: the centers coincide "
            f"({len(same)} duplicate pairs)"
        )
    return Balls(np.ascontiguousarray(centers), np.ascontiguousarray(radii))


def _rows_named(what: str, lines, first_row: int, *rows: int) -> str:
    """Rows of an input in a message: file lines (counted from 1) when known, else 0-based
    indices (offset by ``first_row`` for a chunk of a larger file)."""
    if lines is not None:
        numbers = " and ".join(str(int(lines[row])) for row in rows)
        return f"{what}, line{'s' if len(rows) > 1 else ''} {numbers}"
    indices = " and ".join(str(first_row + int(row)) for row in rows)
    return f"{what}, ball{'s' if len(rows) > 1 else ''} {indices} (0-based)"


def checked_rows(centers, radii, what: str = "balls", first_row: int = 0, lines=None):
    """``centers`` (n, 3) and ``radii`` (n,) as float arrays if every row is a valid ball
    (finite, positive radius, within ``LENGTH_RANGE``); rows are named by their file
    ``lines`` or numbered from ``first_row`` in messages (a chunk of a larger file). The
    checks of :func:`make_balls` that need the whole set (count, duplicates) are not made
    here.
    """
    centers = np.asarray(centers, dtype=float)
    radii = np.asarray(radii, dtype=float)

    def where(*rows: int) -> str:
        return _rows_named(what, lines, first_row, *rows)

    if centers.ndim != 2 or centers.shape[1] != 3:
        raise InputError(f"{what}: centers must have shape (n, 3), got {centers.shape}")
    if radii.shape != (len(centers),):
        raise InputError(f"{what}: {len(centers)} centers but radii of shape {radii.shape}")
    if not len(radii):
        return centers, radii
    bad = np.flatnonzero(~np.isfinite(centers).all(axis=1))
    if len(bad):
        raise InputError(f"{where(bad[0])}: the center is not finite ({len(bad)} such rows)")
    bad = np.flatnonzero(~(np.isfinite(radii) & (radii > 0)))
    if len(bad):
        raise InputError(
            f"{where(bad[0])}: the radius is {float(radii[bad[0]])!r}; radii must be positive "
            f"and finite ({len(bad)} such rows)"
        )
    low, high = LENGTH_RANGE
    bad = np.flatnonzero((radii < low) | (radii > high))
    if len(bad):
        raise InputError(
            f"{where(bad[0])}: radii must lie in [{low:g}, {high:g}] (the supported range), got "
            f"{float(radii[bad[0]]):g} ({len(bad)} such rows)"
        )
    bad = np.flatnonzero((np.abs(centers) > high).any(axis=1))
    if len(bad):
        raise InputError(
            f"{where(bad[0])}: coordinates must lie within ±{high:g} (the supported range), got "
            f"{float(np.abs(centers[bad[0]]).max()):g} ({len(bad)} such rows)"
        )
    return centers, radii
