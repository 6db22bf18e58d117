"""Candidate lattices for the sampler: one jittered candidate per small cell of the surface.

A maximal σ-sparse subset of the candidates is an ε-sample when every surface point x lies
within ``reach`` of the candidate c of its own cell, where

    reach ≤ (1 − σ')·ε·L_min / (1 + λσ'ε),   σ' = σ(1 + SPARSITY_SLACK),

L_min the smallest L on the cell and λ the Lipschitz constant of L. Proof: if c was accepted,
|x − c| ≤ reach < εL(x). Otherwise an accepted p has |c − p| < σ'ε·min(L(c), L(p)) ≤
σ'ε(L(x) + λ|x − c|), so |x − p| < reach·(1 + λσ'ε) + σ'εL(x) ≤ εL(x). Bounding L(c) by the
largest L on the cell, L_max, instead gives the alternative reach ≤ ε(L_min − σ'L_max), which
is the better one on a thin mesh triangle (where the gradient of the interpolated L is large
although L hardly changes).

Here cells are rectangles in the parameters of a surface of revolution (rows of constant
profile parameter t, each split evenly in the rotation angle); meshes have their own lattice
(:mod:`vorobound.sampling.sampler.mesh_lattice`) on the same condition. Jitter keeps the candidates
off a regular grid, whose cocircular points slow the regular triangulation down.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...errors import InputError, LatticeTooLarge
from ..surfaces.analytic import RevolutionShape
from ..surfaces.base import SPARSITY_SLACK

CANDIDATE_JITTER = 0.25
"""On a surface of revolution each candidate is its cell's center moved by up to this fraction
of the cell's size along each parameter (uniformly at random)."""
MAX_CANDIDATES = 40_000_000
"""Largest lattice built, refused before anything is allocated: its ~2.3·10⁶ samples keep a
whole check below 8 GB (measured by benchmarks/bench_check.py, case torus-limit)."""
_ROWS_PER_BLOCK = 256  # rows generated at a time (bounds the temporaries)


@dataclass(frozen=True)
class Candidates:
    """Candidate points on a surface, their L, and the covering radius that was guaranteed."""

    points: np.ndarray
    """(n, 3) candidate positions on the surface."""
    lfs: np.ndarray
    """(n,) local feature size L at each candidate."""
    reach_ratio: float
    """max over cells of reach / (ε·L_min of the cell): every surface point is within
    reach_ratio·ε·L of its cell's candidate (at most (1 − σ')/(1 + λσ'ε))."""


def cell_reach(eps: float, sigma: float, lfs_min, lipschitz: float):
    """Largest distance from a surface point to its cell's candidate that keeps every maximal
    σ-sparse subset an ε-sample (module docstring), for cells whose smallest L is ``lfs_min``.

    References
    ----------
    The sampling conditions of Section 4.1 (ε-sample, σ-sparse).
    """
    s = sigma * (1 + SPARSITY_SLACK)
    if not s < 1:
        raise InputError(f"sigma must be below 1 for a maximal sparse set to cover, got {sigma}")
    return (1 - s) * eps * np.asarray(lfs_min, dtype=float) / (1 + lipschitz * s * eps)


def candidate_limit_error(
    count: float,
    eps: float,
    at_least: bool = False,
    about: bool = False,
    limit: float = MAX_CANDIDATES,
) -> LatticeTooLarge:
    """The one refusal for lattices too large (``count`` a lower bound, an estimate, or
    exact): beyond ``limit``, the memory of a whole lattice or the time of the slab sampler."""
    amount = (
        f"at least {count:.3g}" if at_least else f"about {count:.3g}" if about else f"{count:.3g}"
    )
    why = "that fit in memory" if limit == MAX_CANDIDATES else "the slab sampler takes on"
    return LatticeTooLarge(
        f"eps={eps:g} needs {amount} lattice candidates, more than the {limit:.0e} {why} "
        "(the count grows like area/(eps·L)² and with "
        "sigma near 1): use a larger eps, or a surface with a larger L"
    )


def revolution_candidates(
    shape: RevolutionShape, eps: float, sigma: float, rng: np.random.Generator
) -> Candidates:
    """A jittered candidate lattice on a surface of revolution (rows in t, columns in angle).

    The straight parameter path between two points of a cell [t0, t1] × [α0, α1] has length at
    most sqrt((κΔt)² + (ρ_max Δα)²), κ the profile speed and ρ_max the largest axis distance
    over the row, so the cell's candidate is within (1/2 + jitter)·sqrt(s_t² + s_α²) of every
    point of the cell, s_t = κ·(t1 − t0) and s_α = ρ_max·(α1 − α0).

    Raises
    ------
    InputError
        When the lattice would exceed ``MAX_CANDIDATES``.
    """
    t_lo, t_hi = shape.t_range
    spread = 0.5 + CANDIDATE_JITTER
    fine = np.linspace(t_lo, t_hi, 4097)
    lfs_floor = float(shape.lfs_min(fine[:-1], fine[1:]).min())
    side = cell_reach(eps, sigma, lfs_floor, shape.lipschitz) / (spread * math.sqrt(2))
    length = (t_hi - t_lo) * shape.profile_speed
    # No cell is larger than side × (reach at the largest L)/spread: a lower bound on the count,
    # checked before any per-row array exists.
    lfs_top = float(shape.profile_lfs(fine).max())
    widest = float(cell_reach(eps, sigma, lfs_top, shape.lipschitz)) / spread
    at_least = shape.counts().area / (side * widest)
    if not at_least <= MAX_CANDIDATES:
        raise candidate_limit_error(at_least, eps, at_least=True)
    rows = math.ceil(length / side)
    edges = np.linspace(t_lo, t_hi, rows + 1)
    side_t = length / rows
    reach = cell_reach(eps, sigma, shape.lfs_min(edges[:-1], edges[1:]), shape.lipschitz)
    side_a = np.sqrt((reach / spread) ** 2 - side_t**2)
    columns = np.maximum(
        1, np.ceil(2 * math.pi * shape.rho_max(edges[:-1], edges[1:]) / side_a)
    ).astype(np.int64)
    total = int(columns.sum())
    if total > MAX_CANDIDATES:
        raise candidate_limit_error(total, eps)
    reached = spread * np.hypot(
        side_t, 2 * math.pi * shape.rho_max(edges[:-1], edges[1:]) / columns
    )
    ratio = float((reached / (eps * shape.lfs_min(edges[:-1], edges[1:]))).max())
    points = np.empty((total, 3))
    lfs = np.empty(total)
    starts = np.concatenate([[0], np.cumsum(columns)])
    for first in range(0, rows, _ROWS_PER_BLOCK):
        last = min(first + _ROWS_PER_BLOCK, rows)
        lo, hi = starts[first], starts[last]
        row = np.repeat(np.arange(first, last), columns[first:last])
        column = np.arange(lo, hi) - starts[row]
        jitter = rng.uniform(-CANDIDATE_JITTER, CANDIDATE_JITTER, size=(2, hi - lo))
        t = edges[row] + (0.5 + jitter[0]) * (edges[row + 1] - edges[row])
        angle = (column + 0.5 + jitter[1]) * (2 * math.pi / columns[row])
        points[lo:hi] = shape.embed(t, angle)
        lfs[lo:hi] = shape.profile_lfs(t)
    return Candidates(points, lfs, ratio)
