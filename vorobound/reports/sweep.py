"""Parameter sweeps: bound curves over ε, or ε* tables over σ, ρ_f, δ/ε, λ and mode."""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..bounds.chain import chain_arrays
from ..bounds.params import Mode, SamplingParams
from ..bounds.eps_star import solve_eps_star_batch
from ..errors import VoroboundError

MAX_GRID_POINTS = 10_000_000
"""Refuse grids larger than this (they would not fit in memory as tables)."""


def parse_values(text: str, name: str) -> list[float]:
    """``start:stop:num`` (inclusive, evenly spaced) or a comma list, as floats."""
    text = text.strip()
    try:
        if ":" in text:
            parts = text.split(":")
            if len(parts) != 3:
                raise ValueError
            start, stop, num = float(parts[0]), float(parts[1]), int(parts[2])
            if num < 1 or not (math.isfinite(start) and math.isfinite(stop)):
                raise ValueError
            values = np.linspace(start, stop, num).tolist()
        else:
            values = [float(v) for v in text.split(",")]
    except ValueError:
        raise VoroboundError(
            f"--{name}: expected start:stop:num or a comma list of numbers, got {text!r}"
        ) from None
    if not all(math.isfinite(v) for v in values):
        raise VoroboundError(f"--{name}: values must be finite, got {text!r}")
    return values


@dataclass(frozen=True)
class SweepTable:
    """A sweep's result: named columns and rows in deterministic (nested-loop) order."""

    columns: tuple[str, ...]
    rows: list[tuple]


@dataclass(frozen=True)
class SweepSpec:
    sigma: list[float]
    rho_f: list[float]
    delta_ratio: list[float]
    lipschitz: list[float | None]
    modes: list[Mode]
    eps: list[float] | None = None
    lfs: float = 1.0

    def combos(self):
        """(mode, λ, σ, ρ_f, δ/ε) in nested-loop order; λ only varies for the tight mode."""
        for mode in self.modes:
            lams = self.lipschitz if mode is Mode.tight else [None]
            for lam, sigma, rho_f, ratio in itertools.product(
                lams, self.sigma, self.rho_f, self.delta_ratio
            ):
                yield mode, lam, sigma, rho_f, ratio


def _validate(spec: SweepSpec) -> None:
    combos = list(spec.combos())
    for _, lam, sigma, rho_f, ratio in combos:
        SamplingParams(0.5, sigma, ratio, spec.lfs, rho_f)  # raises on a bad value
        if lam is not None and lam < 0:
            raise VoroboundError(f"--lipschitz must be non-negative, got {lam}")
    for e in spec.eps or []:
        if not 0 < e < 1:
            raise VoroboundError(f"--eps values must lie in (0, 1), got {e}")
    size = len(combos) * (len(spec.eps) if spec.eps else 1)
    if size > MAX_GRID_POINTS:
        raise VoroboundError(f"the grid has {size} points; at most {MAX_GRID_POINTS} allowed")


def _tight_value(args) -> float:
    """One tight row (module-level so that worker processes can run it)."""
    eps, lam, sigma, rho_f, ratio, lfs = args
    if eps is None:
        from ..bounds.tight import solve_tight

        params = SamplingParams(0.5, sigma, ratio, lfs, rho_f)
        return solve_tight(params, lipschitz=lam).eps_star
    from ..bounds.tight import tight_supremum

    return tight_supremum(SamplingParams(eps, sigma, ratio, lfs, rho_f), lipschitz=lam).supremum


def run_sweep(spec: SweepSpec, jobs: int = 1, step: Callable[[], None] | None = None) -> SweepTable:
    """Evaluate the grid. Closed-form modes are vectorized; tight rows run on ``jobs`` processes.

    ``step`` is called once per finished tight row (for a progress bar).
    """
    _validate(spec)
    with_eps = spec.eps is not None
    columns = ("mode", "lipschitz", "sigma", "rho_f", "delta_ratio")
    columns += ("eps", "bound", "target") if with_eps else ("eps_star",)
    rows: list[tuple] = []
    tight_jobs = []
    for mode, lam, sigma, rho_f, ratio in spec.combos():
        key = (mode.value, lam, sigma, rho_f, ratio)
        if mode is Mode.tight:
            for e in spec.eps if with_eps else [None]:
                tight_jobs.append((len(rows), (e, lam, sigma, rho_f, ratio, spec.lfs)))
                rows.append(key + ((e, None, None) if with_eps else (None,)))
        elif with_eps:
            eps = np.asarray(spec.eps)
            chain = chain_arrays(eps, sigma, ratio, spec.lfs, rho_f, mode)
            rows.extend(
                key + (float(e), float(b), float(t))
                for e, b, t in zip(eps, chain.bound, chain.target, strict=True)
            )
        else:
            rows.append(key + (None,))
    if not with_eps:
        _fill_closed_form_eps_star(rows)
    if tight_jobs:
        values = _run_tight(tight_jobs, jobs, step)
        for (index, args), value in zip(tight_jobs, values, strict=True):
            row = rows[index]
            if with_eps:
                params = SamplingParams(args[0], args[2], args[4], args[5], args[3])
                rows[index] = row[:5] + (args[0], value, params.target)
            else:
                rows[index] = row[:5] + (value,)
    return SweepTable(columns, rows)


def _fill_closed_form_eps_star(rows: list[tuple]) -> None:
    for mode in (Mode.paper, Mode.rigorous):
        index = [i for i, r in enumerate(rows) if r[0] == mode.value]
        if not index:
            continue
        sigma = np.array([rows[i][2] for i in index])
        rho_f = np.array([rows[i][3] for i in index])
        ratio = np.array([rows[i][4] for i in index])
        stars = solve_eps_star_batch(sigma, ratio, rho_f, mode)
        for i, value in zip(index, stars, strict=True):
            rows[i] = rows[i][:5] + (None if np.isnan(value) else float(value),)


def _run_tight(tight_jobs, jobs: int, step) -> list[float]:
    args = [a for _, a in tight_jobs]
    if jobs <= 1:
        out = []
        for a in args:
            out.append(_safe_tight(a))
            if step:
                step()
        return out
    from concurrent.futures import ProcessPoolExecutor

    with ProcessPoolExecutor(max_workers=jobs) as pool:
        out = []
        for value in pool.map(_safe_tight, args):
            out.append(value)
            if step:
                step()
        return out


def _safe_tight(args) -> float | None:
    """A tight row; None when that parameter set has no admissible ε (the row says so)."""
    try:
        return _tight_value(args)
    except VoroboundError:
        return None
