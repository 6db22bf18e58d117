"""The tight bound found numerically: the supremum of R − R̂ over every feasible guide triangle
by global optimization, and the ε* it gives.

R − R̂ of eq. (29) and the constraint set of :mod:`vorobound.bounds.constraints` are stated in
:mod:`vorobound.bounds.tight.problem` and optimized by :mod:`vorobound.bounds.tight.search`;
this module reports the extremes and finds the tight ε*. The result is numerical (strong
evidence, no proof); docs/tight.md says where the closed form proves it.

Structure of the optimum, measured for σ = 3/4, δ = 2ε, ρ_f = 1.38 (evidence at ε = 0.0047:
all 8 polishes reach the same supremum, spread < 1e-15 relative; differential evolution with
13 times the iterations, three seeds, and 10⁶ sampled triangles find nothing larger, the
sample's best being 0.83 of it; the closed-form vertex below matches to 1e-15):

* Small ε, the regime of ε*: the supremum lies on the boundary, at a vertex of the
  constraint set: b = c = σεL_i (sparsity (34) and (35) tight), L_j = L_k = (1+ε)/(1−ε)·L_i
  ((33) tight twice) and R = ε/(1−ε)·L_i (H3 tight), which fixes the obtuse angle
  θ = 2 arccos(σ(1−ε)/2) ≈ 136°; the bounds (36) on a are slack. With λ = 1 the Lipschitz
  conditions to p_i replace (33): L_j = L_k = L_i(1 + λσε). At ε = 0.0047 the supremum is
  0.17841 of the target (ρ_f − 1)δL_i without λ and 0.066393 with λ = 1; the tight ε* is
  0.024781 and 0.065031 (the rigorous chain gives 0.0058164).
* Large ε: once that vertex has w_B = c², i.e. ε ≥ 0.03288 without λ (16ε/(1−ε)² = σ²) and
  ε ≥ 0.0907 with λ = 1, the weights can put the orthocenter on A, R̂ = 0, and the supremum
  is the trivial bound R ≤ ε/(1−ε)·L_i, attained on a two-dimensional family (w_B = c²,
  w_C = b², R maximal). R − R̂ is not smooth there, so a polish that approaches R̂ = 0 is
  finished by Newton steps onto that family, which reach the value.
* The infimum (−0.134 of the target at ε = 0.0047, no λ) has θ = arcsin(σ(1−ε)/2),
  b = σεL_i, L_j = L_i, L_k maximal, a = σεL_j and R maximal. Other local minima exist
  (e.g. R − R̂ = 0 at L_j = L_k = L_i), which the random starts find.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from ...errors import NoCrossing, VoroboundWarning
from ...progress import Progress, silent
from ..claims import NUMERICAL
from ..configurations import GuideConfiguration, sample_feasible
from ..eps_star import EpsStar, feasible_grid, feasible_start, find_eps_star
from ..params import QualityParams, SamplingParams
from .problem import AGREE_RTOL, Problem, checked_problem, describe
from .search import SearchEvidence, best_feasible, best_of_sample, extremum, polish

DENSE_SAMPLES = 20_000
"""Feasible configurations sampled (half biased to the boundaries) as evidence and as starts."""
DE_MAXITER = 150
SCAN_SAMPLES = 2_000
SCAN_SAMPLE_STARTS = 2
"""At each scanned ε, polishes also start from the best of ``SCAN_SAMPLES`` sampled points."""
TIGHT_SCAN_GRID = np.geomspace(1e-7, 0.999, 50)
"""ε values scanned for the first crossing of the tight bound and the target."""
VERIFY_ROUNDS = 3
"""How often ε* is recomputed after a global search finds a better maximizer than the scan."""


@dataclass(frozen=True)
class TightResult:
    """Extremes of the objective over the feasible guide triangles at one ε (numerical
    optimization): R − R̂, or (R − R̂)/R for the ratio target."""

    supremum: float
    """max R − R̂ of eq. (29) (ratio target: max (R − R̂)/R, eq. (17)), without the chain."""
    infimum: float
    """min of the same."""
    maximizer: GuideConfiguration
    """The worst guide triangle."""
    minimizer: GuideConfiguration
    evidence: SearchEvidence
    """Why the supremum is believed global: optima from several starts, a dense sample."""
    infimum_evidence: SearchEvidence
    params: SamplingParams
    """ε, λ and the target the extremes are for."""

    @property
    def eps(self) -> float:
        return self.params.eps

    @property
    def lipschitz(self) -> float | None:
        return self.params.lipschitz

    @property
    def target(self) -> str:
        return self.params.target.value


def tight_supremum(
    params: SamplingParams,
    seed: int = 0,
    *,
    dense_samples: int = DENSE_SAMPLES,
    de_maxiter: int = DE_MAXITER,
) -> TightResult:
    """Supremum and infimum of R − R̂ (additive target) or of (R − R̂)/R = 1 − R̂/R (ratio
    target R ≤ ρ_f·R̂, eq. (54)) over all feasible guide triangles at ``params.eps``.

    Parameters
    ----------
    params : SamplingParams
        ε, σ, δ/ε, L_i, the target and λ (λ ≥ 0 adds |L_x − L_y| ≤ λ|p_x − p_y| for each
        pair of vertices); ρ_f does not enter.
    seed : int
        Seeds the dense sample, the choice of starts and differential evolution.
    dense_samples, de_maxiter : int
        Budgets of the dense feasible sample and of the global search.

    Returns
    -------
    TightResult
        The extremes, their configurations (feasible by ``feasible_mask``) and the evidence.

    References
    ----------
    Eq. (29), (33)–(37), property H3 of Section 4.1.
    """
    problem = checked_problem(params)
    if problem.lipschitz == 0:
        return _constant_lfs_result(problem)
    rng = np.random.default_rng(seed)
    tri = sample_feasible(params, dense_samples, rng)
    sample = problem.coordinates(tri)
    x_max, sup, evidence = extremum(problem, 1.0, sample, rng, de_maxiter)
    x_min, inf, inf_evidence = extremum(problem, -1.0, sample, rng, de_maxiter)
    return TightResult(
        supremum=sup * problem.unit,
        infimum=inf * problem.unit,
        maximizer=describe(problem, x_max),
        minimizer=describe(problem, x_min),
        evidence=evidence,
        infimum_evidence=inf_evidence,
        params=params,
    )


def _constant_lfs_result(problem: Problem) -> TightResult:
    """λ = 0 makes L constant, so every weight is equal and R̂ = R: R − R̂ = 0 exactly."""
    x = np.array([problem.params.sigma, problem.params.sigma, np.pi / 2, 0.0, 0.0])
    config = describe(problem, x)
    evidence = SearchEvidence(
        starts=0,
        agreeing_starts=0,
        spread_of_local_optima=None,
        other_local_optima=(),
        global_search_value=0.0,
        active_constraints=("L_j = L_k = L_i (λ = 0)",),
        dense_samples=0,
        dense_sample_extreme=None,
        methods=("exact: equal weights give R̂ = R",),
    )
    return TightResult(0.0, 0.0, config, config, evidence, evidence, problem.params)


class _WarmScan:
    """ε ↦ sup(R − R̂)/target, polishing from the last maximizer, known global ones and the
    best points of a small sample (which catch a change of the maximizer's structure)."""

    def __init__(self, quality, pool: list[np.ndarray], seed: int, advance: Callable):
        self.quality, self.seed = quality, seed
        self.pool, self.last = pool, pool[-1]
        self.advance = advance
        self.found: dict[float, tuple[np.ndarray, float]] = {}
        """Maximizer and ratio per ε evaluated (so a bracket end is not searched twice)."""

    def ratio(self, eps: float) -> float:
        eps = float(eps)
        if eps not in self.found:
            problem = Problem(self.quality.at(eps))
            rng = np.random.default_rng(self.seed)
            tri = sample_feasible(problem.params, SCAN_SAMPLES, rng)
            sample = problem.coordinates(tri)
            picks, _ = best_of_sample(problem, sample, 1.0, SCAN_SAMPLE_STARTS)
            starts = [self.last, *self.pool, *sample[:, picks].T]
            polished = [polish(problem, x, 1.0) for x in starts]
            self.last, value = best_feasible(problem, polished, 1.0)
            self.found[eps] = (self.last, problem.ratio(value))
        return self.found[eps][1]

    def gap(self, eps):
        """The relative gap at a float or an array of ε (the form ``find_eps_star`` expects)."""
        self.advance("refining ε*")
        values = np.array([self.ratio(e) for e in np.atleast_1d(eps)]) - 1
        return values if np.ndim(eps) else float(values[0])

    def first_crossing(self, grid: np.ndarray) -> int:
        """Index of the first ε in ``grid`` with a positive gap (the last index if none)."""
        for index, eps in enumerate(grid):
            self.advance("scanning ε")
            if self.ratio(eps) > 1:
                return index
        return len(grid) - 1


def solve_tight(
    quality: QualityParams,
    progress: Progress | None = None,
    seed: int = 0,
    *,
    dense_samples: int = DENSE_SAMPLES,
    de_maxiter: int = DE_MAXITER,
    grid: np.ndarray = TIGHT_SCAN_GRID,
) -> EpsStar:
    """Largest ε whose numerical tight bound stays within the target: sup(R − R̂) within
    (ρ_f − 1)·δ·L_i, or sup R/R̂ within ρ_f (``target="ratio"``, eq. (54)).

    Scans ``grid`` upwards, warm-starting each ε from the previous maximizer, up to the
    first crossing; refines it with brentq (:func:`vorobound.bounds.eps_star.find_eps_star`);
    confirms the root and the bracket's lower end by full global searches, and repeats with
    their maximizers as extra starts if they beat the scan.

    Parameters
    ----------
    quality : QualityParams
        σ, δ/ε, ρ_f, L_i, the target (:mod:`vorobound.bounds.targets`) and λ of the
        Lipschitz conditions, as in :func:`tight_supremum`.
    progress : Progress, optional
        Called with ("scanning ε", done, total), ("refining ε*", ...) and ("global search", ...).
    seed, dense_samples, de_maxiter : int
        As in :func:`tight_supremum`, for the global searches.
    grid : array_like
        Increasing ε values scanned for the first crossing (those below the ε from which
        guide triangles exist, σ > √3, are dropped: the target holds vacuously there).

    Returns
    -------
    EpsStar
        Mode ``"tight"``, method ``"optimizer"``, with the maximizer at ε* and the residual
        of the search there.

    References
    ----------
    Eq. (29), (33)–(37), (54)–(55).
    """
    start = feasible_start(quality, "tight")
    if quality.lipschitz == 0:
        raise NoCrossing(
            "with lipschitz = 0 every L is equal, so R - R_hat = 0 for every guide triangle: "
            "the tight bound never reaches the target (no crossing), so no eps*"
        )
    grid = feasible_grid(grid, start)
    checked_problem(quality.at(float(grid[0])))
    report = progress or silent
    counts: dict[str, int] = {}

    def advance(phase: str) -> None:
        counts[phase] = counts.get(phase, 0) + 1
        report(phase, counts[phase], len(grid) if phase == "scanning ε" else None)

    def global_max(eps: float) -> tuple[np.ndarray, float]:
        """Maximizer and sup(R − R̂)/target at ``eps`` by the full search."""
        advance("global search")
        problem = Problem(quality.at(eps))
        rng = np.random.default_rng(seed)
        sample = problem.coordinates(sample_feasible(problem.params, dense_samples, rng))
        x, value, _ = extremum(problem, 1.0, sample, rng, de_maxiter)
        return x, problem.ratio(value)

    pool = [global_max(float(grid[0]))[0]]
    for _ in range(VERIFY_ROUNDS):
        scan = _WarmScan(quality, pool, seed, advance)
        stop = scan.first_crossing(grid)
        bracket = grid[max(stop - 1, 0) : stop + 1]
        result = find_eps_star(
            scan.gap, "tight", quality, NUMERICAL, grid=bracket, method="optimizer"
        )
        scanned = scan.found[result.eps_star]
        x_root, at_root = global_max(result.eps_star)
        x_low, at_low = global_max(result.bracket[0])
        if at_root <= scanned[1] + AGREE_RTOL * abs(scanned[1]) and at_low <= 1:
            break
        pool += [x_root, x_low]
    else:
        warnings.warn(
            "global searches kept beating the warm-started scan: the tight eps* may be off",
            VoroboundWarning,
            stacklevel=2,
        )
    x_best, best = max([scanned, (x_root, at_root)], key=lambda pair: pair[1])
    return replace(
        result,
        residual=float(best - 1),
        maximizer=describe(Problem(result.params), x_best),
    )
