"""Numerical supremum of R/R̂ under Cheng, Dey and Shewchuk's weight condition (Section 1).

A simplex's vertices s carry weights w_s ∈ [0, α² N(s)²], α ∈ [0, 1/2), N(s) the distance from
s to its nearest other vertex of the simplex. Cheng et al. show R ≤ c_rad R̂ for triangles with
c_rad = 1/sqrt(1 − 4α²) and conjecture c_rad = 1/sqrt(1 − 3α²). This module maximizes R/R̂ over
triangles (dim 2) and tetrahedra (dim 3) with a seeded global search and local polishing.

Search space. Scale and rigid motions are fixed by putting vertex 0 at the origin and vertex 1
at e₁, so that edge 01 may be taken as the longest edge: vertex 2 = (x, y[, 0]) with
x ∈ [0, 1], y ∈ [h, 1], and in 3-D vertex 3 = (x, y, z) with x ∈ [0, 1], y ∈ [−1, 1],
z ∈ [h, 1]. The flatness floor h keeps the simplex non-degenerate; weights are fractions
f ∈ [0, 1] of their upper bounds. The search is repeated while h shrinks: a maximum that keeps
growing like 1/h means the supremum is infinite (the 3-D case, see ``docs/cheng.md``).
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, field

import numpy as np

from ..checks import checked_seed
from ..errors import InputError
from ..geometry.simplex import nearest_vertex_distances, simplex_radii

ALPHA_LIMIT = 0.5
"""Cheng et al.'s condition requires α < 1/2: balls of radius α·N(s) are then disjoint."""

FLATNESS_FLOORS = (1e-3, 1e-4, 1e-5, 1e-6)
"""Successive lower bounds on the heights y (vertex 2) and z (vertex 3) of the search box."""

UNBOUNDED_GROWTH = 100.0
"""The supremum is reported infinite when the maximum grows by this factor while the floor
shrinks by 1000 (a bounded supremum gives a factor near 1, a 1/h divergence a factor near 1000)."""

SAMPLE_SIZE = {2: 40_000, 3: 80_000}
"""Uniform random configurations per dimension (evidence, and starts for the local polish)."""

LOCAL_STARTS = 8
"""Best random-sample configurations polished locally, besides the global-search result."""

DE_OPTIONS = {2: {"popsize": 30, "maxiter": 400}, 3: {"popsize": 15, "maxiter": 150}}
"""Differential-evolution effort per dimension (population size multiplier, generations)."""

DE_TOLERANCE = 1e-12
"""Relative convergence tolerance of the global search."""

FD_RELATIVE_STEP = 1e-7
"""Finite-difference step of the local polish, relative to the coordinate's size."""

POLISH_METHOD = "TNC"
"""Local optimizer (bounded truncated Newton). L-BFGS-B converges similarly but calls threaded
BLAS on every iteration, which stalls for seconds when other processes share the cores."""

POLISH_OPTIONS = {"maxfun": 600, "ftol": 1e-15, "xtol": 0.0, "gtol": 0.0}
"""Stop after 600 evaluations or when R/R̂ changes by less than 1e-15 (relative): 2-D polishes
converge well within the cap; on a nearly flat tetrahedron R/R̂ is only accurate to about
ε/height and the cap ends the polish."""

HEIGHT_INDEX = {2: [1], 3: [1, 4]}
"""Positions of the heights (y of vertex 2, z of vertex 3) in the search vector."""

FLOOR_RTOL = 1e-9
"""A height within this relative distance of the floor counts as resting on it."""

SAME_OPTIMUM_RTOL = 1e-9
"""Local optima within this relative distance of the best count as reaching it."""


@dataclass(frozen=True)
class ChengMaximizer:
    """A weighted simplex (vertex 0 at the origin, vertex 1 at e₁) and its radii."""

    points: list[list[float]]
    weights: list[float]
    weight_fractions: list[float]
    """Each weight over its upper bound α² N(s)²."""
    nearest_distances: list[float]
    """N(s) of each vertex."""
    circumradius: float
    orthoradius: float
    ratio: float
    """R/R̂."""


