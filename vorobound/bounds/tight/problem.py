"""The tight bound's problem: the objective and the feasible guide triangles in normalized
coordinates.

The chain (33)–(53) bounds each term of (29) separately; the tight bound maximizes, over the
whole constraint set of :mod:`vorobound.bounds.constraints`, Theorem 1's R − R̂
(``GuideTriangles.radius_gap``) for the additive target, or (R − R̂)/R = 1 − R̂/R for the ratio
target R ≤ ρ_f·R̂ of eq. (54) (:mod:`vorobound.bounds.targets`), in normalized coordinates

    x = (b/(εL_i), c/(εL_i), θ, s_j, s_k),   L_j = L_i(1 + s_j·2ε/(1−ε)·min(1, λ)), s ∈ [0, 1],

in which the feasible set barely changes with ε.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ...errors import InputError
from .. import constraints
from ..configurations import GuideConfiguration, GuideTriangles
from ..params import SamplingParams, Target

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


@dataclass(frozen=True)
class Problem:
    """The constraint set of :mod:`vorobound.bounds.constraints` in normalized coordinates.

    Coordinates are (5, ...) arrays with the batch last.
    """

    params: SamplingParams
    """ε, σ, δ/ε, ρ_f, L_i, λ and the target: R − R̂ is maximized for the additive target,
    (R − R̂)/R for the ratio target (eq. (54))."""

    @property
    def lipschitz(self) -> float | None:
        return self.params.lipschitz

    @property
    def target(self) -> Target:
        return self.params.target

    @property
    def lfs_scale(self) -> float:
        """min(1, λ): the Lipschitz conditions cap L − L_i at λ·2ε/(1−ε)·L_i (1 without λ)."""
        return 1.0 if self.lipschitz is None else min(1.0, self.lipschitz)

    @property
    def lfs_span(self) -> float:
        """(L_max − L_i)/L_i for s = 1: 2ε/(1−ε), eq. (33), times :attr:`lfs_scale`.

        Scaling the span by λ < 1 keeps s of order one however small λ is, so finite
        differences and the optimizer's tolerances resolve the L direction.
        """
        return 2 * self.params.eps / (1 - self.params.eps) * self.lfs_scale

    @property
    def unit(self) -> float:
        """The objective's natural size, so that objective/unit is of order one at every ε
        and λ: δ²L_i·min(1, λ) for R − R̂ (weights are O(δ²L_i·λε), eq. (37)), and that over
        εL_i (the size of R) for (R − R̂)/R."""
        size = self.params.delta**2 * self.lfs_scale
        if self.target is Target.ratio:
            return size / self.params.eps
        return size * self.params.lfs

    def box(self) -> tuple[np.ndarray, np.ndarray]:
        """Coordinate bounds: (34)–(35), (33), and θ from sin of every angle ≥ k_sin (48)."""
        eps, sigma = self.params.eps, self.params.sigma
        k_sin = constraints.k_sin(eps, sigma)
        constraints.require_guide_triangles(eps, sigma)
        theta_lo = np.arcsin(k_sin)
        # The other two angles are each ≥ arcsin(k_sin); near σ(1−ε) = √3 both ends of θ and
        # of the edges close in on the equilateral triangle.
        theta_hi = float(constraints.angle_max(eps, sigma))
        edge_hi = float(constraints.edge_cap(eps, sigma))  # (34)–(35) and H3 over εL_i
        lo = np.array([sigma, sigma, theta_lo, 0.0, 0.0])
        hi = np.array([edge_hi, edge_hi, theta_hi, 1.0, 1.0])
        return lo, hi

    def triangles(self, x) -> GuideTriangles:
        unit, span = self.params.eps * self.params.lfs, self.lfs_span
        u_b, u_c, theta, s_j, s_k = x
        return GuideTriangles.of(u_b * unit, u_c * unit, theta, span * s_j, span * s_k)

    def coordinates(self, tri: GuideTriangles) -> np.ndarray:
        unit, span = self.params.eps * self.params.lfs, self.lfs_span
        s_j, s_k = tri.excess_j / span, tri.excess_k / span
        return np.stack([tri.b / unit, tri.c / unit, tri.theta, s_j, s_k])

    def scaled(self, x) -> constraints.ScaledConfiguration:
        """The configuration at ``x`` in the units of the constraint set."""
        u_b, u_c, theta, s_j, s_k = x
        per_s = self.lfs_span / self.params.eps
        return constraints.ScaledConfiguration(
            edge_b=u_b,
            edge_c=u_c,
            edge_a=_side_a(x),
            sin_theta=np.sin(theta),
            excess_j=per_s * s_j,
            excess_k=per_s * s_k,
        )

    def _coupled(self) -> tuple[constraints.Constraint, ...]:
        """The constraints that are not coordinate bounds (those of (33)–(35) are the box).

        With λ = 0 the box already fixes L_j = L_k = L_i, so no Lipschitz condition remains.
        """
        limits = constraints.ConstraintParams(self.params.eps, self.params.sigma, self.lipschitz)
        boxed = {"lfs_j_min", "lfs_j_max", "lfs_k_min", "lfs_k_max"}
        boxed |= {"b_min", "b_max", "c_min", "c_max"}
        return tuple(
            c
            for c in constraints.active_constraints(limits)
            if c.name not in boxed and not (c.lipschitz and self.lipschitz == 0)
        )

    def slacks(self, x) -> np.ndarray:
        """The coupled constraints as slacks ≥ 0 (names in :meth:`slack_names`): eq. (36), H3
        and the Lipschitz conditions (those divided by min(1, λ), so all are of order one)."""
        limits = constraints.ConstraintParams(self.params.eps, self.params.sigma, self.lipschitz)
        cfg = self.scaled(x)
        rows = []
        for constraint in self._coupled():
            small, large = constraint.sides(cfg, limits, np)
            slack = large - small
            rows.append(slack / self.lfs_scale if constraint.lipschitz else slack)
        return np.array(rows)

    def slack_names(self) -> list[str]:
        """Each coupled constraint as the equation it becomes when active, e.g. "R = … (H3)"."""
        names = []
        for c in self._coupled():
            equal = c.statement.replace("≤", "=").replace("≥", "=")
            names.append(
                f"{equal} {c.equation if c.equation.startswith('(') else f'({c.equation})'}"
            )
        return names

    def radius_slack(self, x) -> np.ndarray:
        """R ≤ ε/(1−ε)·L_i as 2 sin θ/(1−ε) − a/(εL_i) ≥ 0 (times 2 sin θ > 0), property H3."""
        limits = constraints.ConstraintParams(self.params.eps, self.params.sigma, self.lipschitz)
        small, large = constraints.BY_NAME["circumradius_max"].sides(self.scaled(x), limits, np)
        return large - small

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
        cap = "(33)" if self.lfs_scale == 1 else "(Lipschitz cap λ·2ε/(1−ε))"
        names_lo = ("b = σεL_i (35)", "c = σεL_i (34)", "", "L_j = L_i", "L_k = L_i")
        names_hi: tuple[str, ...] = ("b = 2ε/(1−ε)·L_i (35)", "c = 2ε/(1−ε)·L_i (34)", "")
        names_hi += (f"L_j at its cap {cap}", f"L_k at its cap {cap}")
        pairs = list(zip(names_lo, x - lo, strict=True))
        pairs += list(zip(names_hi, hi - x, strict=True))
        pairs += list(zip(self.slack_names(), self.slacks(x), strict=True))
        pairs += [("R̂ = 0 (w_B = c², w_C = b²)", np.abs(self.plateau_equations(x)[1:]).max())]
        return [name for name, slack in pairs if name and abs(slack) <= ACTIVE_ATOL]

    def objective(self, x) -> np.ndarray:
        """The maximized quantity over :attr:`unit` at the coordinates ``x``: R − R̂ (eq. (29))
        or, for the ratio target, (R − R̂)/R = (a − â)/a (eq. (17))."""
        tri = self.triangles(x)
        gap = tri.radius_gap(self.params)
        if self.target is Target.ratio:
            gap = gap / tri.circumradius
        return gap / self.unit

    def limit(self) -> float:
        """The target in the objective's units: (ρ_f − 1)δL_i (eq. (55)), or 1 − 1/ρ_f, the
        largest (R − R̂)/R with R ≤ ρ_f·R̂ (eq. (54))."""
        if self.target is Target.ratio:
            return self.params.share_allowance
        return self.params.gap_allowance

    def ratio(self, scaled: float) -> float:
        """A scaled objective as a fraction of the target (1 means the target is just met)."""
        return scaled * self.unit / self.limit()

    def plateau_value(self) -> float:
        """The objective's largest possible value over :attr:`unit`: R ≤ ε/(1−ε)·L_i (H3) for
        R − R̂, and 1 for (R − R̂)/R (R̂ ≥ 0); both are reached where R̂ = 0."""
        if self.target is Target.ratio:
            return 1 / self.unit
        return self.params.eps / (1 - self.params.eps) * self.params.lfs / self.unit

    def feasible(self, x) -> np.ndarray:
        """True where ``x`` lies in the constraint set (θ in (0, π) and every constraint)."""
        limits = constraints.ConstraintParams(self.params.eps, self.params.sigma, self.lipschitz)
        inside = (x[2] > 0) & (x[2] < np.pi)
        return np.atleast_1d(inside & constraints.feasible(self.scaled(x), limits))


def _side_a(x) -> np.ndarray:
    """a/(εL_i) by the law of cosines in the cancellation-free form (b−c)² + 4bc sin²(θ/2)."""
    u_b, u_c, theta = x[0], x[1], x[2]
    half = np.sin(theta / 2)
    return np.sqrt((u_b - u_c) ** 2 + 4 * u_b * u_c * half * half)


def with_jacobian(fn: Callable, x: np.ndarray, lo: np.ndarray, hi: np.ndarray):
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


def project(problem: Problem, x: np.ndarray, extra: Callable | None = None) -> np.ndarray:
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
            residual, jacobian = with_jacobian(equations, x, lo, hi)
            x[free] -= np.linalg.lstsq(jacobian[:, free], residual, rcond=None)[0]
    return np.clip(x, lo, hi)


def onto_plateau(problem: Problem, x: np.ndarray) -> np.ndarray | None:
    """A feasible point with R̂ = 0 and R maximal near ``x``, or None.

    R − R̂ ≤ R ≤ ε/(1−ε)·L_i and (R − R̂)/R ≤ 1 for every feasible triangle, so such a point is
    a global maximizer of either objective.
    """
    tri = problem.triangles(x)
    if not tri.radius_gap(problem.params)[0] >= (1 - PLATEAU_TRIGGER) * tri.circumradius[0]:
        return None
    with np.errstate(all="ignore"):
        y = project(problem, x, problem.plateau_equations)
    reached = problem.objective(y)[0] >= problem.plateau_value() * (1 - AGREE_RTOL)
    return y if reached and problem.feasible(y)[0] else None


def describe(problem: Problem, x: np.ndarray) -> GuideConfiguration:
    """The configuration at ``x``, in the paper's order L_j ≤ L_k.

    Reflecting the triangle in the bisector of θ swaps (c, L_j) with (b, L_k) and preserves
    R − R̂ and every constraint.
    """
    if x[3] > x[4]:
        x = x[[1, 0, 2, 4, 3]]
    return GuideConfiguration.of(problem.triangles(x), problem.params)


def checked_problem(params: SamplingParams) -> Problem:
    """The problem for ``params``; raises if the constraint set is empty."""
    if not isinstance(params, SamplingParams):
        raise InputError(f"params must be SamplingParams, got {type(params).__name__}")
    constraints.require_guide_triangles(params.eps, params.sigma)
    return Problem(params)
