"""The tight bound: the exact supremum of R − R̂ over every feasible guide triangle.

The chain (33)–(53) bounds each term of (29) separately; here Theorem 1's R − R̂
(``GuideTriangles.delta``) is maximized over the whole constraint set of
:mod:`vorobound.bounds.feasible`, in normalized coordinates

    x = (b/(εL_i), c/(εL_i), θ, s_j, s_k),   L_j = L_i(1 + s_j·2ε/(1−ε)), s_j, s_k ∈ [0, 1],

in which the feasible set barely changes with ε. Differential evolution searches globally,
SLSQP polishes from its result and from points of a dense feasible sample, and a point is
reported only if ``feasible_mask`` accepts it.

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
  finished by Newton steps onto that family, which certify the value.
* The infimum (−0.134 of the target at ε = 0.0047, no λ) has θ = arcsin(σ(1−ε)/2),
  b = σεL_i, L_j = L_i, L_k maximal, a = σεL_j and R maximal. Other local minima exist
  (e.g. R − R̂ = 0 at L_j = L_k = L_i), which the random starts find.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, replace

import numpy as np

from ..errors import VoroboundError
from .feasible import GuideTriangles, feasible_mask, sample_feasible
from .params import SamplingParams
from .solve import EpsStar, find_eps_star

DENSE_SAMPLES = 20_000
"""Feasible configurations sampled (half biased to the boundaries) as evidence and as starts."""
DE_POPSIZE = 12
"""Differential evolution population, per coordinate."""
DE_MAXITER = 150
DE_TOL = 1e-10
BEST_SAMPLE_STARTS = 3
"""Local polishes started from the best points of the dense sample."""
RANDOM_SAMPLE_STARTS = 4
"""Local polishes started from random points of the dense sample (they find other optima)."""
SCAN_SAMPLES = 2_000
SCAN_SAMPLE_STARTS = 2
"""At each scanned ε, polishes also start from the best of ``SCAN_SAMPLES`` sampled points."""
POLISH_FTOL = 1e-12
"""SLSQP's absolute tolerance on R − R̂/(δ²L_i), of order one; projections finish vertices."""
POLISH_FIRST_MAXITER = 15
POLISH_MAXITER = 100
PROJECTION_STEPS = 6
"""Newton steps onto active constraints (quadratic convergence: three or four suffice)."""
PLATEAU_TRIGGER = 0.05
"""Try the Newton steps onto R̂ = 0 once R̂ < PLATEAU_TRIGGER·R."""
FD_STEP = 1e-7
"""Finite-difference step in normalized coordinates (all of order one)."""
AGREE_RTOL = 1e-9
"""Optima within this relative distance of the best count as the same optimum."""
ACTIVE_ATOL = 1e-9
"""A constraint whose normalized slack is below this is active (reported, projected onto)."""
TIGHT_SCAN_GRID = np.geomspace(1e-7, 0.999, 50)
"""ε values scanned for the first crossing of the tight bound and the target."""
VERIFY_ROUNDS = 3
"""How often ε* is recomputed after a global search finds a better maximizer than the scan."""


@dataclass(frozen=True)
class TightResult:
    """Extremes of R − R̂ over the feasible guide triangles at one ε."""

    supremum: float
    """max R − R̂ of eq. (29), without the chain (33)–(53)."""
    infimum: float
    """min R − R̂."""
    maximizer: dict
    """b, c, theta, lfs_j, lfs_k, a, circumradius, w_b, w_c (eq. (37)) of the worst triangle."""
    minimizer: dict
    evidence: dict
    """Why the optimum is believed global: optima from several starts, a dense sample."""
    eps: float
    lipschitz: float | None