@dataclass(frozen=True)
class ChengEvidence:
    """How a numerical supremum of R/R̂ was obtained."""

    seed: int
    global_search_value: float | None
    """Best R/R̂ of differential evolution (before polishing)."""
    global_search_evaluations: int
    local_optima: tuple[float, ...]
    """R/R̂ after each local polish, best first."""
    local_spread: float | None
    """Best minus worst local optimum."""
    reaching_best: int
    """Polishes within ``SAME_OPTIMUM_RTOL`` of the best."""
    random_sample_size: int
    random_sample_max: float | None
    regular_simplex_ratio: float
    """R/R̂ of the regular simplex with every weight at its bound."""
    max_by_flatness_floor: dict[str, float]
    """Best R/R̂ as the flatness floor h shrinks."""
    growth_over_floors: float | None
    """Best at the smallest floor over best at the largest (≈ 1000 for a 1/h divergence)."""
    unbounded: bool
    reason: str = ""
    methods: tuple[str, ...] = (
        "scipy.optimize.differential_evolution",
        f"scipy.optimize.minimize({POLISH_METHOD})",
    )


@dataclass(frozen=True)
class ChengResult:
    """Numerical supremum of R/R̂ under the weight condition w_s ∈ [0, α² N(s)²]."""

    alpha: float
    """α of the weight condition, in [0, 1/2)."""
    dim: int
    """2 for triangles, 3 for tetrahedra."""
    c_rad: float = field(metadata={"equation": "Section 1, Cheng et al.'s bound"})
    """1/sqrt(1 − 4α²): Cheng et al.'s proven constant (for triangles)."""
    c_conjectured: float = field(metadata={"equation": "Section 1, Cheng et al.'s conjecture"})
    """1/sqrt(1 − 3α²): the constant Cheng et al. conjecture."""
    numeric_sup: float
    """Largest R/R̂ found; ``math.inf`` when the search shows a 1/h divergence."""
    maximizer: ChengMaximizer
    """Best configuration found at the smallest flatness floor."""
    evidence: ChengEvidence
    """How the number was obtained (numerical evidence, no proof)."""


def _checked_alpha(alpha, dim) -> float:
    # an array is no dim; int is a numbers.Number only by ABC registration, unseen by typeshed
    if not isinstance(dim, numbers.Number) or dim not in (2, 3):  # type: ignore[comparison-overlap]
        raise InputError(f"dim must be 2 (triangle) or 3 (tetrahedron), got {dim!r}")
    try:
        value = float(alpha)
    except (TypeError, ValueError):
        raise InputError(f"alpha must be a number, got {alpha!r}") from None
    if not 0 <= value < ALPHA_LIMIT:  # also rejects NaN
        raise InputError(f"alpha must lie in [0, 1/2), got {alpha!r}")
    return value


def _box(dim: int, floor: float) -> list[tuple[float, float]]:
    """Bounds of the search vector: coordinates of vertices 2.. then weight fractions."""
    coords = [(0.0, 1.0), (floor, 1.0)]
    if dim == 3:
        coords += [(0.0, 1.0), (-1.0, 1.0), (floor, 1.0)]
    return coords + [(0.0, 1.0)] * (dim + 1)


def _configurations(x: np.ndarray, dim: int, alpha: float):
    """Points (m, d+1, d), weights and weight fractions (m, d+1) from search vectors (m, k)."""
    m = x.shape[0]
    points = np.zeros((m, dim + 1, dim))
    points[:, 1, 0] = 1.0
    points[:, 2, :2] = x[:, :2]
    if dim == 3:
        points[:, 3, :] = x[:, 2:5]
    fractions = x[:, -(dim + 1) :]
    weights = fractions * alpha**2 * nearest_vertex_distances(points) ** 2
    return points, weights, fractions


def _ratio(x: np.ndarray, dim: int, alpha: float) -> np.ndarray:
    """R/R̂ for search vectors (m, k); 0 where it is undefined (never for admissible input)."""
    points, weights, _ = _configurations(x, dim, alpha)
    radii = simplex_radii(points, weights)
    with np.errstate(all="ignore"):
        ratio = radii.circumradius / np.sqrt(radii.orthoradius_sq)
    return np.where(np.isfinite(ratio), ratio, 0.0)


