"""The tight bound's optimizer: global search and local polishes for the extremes of R − R̂.

Differential evolution searches globally, SLSQP polishes from its result and from points of a
dense feasible sample, and a point is reported only if ``feasible_mask`` accepts it.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ...errors import InputError, VoroboundWarning
from .problem import AGREE_RTOL, Problem, onto_plateau, project, with_jacobian

DE_POPSIZE = 12
"""Differential evolution population, per coordinate."""
DE_TOL = 1e-10
BEST_SAMPLE_STARTS = 3
"""Local polishes started from the best points of the dense sample."""
RANDOM_SAMPLE_STARTS = 4
"""Local polishes started from random points of the dense sample (they find other optima)."""
POLISH_FTOL = 1e-12
"""SLSQP's absolute tolerance on R − R̂/(δ²L_i), of order one; projections finish vertices."""
POLISH_FIRST_MAXITER = 15
POLISH_MAXITER = 100


def _slsqp(problem: Problem, x0: np.ndarray, sign: float, maxiter: int):
    """SLSQP for the maximum (sign 1) or minimum (sign −1); returns (x, converged)."""
    from scipy.optimize import minimize

    lo, hi = problem.box()
    result = minimize(
        lambda x: with_jacobian(lambda p: -sign * problem.objective(p), x, lo, hi),
        np.clip(x0, lo, hi),
        jac=True,
        method="SLSQP",
        bounds=list(zip(lo, hi, strict=True)),
        constraints={"type": "ineq", "fun": problem.slacks},
        options={"ftol": POLISH_FTOL, "maxiter": maxiter},
    )
    return np.clip(result.x, lo, hi), result.nit < maxiter


def polish(problem: Problem, x0: np.ndarray, sign: float) -> np.ndarray:
    """Local optimization from ``x0``: SLSQP, finished by Newton steps (see :func:`project`).

    A maximization near R̂ = 0, where SLSQP crawls, ends on that plateau if it can.
    """
    x = x0
    for maxiter in (POLISH_FIRST_MAXITER, POLISH_MAXITER):
        plateau = onto_plateau(problem, x) if sign > 0 else None
        if plateau is not None:
            return plateau
        x, converged = _slsqp(problem, x, sign, maxiter)
        if converged:
            break
    return project(problem, x)


def _global_search(problem: Problem, sign: float, seed: int, maxiter: int) -> np.ndarray:
    """Differential evolution over the box, the nonlinear constraints as constraints."""
    from scipy.optimize import NonlinearConstraint, differential_evolution

    lo, hi = problem.box()
    result = differential_evolution(
        lambda x: -sign * problem.objective(x),
        list(zip(lo, hi, strict=True)),
        constraints=NonlinearConstraint(problem.slacks, 0, np.inf),
        vectorized=True,
        updating="deferred",
        polish=False,
        seed=seed,
        popsize=DE_POPSIZE,
        maxiter=maxiter,
        tol=DE_TOL,
    )
    return result.x


def best_feasible(problem: Problem, candidates: list[np.ndarray], sign: float):
    """(coordinates, scaled R − R̂) of the best feasible candidate; raises if there is none."""
    points = np.column_stack(candidates)
    values = np.where(problem.feasible(points), sign * problem.objective(points), -np.inf)
    best = int(np.argmax(values))
    if not np.isfinite(values[best]):
        raise InputError(
            f"found no feasible guide triangle at eps={problem.params.eps:g} "
            f"(sigma={problem.params.sigma:g}): the constraint set may be empty"
        )
    return points[:, best], float(sign * values[best])


def best_of_sample(problem: Problem, sample: np.ndarray, sign: float, count: int):
    """Indices of the ``count`` best sample points and the signed scaled values of all."""
    values = sign * problem.objective(sample) if sample.shape[1] else np.empty(0)
    return np.argsort(-values)[:count], values


@dataclass(frozen=True)
class SearchEvidence:
    """Why the optimum that :func:`extremum` returns is believed global (numerical evidence)."""

    starts: int
    """Local polishes run (from the global search and from sample points)."""
    agreeing_starts: int
    """Polishes that reached the reported optimum (within ``AGREE_RTOL``)."""
    spread_of_local_optima: float | None
    """Relative spread of the agreeing polishes."""
    other_local_optima: tuple[float, ...]
    """Values of R − R̂ at the other local optima found."""
    global_search_value: float
    """R − R̂ where differential evolution stopped (before polishing)."""
    active_constraints: tuple[str, ...]
    """Constraints holding with equality at the optimum."""
    dense_samples: int
    """Feasible configurations sampled as evidence and starts."""
    dense_sample_extreme: float | None
    """The sample's best R − R̂ (never beyond the optimum, or a warning is raised)."""
    methods: tuple[str, ...] = ("differential_evolution", "SLSQP", "Newton projection")


def extremum(problem: Problem, sign: float, sample: np.ndarray, rng, maxiter: int):
    """Global search, then polishes from its result and from sample points.

    Returns the best feasible point, its scaled R − R̂ and the :class:`SearchEvidence`.
    """
    de_x = _global_search(problem, sign, int(rng.integers(2**31)), maxiter)
    picks, sample_values = best_of_sample(problem, sample, sign, BEST_SAMPLE_STARTS)
    rest = np.setdiff1d(np.arange(sample_values.size), picks)
    picks = [*picks, *rng.choice(rest, min(RANDOM_SAMPLE_STARTS, rest.size), replace=False)]
    starts = [de_x] + [sample[:, i] for i in picks]
    polished = [polish(problem, x, sign) for x in starts]
    x, value = best_feasible(problem, polished + [de_x], sign)
    unit, scale = problem.unit, max(abs(value), np.finfo(float).tiny)
    local = np.column_stack(polished)
    local = sign * problem.objective(local)[problem.feasible(local)]
    agree = local >= sign * value - AGREE_RTOL * scale
    dense = float(sign * sample_values.max() * unit) if sample_values.size else None
    if dense is not None and sign * (dense / unit - value) > AGREE_RTOL * scale:
        warnings.warn(
            f"a sampled guide triangle beats the optimizer at eps={problem.params.eps:g}: "
            "the tight bound may not be global",
            VoroboundWarning,
            stacklevel=3,
        )
    evidence = SearchEvidence(
        starts=len(starts),
        agreeing_starts=int(agree.sum()),
        spread_of_local_optima=float(np.ptp(local[agree]) / scale) if agree.any() else None,
        other_local_optima=tuple(sorted({float(f"{sign * v * unit:.12g}") for v in local[~agree]})),
        global_search_value=float(problem.objective(de_x)[0] * unit),
        active_constraints=tuple(problem.active(x)),
        dense_samples=int(sample.shape[1]),
        dense_sample_extreme=dense,
    )
    return x, value, evidence
