"""Large σ-sparse ε-samples of a ring torus made row by row, for scale tests of ``check``.

The maximal sparse subset of :mod:`vorobound.sampling.sampler.maximal` visits its candidates in
one random order, which does not split into independent pieces; it stops at about 2·10⁶
samples (``MAX_CANDIDATES``). This module makes samples of any size, in chunks of rows, each
chunk from its own random stream, so memory does not grow with the sample:

On a ring torus with R ≥ 2r the local feature size is L = r everywhere (the core circle is at
distance r from every point, the z axis at ρ ≥ R − r ≥ r). Row k is the circle at tube angle
φ_k = (k + ½)·Δφ, n_φ = ⌈2πr/h⌉ rows with Δφ = 2π/n_φ, h = ``ROW_SPACING``·εL; it carries
n_k = ⌈2πρ_k/h⌉ points at angles (j + ½ + u)·2π/n_k, and every point is moved by up to
``JITTER`` of its row's steps in both angles (u and the moves are uniform random).

* σ-sparse: two points of one row are at least (1 − 2·JITTER) of a step apart along it, a
  step being at least h·(1 − h/(2πρ)); two points of different rows are at least
  (1 − 2·JITTER)·Δφ apart in tube angle; chords are shorter than arcs by a factor
  1 − O(h²/L²). With the defaults (h = εL, jitter 0.1) every pair is at least 0.79·εL apart for
  ε ≤ ``MAX_EPS``: σ = 3/4 holds.
* an ε-sample: a surface point is within half a row step in φ and half a point step in θ of a
  lattice site, and the site's point within JITTER steps of it, so within
  (½ + JITTER)·√2·h ≈ 0.85·εL.

``check`` measures both (sparsity_min is exact; coverage needs ``--torus`` with the balls).
Not a maximal sparse set and not random-looking at large scale: a test input, not a sampler.
"""

from __future__ import annotations

import math
from collections.abc import Iterator

import numpy as np

from ...errors import InputError

ROW_SPACING = 1.0
"""Row and point spacing h in units of εL."""
JITTER = 0.1
"""Each point moves by up to this fraction of its row's steps, in both angles."""
MAX_EPS = 0.1
"""Largest ε made (the sparsity argument below needs h small against the torus)."""
ROWS_PER_CHUNK = 64
"""Rows made at a time (a chunk holds about ROWS_PER_CHUNK·2πR/h points)."""


def torus_row_count(major: float, minor: float, eps: float) -> int:
    """Number of points :func:`torus_rows` makes (without making them)."""
    rows, columns = _layout(major, minor, eps)
    return int(columns.sum())


def _layout(major: float, minor: float, eps: float) -> tuple[int, np.ndarray]:
    if not (0 < minor and 2 * minor <= major and math.isfinite(major)):
        raise InputError(f"a row sample needs a torus with R >= 2r > 0, got R={major}, r={minor}")
    if not 0 < eps <= MAX_EPS:
        raise InputError(f"a row sample needs 0 < eps <= {MAX_EPS}, got {eps}")
    step = ROW_SPACING * eps * minor
    rows = math.ceil(2 * math.pi * minor / step)
    phi = (np.arange(rows) + 0.5) * (2 * math.pi / rows)
    columns = np.ceil(2 * math.pi * (major + minor * np.cos(phi)) / step).astype(np.int64)
    return rows, columns


def torus_rows(
    major: float, minor: float, eps: float, delta_ratio: float = 2.0, seed: int = 0
) -> Iterator[tuple[np.ndarray, np.ndarray]]:
    """Chunks (centers (m, 3), radii (m,)) of the row sample (module docstring), radius δL.

    Parameters
    ----------
    major, minor : float
        Torus radii R ≥ 2r.
    eps : float
        Sampling density ε ≤ 0.05.
    delta_ratio : float
        δ/ε; the balls have radius δ·L = delta_ratio·ε·r.
    seed : int
        Random seed; chunk k uses the stream (seed, k), so chunks can be made independently.
    """
    rows, columns = _layout(major, minor, eps)
    radius = delta_ratio * eps * minor
    dphi = 2 * math.pi / rows
    for chunk, first in enumerate(range(0, rows, ROWS_PER_CHUNK)):
        rng = np.random.default_rng([seed, chunk])
        row = np.arange(first, min(first + ROWS_PER_CHUNK, rows))
        count = columns[row]
        which = np.repeat(row, count)
        column = np.arange(int(count.sum())) - np.repeat(np.cumsum(count) - count, count)
        offset = rng.uniform(0, 1, len(row))
        jitter = rng.uniform(-JITTER, JITTER, (2, len(which)))
        phi = (which + 0.5 + jitter[0]) * dphi
        theta = (column + 0.5 + np.repeat(offset, count) + jitter[1]) * (
            2 * math.pi / columns[which]
        )
        rho = major + minor * np.cos(phi)
        centers = np.column_stack([rho * np.cos(theta), rho * np.sin(theta), minor * np.sin(phi)])
        yield centers, np.full(len(centers), radius)