def _regular_simplex(dim: int) -> np.ndarray:
    """Search vector of the regular simplex with unit edge and every weight at its bound."""
    if dim == 2:
        coords = [0.5, math.sqrt(3) / 2]
    else:
        coords = [0.5, math.sqrt(3) / 2, 0.5, math.sqrt(3) / 6, math.sqrt(2 / 3)]
    return np.array(coords + [1.0] * (dim + 1))


def _ratio_and_gradient(x: np.ndarray, dim: int, alpha: float, bounds) -> tuple:
    """−R/R̂ and its central-difference gradient, all 2k + 1 evaluations in one batch.

    Steps scale with |x_i| plus the coordinate's lower bound, so a height resting on a small
    flatness floor is perturbed by a fraction of itself rather than by more than its size.
    """
    low, high = np.array(bounds).T
    step = FD_RELATIVE_STEP * (np.abs(x) + low.clip(min=FD_RELATIVE_STEP))
    eye = np.diag(step)
    plus = np.clip(x + eye, low, high)
    minus = np.clip(x - eye, low, high)
    ratio = _ratio(np.vstack([x[None], plus, minus]), dim, alpha)
    k = x.size
    gradient = (ratio[1 : k + 1] - ratio[k + 1 :]) / (plus.diagonal() - minus.diagonal())
    return -ratio[0], -gradient


def _polish(start: np.ndarray, dim: int, alpha: float, bounds) -> tuple[float, np.ndarray]:
    """Local maximization of R/R̂ from ``start`` within ``bounds``; returns (value, x)."""
    from scipy.optimize import minimize

    start = np.clip(start, *np.array(bounds).T)
    result = minimize(
        _ratio_and_gradient,
        start,
        args=(dim, alpha, bounds),
        jac=True,
        method=POLISH_METHOD,
        bounds=bounds,
        options=POLISH_OPTIONS,
    )
    candidates = np.vstack([result.x, start])
    values = _ratio(candidates, dim, alpha)
    best = int(np.argmax(values))
    return float(values[best]), candidates[best]


LEGACY_SEED_LIMIT = 1 << 32
"""Integer seeds of numpy's legacy RandomState (what scipy makes of an int seed) are below
this."""


def _search(alpha: float, dim: int, seed: int):
    """Global search, local polish from several starts, and continuation in the floor."""
    from scipy.optimize import differential_evolution

    rng = np.random.default_rng(seed)
    floor = FLATNESS_FLOORS[0]
    bounds = _box(dim, floor)
    low, high = np.array(bounds).T
    sample = low + (high - low) * rng.random((SAMPLE_SIZE[dim], len(bounds)))
    sample_ratio = _ratio(sample, dim, alpha)

    global_run = differential_evolution(
        lambda xs: -_ratio(xs.T, dim, alpha),
        bounds,
        # scipy seeds a legacy RandomState from an int, which must be below 2³²: larger seeds
        # (accepted up to 2⁶³ − 1 like every seed) go in as a Generator.
        seed=seed if seed < LEGACY_SEED_LIMIT else np.random.default_rng(seed),
        vectorized=True,
        updating="deferred",
        polish=False,
        tol=DE_TOLERANCE,
        **DE_OPTIONS[dim],
    )
    starts = [global_run.x] + list(sample[np.argsort(sample_ratio)[::-1][:LOCAL_STARTS]])
    optima = [_polish(s, dim, alpha, bounds) for s in starts]
    best_value, best_x = max(optima, key=lambda vx: vx[0])

    # Follow the best configuration while the flatness floor shrinks: a height resting on the
    # old floor moves to the new one before polishing.
    by_floor = {floor: best_value}
    for new_floor in FLATNESS_FLOORS[1:]:
        start = best_x.copy()
        heights = HEIGHT_INDEX[dim]
        start[heights] = np.where(
            start[heights] <= floor * (1 + FLOOR_RTOL), new_floor, start[heights]
        )
        floor = new_floor
        best_value, best_x = _polish(start, dim, alpha, _box(dim, floor))
        by_floor[floor] = best_value

    values = np.array([v for v, _ in optima])
    growth = by_floor[FLATNESS_FLOORS[-1]] / by_floor[FLATNESS_FLOORS[0]]
    evidence = ChengEvidence(
        seed=seed,
        global_search_value=-float(global_run.fun),
        global_search_evaluations=int(global_run.nfev),
        local_optima=tuple(sorted((float(v) for v in values), reverse=True)),
        local_spread=float(values.max() - values.min()),
        reaching_best=int(np.sum(values >= values.max() * (1 - SAME_OPTIMUM_RTOL))),
        random_sample_size=int(sample.shape[0]),
        random_sample_max=float(sample_ratio.max()),
        regular_simplex_ratio=float(_ratio(_regular_simplex(dim)[None], dim, alpha)[0]),
        max_by_flatness_floor={f"{f:.0e}": float(v) for f, v in by_floor.items()},
        growth_over_floors=float(growth),
        unbounded=bool(growth >= UNBOUNDED_GROWTH),
    )
    return best_x, by_floor, evidence