@dataclass(frozen=True)
class _Problem:
    """The constraint set of :mod:`vorobound.bounds.feasible` in normalized coordinates.

    Coordinates are (5, ...) arrays with the batch last.
    """

    params: SamplingParams
    lipschitz: float | None

    @property
    def lfs_span(self) -> float:
        """(L_max − L_i)/L_i = 2ε/(1−ε), eq. (33)."""
        return 2 * self.params.eps / (1 - self.params.eps)

    @property
    def unit(self) -> float:
        """δ²L_i: R − R̂ over it is of order one at every ε (weights are O(δ²L_i·ε), eq. (37))."""
        return self.params.delta**2 * self.params.lfs

    def box(self) -> tuple[np.ndarray, np.ndarray]:
        """Coordinate bounds: (34)–(35), (33), and θ from sin of every angle ≥ σ(1−ε)/2 (48)."""
        eps, sigma = self.params.eps, self.params.sigma
        k_sin = sigma * (1 - eps) / 2
        if k_sin >= 1:  # then also σεL_i ≥ 2ε/(1−ε)·L_i: no edge length is allowed
            raise VoroboundError(f"no feasible guide triangle for sigma={sigma:g}, eps={eps:g}")
        theta_lo = np.arcsin(k_sin)
        # An obtuse θ leaves two acute angles, each ≥ arcsin(k_sin).
        theta_hi = max(np.pi / 2, np.pi - 2 * theta_lo)
        lo = np.array([sigma, sigma, theta_lo, 0.0, 0.0])
        hi = np.array([2 / (1 - eps), 2 / (1 - eps), theta_hi, 1.0, 1.0])
        return lo, hi

    def triangles(self, x) -> GuideTriangles:
        eps, lfs, span = self.params.eps, self.params.lfs, self.lfs_span
        u_b, u_c, theta, s_j, s_k = x
        return GuideTriangles.of(
            u_b * eps * lfs, u_c * eps * lfs, theta, lfs * (1 + span * s_j), lfs * (1 + span * s_k)
        )

    def coordinates(self, tri: GuideTriangles) -> np.ndarray:
        lfs, scale = self.params.lfs, self.params.eps * self.params.lfs
        span = lfs * self.lfs_span
        s_j, s_k = (tri.lfs_j - lfs) / span, (tri.lfs_k - lfs) / span
        return np.stack([tri.b / scale, tri.c / scale, tri.theta, s_j, s_k])

    def slacks(self, x) -> np.ndarray:
        """Nonlinear constraints as slacks ≥ 0 (names in :meth:`slack_names`), eq. (36), H3."""
        eps, sigma = self.params.eps, self.params.sigma
        u_b, u_c, _, s_j, s_k = x
        a = _side_a(x)
        rows = [
            2 * (1 + eps) / (1 - eps) ** 2 - a,
            # Not smooth where s_j = s_k, which matters only if it is active there.
            a - sigma * (1 + self.lfs_span * np.minimum(s_j, s_k)),
            self.radius_slack(x),
        ]
        if self.lipschitz is not None:
            lam, per_unit = self.lipschitz, 2 / (1 - eps)
            rows += [lam * u_c - per_unit * s_j, lam * u_b - per_unit * s_k]
            rows += [lam * a - per_unit * (s_k - s_j), lam * a - per_unit * (s_j - s_k)]
        return np.array(rows)

    def slack_names(self) -> list[str]:
        names = ["a = 2ε(1+ε)/(1−ε)²·L_i (36)", "a = σε·min(L_j, L_k) (36)"]
        names += ["R = ε/(1−ε)·L_i (H3)"]
        if self.lipschitz is not None:
            names += ["L_j − L_i = λc", "L_k − L_i = λb", "L_k − L_j = λa", "L_j − L_k = λa"]
        return names

    def radius_slack(self, x) -> np.ndarray:
        """R ≤ ε/(1−ε)·L_i as 2 sin θ/(1−ε) − a/(εL_i) ≥ 0 (times 2 sin θ > 0), property H3."""
        return 2 * np.sin(x[2]) / (1 - self.params.eps) - _side_a(x)

    def plateau_equations(self, x) -> np.ndarray:
        """Zero where R = ε/(1−ε)·L_i and R̂ = 0 (w_B = c², w_C = b², the orthocenter is A)."""
        u_b, u_c, _, s_j, s_k = x
        ratio_sq, span = self.params.delta_ratio**2, self.lfs_span
        return np.array(
            [
                self.radius_slack(x),
                u_c**2 - ratio_sq * span * s_j * (2 + span * s_j),
                u_b**2 - ratio_sq * span * s_k * (2 + span * s_k),
            ]
        )

    def active(self, x: np.ndarray) -> list[str]:
        """Names of the constraints holding with equality at ``x`` (θ bounds are implied)."""
        lo, hi = self.box()
        names_lo = ("b = σεL_i (35)", "c = σεL_i (34)", "", "L_j = L_i", "L_k = L_i")
        names_hi = ("b = 2ε/(1−ε)·L_i (35)", "c = 2ε/(1−ε)·L_i (34)", "")
        names_hi += ("L_j = (1+ε)/(1−ε)·L_i (33)", "L_k = (1+ε)/(1−ε)·L_i (33)")
        pairs = list(zip(names_lo, x - lo, strict=True))
        pairs += list(zip(names_hi, hi - x, strict=True))
        pairs += list(zip(self.slack_names(), self.slacks(x), strict=True))
        pairs += [("R̂ = 0 (w_B = c², w_C = b²)", np.abs(self.plateau_equations(x)[1:]).max())]
        return [name for name, slack in pairs if name and abs(slack) <= ACTIVE_ATOL]

    def scaled_delta(self, x) -> np.ndarray:
        """(R − R̂)/(δ²L_i) at the coordinates ``x``, eq. (29)."""
        return self.triangles(x).delta(self.params) / self.unit

    def ratio(self, scaled: float) -> float:
        """A scaled R − R̂ as a fraction of the target (ρ_f − 1)δL_i, eq. (55)."""
        return scaled * self.unit / self.params.target

    def feasible(self, x) -> np.ndarray:
        return feasible_mask(self.triangles(x), self.params, self.lipschitz)