def _maximizer(x: np.ndarray, dim: int, alpha: float) -> ChengMaximizer:
    points, weights, fractions = _configurations(x[None], dim, alpha)
    radii = simplex_radii(points, weights)
    circumradius = float(radii.circumradius[0])
    orthoradius = math.sqrt(float(radii.orthoradius_sq[0]))
    return ChengMaximizer(
        points=points[0].tolist(),
        weights=weights[0].tolist(),
        weight_fractions=fractions[0].tolist(),
        nearest_distances=nearest_vertex_distances(points[0]).tolist(),
        circumradius=circumradius,
        orthoradius=orthoradius,
        ratio=circumradius / orthoradius,
    )


def cheng_constants(alpha: float, dim: int = 2, seed: int = 0) -> ChengResult:
    """Numerically maximize R/R̂ over weighted triangles or tetrahedra with w_s ≤ α² N(s)².

    Parameters
    ----------
    alpha : float
        α ∈ [0, 1/2) of the weight condition w_s ∈ [0, α² N(s)²].
    dim : {2, 3}
        2 maximizes over triangles, 3 over tetrahedra.
    seed : int
        Seed of the global search and of the random sample.

    Returns
    -------
    ChengResult
        ``numeric_sup`` is ``math.inf`` when the maximum grows by at least
        ``UNBOUNDED_GROWTH`` across ``FLATNESS_FLOORS``.

    References
    ----------
    Section 1 (Cheng, Dey and Shewchuk's bound and conjecture); eq. (2)–(3).
    """
    alpha = _checked_alpha(alpha, dim)
    seed = checked_seed(seed)
    c_rad = 1 / math.sqrt(1 - 4 * alpha**2)
    c_conjectured = 1 / math.sqrt(1 - 3 * alpha**2)
    if alpha <= 0:
        # α = 0: every weight is 0, so ẑ = z and R̂ = R for every simplex.
        regular = _regular_simplex(dim)
        return ChengResult(
            alpha=alpha,
            dim=dim,
            c_rad=c_rad,
            c_conjectured=c_conjectured,
            numeric_sup=1.0,
            maximizer=_maximizer(regular, dim, alpha),
            evidence=ChengEvidence(
                seed=seed,
                global_search_value=None,
                global_search_evaluations=0,
                local_optima=(),
                local_spread=None,
                reaching_best=0,
                random_sample_size=0,
                random_sample_max=None,
                regular_simplex_ratio=1.0,
                max_by_flatness_floor={},
                growth_over_floors=None,
                unbounded=False,
                reason="alpha = 0 forces all weights to 0, hence R = R̂",
            ),
        )
    best_x, by_floor, evidence = _search(alpha, dim, seed)
    numeric_sup = math.inf if evidence.unbounded else max(by_floor.values())
    return ChengResult(
        alpha=alpha,
        dim=dim,
        c_rad=c_rad,
        c_conjectured=c_conjectured,
        numeric_sup=numeric_sup,
        maximizer=_maximizer(best_x, dim, alpha),
        evidence=evidence,
    )