def _side_a(x) -> np.ndarray:
    """a/(εL_i) by the law of cosines in the cancellation-free form (b−c)² + 4bc sin²(θ/2)."""
    u_b, u_c, theta = x[0], x[1], x[2]
    half = np.sin(theta / 2)
    return np.sqrt((u_b - u_c) ** 2 + 4 * u_b * u_c * half * half)


def _with_jacobian(fn: Callable, x: np.ndarray, lo: np.ndarray, hi: np.ndarray):
    """``fn(x)`` and its Jacobian by differences inside the box, from one batched call of ``fn``.

    ``fn`` maps (5, S) coordinates to (..., S) values. Differences are central where the box
    allows and one-sided at its faces (R − R̂ has a kink at L = L_i, where A stops being the
    minimum-weight vertex).
    """
    steps = np.minimum(FD_STEP, (hi - lo) / 4)
    up = np.where(x + steps <= hi, steps, 0.0)
    down = np.where(x - steps >= lo, steps, 0.0)
    values = fn(np.column_stack([x, x[:, None] + np.diag(up), x[:, None] - np.diag(down)]))
    n = len(x)
    return values[..., 0], (values[..., 1 : n + 1] - values[..., n + 1 :]) / (up + down)


def _project(problem: _Problem, x: np.ndarray, extra: Callable | None = None) -> np.ndarray:
    """Snap ``x`` to the box faces it touches, then least-norm Newton steps onto the active
    nonlinear constraints (and the equations ``extra``, if given), with the rest fixed.

    SLSQP stops with active constraints violated by up to ~1e-11; this removes that while
    moving R − R̂ only at that level.
    """
    lo, hi = problem.box()
    x = np.where(x - lo <= ACTIVE_ATOL, lo, np.where(hi - x <= ACTIVE_ATOL, hi, x))
    free = (x > lo) & (x < hi)
    active = problem.slacks(x) <= ACTIVE_ATOL

    def equations(p):
        rows = problem.slacks(p)[active]
        return rows if extra is None else np.concatenate([rows, extra(p)])

    if free.any() and (active.any() or extra is not None):
        for _ in range(PROJECTION_STEPS):
            residual, jacobian = _with_jacobian(equations, x, lo, hi)
            x[free] -= np.linalg.lstsq(jacobian[:, free], residual, rcond=None)[0]
    return np.clip(x, lo, hi)


def _onto_plateau(problem: _Problem, x: np.ndarray) -> np.ndarray | None:
    """A feasible point with R̂ = 0 and R maximal near ``x``, or None.

    R − R̂ ≤ R ≤ ε/(1−ε)·L_i for every feasible triangle, so such a point is a global maximizer.
    """
    tri = problem.triangles(x)
    if not tri.delta(problem.params)[0] >= (1 - PLATEAU_TRIGGER) * tri.circumradius[0]:
        return None
    with np.errstate(all="ignore"):
        y = _project(problem, x, problem.plateau_equations)
    r_max = problem.params.eps / (1 - problem.params.eps) * problem.params.lfs / problem.unit
    reached = problem.scaled_delta(y)[0] >= r_max * (1 - AGREE_RTOL)
    return y if reached and problem.feasible(y)[0] else None


def _slsqp(problem: _Problem, x0: np.ndarray, sign: float, maxiter: int):
    """SLSQP for the maximum (sign 1) or minimum (sign −1); returns (x, converged)."""
    from scipy.optimize import minimize

    lo, hi = problem.box()
    result = minimize(
        lambda x: _with_jacobian(lambda p: -sign * problem.scaled_delta(p), x, lo, hi),
        np.clip(x0, lo, hi),
        jac=True,
        method="SLSQP",
        bounds=list(zip(lo, hi, strict=True)),
        constraints={"type": "ineq", "fun": problem.slacks},
        options={"ftol": POLISH_FTOL, "maxiter": maxiter},
    )
    return np.clip(result.x, lo, hi), result.nit < maxiter


def _polish(problem: _Problem, x0: np.ndarray, sign: float) -> np.ndarray:
    """Local optimization from ``x0``: SLSQP, finished by Newton steps (see :func:`_project`).

    A maximization near R̂ = 0, where SLSQP crawls, ends on that plateau if it can.
    """
    x = x0
    for maxiter in (POLISH_FIRST_MAXITER, POLISH_MAXITER):
        plateau = _onto_plateau(problem, x) if sign > 0 else None
        if plateau is not None:
            return plateau
        x, converged = _slsqp(problem, x, sign, maxiter)
        if converged:
            break
    return _project(problem, x)


def _global_search(problem: _Problem, sign: float, seed: int, maxiter: int) -> np.ndarray:
    """Differential evolution over the box, the nonlinear constraints as constraints."""
    from scipy.optimize import NonlinearConstraint, differential_evolution

    lo, hi = problem.box()
    result = differential_evolution(
        lambda x: -sign * problem.scaled_delta(x),
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


def _best_feasible(problem: _Problem, candidates: list[np.ndarray], sign: float):
    """(coordinates, scaled R − R̂) of the best feasible candidate; raises if there is none."""
    points = np.column_stack(candidates)
    values = np.where(problem.feasible(points), sign * problem.scaled_delta(points), -np.inf)
    best = int(np.argmax(values))
    if not np.isfinite(values[best]):
        raise VoroboundError(
            f"found no feasible guide triangle at eps={problem.params.eps:g} "
            f"(sigma={problem.params.sigma:g}): the constraint set may be empty"
        )
    return points[:, best], float(sign * values[best])


def _best_of_sample(problem: _Problem, sample: np.ndarray, sign: float, count: int):
    """Indices of the ``count`` best sample points and the signed scaled values of all."""
    values = sign * problem.scaled_delta(sample) if sample.shape[1] else np.empty(0)
    return np.argsort(-values)[:count], values


def _extremum(problem: _Problem, sign: float, sample: np.ndarray, rng, maxiter: int):
    """Global search, then polishes from its result and from sample points.

    Returns the best feasible point, its scaled R − R̂, the evidence (values of R − R̂) and
    the sample's extreme R − R̂.
    """
    de_x = _global_search(problem, sign, int(rng.integers(2**31)), maxiter)
    picks, sample_values = _best_of_sample(problem, sample, sign, BEST_SAMPLE_STARTS)
    rest = np.setdiff1d(np.arange(sample_values.size), picks)
    picks = [*picks, *rng.choice(rest, min(RANDOM_SAMPLE_STARTS, rest.size), replace=False)]
    starts = [de_x] + [sample[:, i] for i in picks]
    polished = [_polish(problem, x, sign) for x in starts]
    x, value = _best_feasible(problem, polished + [de_x], sign)
    unit, scale = problem.unit, max(abs(value), np.finfo(float).tiny)
    local = np.column_stack(polished)
    local = sign * problem.scaled_delta(local)[problem.feasible(local)]
    agree = local >= sign * value - AGREE_RTOL * scale
    dense = float(sign * sample_values.max() * unit) if sample_values.size else None
    if dense is not None and sign * (dense / unit - value) > AGREE_RTOL * scale:
        warnings.warn(
            f"a sampled guide triangle beats the optimizer at eps={problem.params.eps:g}: "
            "the tight bound may not be global",
            RuntimeWarning,
            stacklevel=3,
        )
    evidence = {
        "starts": len(starts),
        "agreeing_starts": int(agree.sum()),
        "spread_of_local_optima": float(np.ptp(local[agree]) / scale) if agree.any() else None,
        "other_local_optima": sorted({float(f"{sign * v * unit:.12g}") for v in local[~agree]}),
        "global_search_value": float(problem.scaled_delta(de_x)[0] * unit),
        "active_constraints": problem.active(x),
    }
    return x, value, evidence, dense


def _describe(problem: _Problem, x: np.ndarray) -> dict:
    """The configuration at ``x`` as plain floats, in the paper's order L_j ≤ L_k.

    Reflecting the triangle in the bisector of θ swaps (c, L_j) with (b, L_k) and preserves
    R − R̂ and every constraint.
    """
    if x[3] > x[4]:
        x = x[[1, 0, 2, 4, 3]]
    tri = problem.triangles(x)
    w_b, w_c = tri.weights(problem.params)
    fields = {"b": tri.b, "c": tri.c, "theta": tri.theta, "lfs_j": tri.lfs_j}
    fields |= {"lfs_k": tri.lfs_k, "a": tri.a, "circumradius": tri.circumradius}
    fields |= {"w_b": w_b, "w_c": w_c}
    return {key: float(value[0]) for key, value in fields.items()}


def _checked_problem(params: SamplingParams, lipschitz: float | None) -> _Problem:
    if lipschitz is not None and not (np.isfinite(lipschitz) and lipschitz >= 0):
        raise VoroboundError(f"lipschitz must be a finite number >= 0, got {lipschitz!r}")
    problem = _Problem(params, lipschitz)
    problem.box()
    return problem


def tight_supremum(
    params: SamplingParams,
    lipschitz: float | None = None,
    seed: int = 0,
    *,
    dense_samples: int = DENSE_SAMPLES,
    de_maxiter: int = DE_MAXITER,
) -> TightResult:
    """Supremum and infimum of R − R̂ over all feasible guide triangles at ``params.eps``.

    Parameters
    ----------
    params : SamplingParams
        ε, σ, δ/ε and L_i (ρ_f does not enter).
    lipschitz : float, optional
        λ ≥ 0 adds |L_x − L_y| ≤ λ|p_x − p_y| for each pair of vertices.
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
    problem = _checked_problem(params, lipschitz)
    rng = np.random.default_rng(seed)
    tri = sample_feasible(params, dense_samples, rng, lipschitz)
    sample = problem.coordinates(tri)
    x_max, sup, evidence, dense_max = _extremum(problem, 1.0, sample, rng, de_maxiter)
    x_min, inf, inf_evidence, dense_min = _extremum(problem, -1.0, sample, rng, de_maxiter)
    evidence |= {"methods": ["differential_evolution", "SLSQP", "Newton projection"]}
    evidence |= {"dense_samples": len(tri), "dense_sample_max": dense_max}
    evidence["infimum"] = inf_evidence | {"dense_sample_min": dense_min}
    return TightResult(
        supremum=sup * problem.unit,
        infimum=inf * problem.unit,
        maximizer=_describe(problem, x_max),
        minimizer=_describe(problem, x_min),
        evidence=evidence,
        eps=params.eps,
        lipschitz=lipschitz,
    )


class _WarmScan:
    """ε ↦ sup(R − R̂)/target, polishing from the last maximizer, known global ones and the
    best points of a small sample (which catch a change of the maximizer's structure)."""

    def __init__(self, params, lipschitz, pool: list[np.ndarray], seed: int, advance: Callable):
        self.params, self.lipschitz, self.seed = params, lipschitz, seed
        self.pool, self.last = pool, pool[-1]
        self.advance = advance
        self.found: dict[float, tuple[np.ndarray, float]] = {}
        """Maximizer and ratio per ε evaluated (so a bracket end is not searched twice)."""

    def ratio(self, eps: float) -> float:
        eps = float(eps)
        if eps not in self.found:
            problem = _Problem(self.params.with_eps(eps), self.lipschitz)
            rng = np.random.default_rng(self.seed)
            tri = sample_feasible(problem.params, SCAN_SAMPLES, rng, self.lipschitz)
            sample = problem.coordinates(tri)
            picks, _ = _best_of_sample(problem, sample, 1.0, SCAN_SAMPLE_STARTS)
            starts = [self.last, *self.pool, *sample[:, picks].T]
            polished = [_polish(problem, x, 1.0) for x in starts]
            self.last, value = _best_feasible(problem, polished, 1.0)
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
    params: SamplingParams,
    lipschitz: float | None = None,
    progress: bool = False,
    seed: int = 0,
    *,
    dense_samples: int = DENSE_SAMPLES,
    de_maxiter: int = DE_MAXITER,
    grid: np.ndarray = TIGHT_SCAN_GRID,
) -> EpsStar:
    """Largest ε whose tight bound sup(R − R̂) stays within (ρ_f − 1)·δ·L_i.

    Scans ``grid`` upwards, warm-starting each ε from the previous maximizer, up to the
    first crossing; refines it with brentq (:func:`vorobound.bounds.solve.find_eps_star`);
    confirms the root and the bracket's lower end by full global searches, and repeats with
    their maximizers as extra starts if they beat the scan.

    Parameters
    ----------
    params : SamplingParams
        σ, δ/ε, L_i and ρ_f (its ε is ignored).
    lipschitz : float, optional
        λ of the Lipschitz conditions, as in :func:`tight_supremum`.
    progress : bool
        Show a progress bar on stderr.
    seed, dense_samples, de_maxiter : int
        As in :func:`tight_supremum`, for the global searches.
    grid : array_like
        Increasing ε values scanned for the first crossing.

    Returns
    -------
    EpsStar
        Mode ``"tight"``, with the maximizer at ε* and the residual of the search there.

    References
    ----------
    Eq. (29), (33)–(37), (54)–(55).
    """
    grid = np.asarray(grid, dtype=float)
    _checked_problem(params.with_eps(float(grid[0])), lipschitz)

    def global_max(eps: float) -> tuple[np.ndarray, float]:
        """Maximizer and sup(R − R̂)/target at ``eps`` by the full search."""
        advance("global search")
        problem = _Problem(params.with_eps(eps), lipschitz)
        rng = np.random.default_rng(seed)
        sample = problem.coordinates(sample_feasible(problem.params, dense_samples, rng, lipschitz))
        x, value, _, _ = _extremum(problem, 1.0, sample, rng, de_maxiter)
        return x, problem.ratio(value)

    with _progress_bar(progress, len(grid)) as advance:
        pool = [global_max(float(grid[0]))[0]]
        for _ in range(VERIFY_ROUNDS):
            scan = _WarmScan(params, lipschitz, pool, seed, advance)
            stop = scan.first_crossing(grid)
            bracket = grid[max(stop - 1, 0) : stop + 1]
            result = find_eps_star(scan.gap, "tight", params, grid=bracket)
            scanned = scan.found[result.eps_star]
            x_root, at_root = global_max(result.eps_star)
            x_low, at_low = global_max(result.bracket[0])
            if at_root <= scanned[1] + AGREE_RTOL * abs(scanned[1]) and at_low <= 1:
                break
            pool += [x_root, x_low]
        else:
            warnings.warn(
                "global searches kept beating the warm-started scan: the tight eps* may be off",
                RuntimeWarning,
                stacklevel=2,
            )
    x_best, best = max([scanned, (x_root, at_root)], key=lambda pair: pair[1])
    return replace(
        result,
        residual=float(best - 1),
        maximizer=_describe(_Problem(result.params, lipschitz), x_best),
    )


@contextmanager
def _progress_bar(enabled: bool, scan_points: int) -> Iterator[Callable[[str], None]]:
    """Yield ``advance(phase)``: a rich progress bar on stderr if enabled, else a no-op."""
    if not enabled:
        yield lambda phase: None
        return
    from rich.console import Console
    from rich.progress import Progress

    with Progress(console=Console(stderr=True), transient=True) as bar:
        tasks: dict[str, int] = {}

        def advance(phase: str) -> None:
            if phase not in tasks:
                total = scan_points if phase == "scanning ε" else None
                tasks[phase] = bar.add_task(phase, total=total)
            bar.advance(tasks[phase])

        yield advance
