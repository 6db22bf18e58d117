"""The largest ε whose bound on R − R̂ stays within the quality target (ρ_f − 1)·δ·L_i.

ε* is the first crossing of bound(ε)/target(ε) − 1 from below, found by a log-spaced scan and a
root finder. A crossing must be a root: where a chain stops being defined (the printed chain's
eq. (52) needs |k_cos| ≤ 1) before it reaches the target, there is no ε*, and the solvers say so
(:class:`NoCrossing`) instead of reporting the edge of the domain as a root.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..checks import EPS_RANGE
from ..errors import EmptyConstraintSet, InputError, NoAdmissibleEps, NoCrossing
from . import constraints
from .chain import chain_arrays
from .claims import CHAIN_CLAIM
from .configurations import GuideConfiguration
from .params import Mode, QualityParams, SamplingParams, Target
from .roots import bracketed_roots, largest_root

SCAN_GRID = np.geomspace(EPS_RANGE[0], EPS_RANGE[1], 800)
"""ε values scanned for the first crossing of bound and target (log-spaced)."""
RTOL = 1e-13
"""Relative width of the bracket at which an ε* is final (well below what any output prints)."""
EMPTY_START_RTOL = 1e-6
"""Scans for σ > √3 start this far (relative) above the ε below which no guide triangle exists."""


@dataclass(frozen=True)
class EpsStar:
    """Result of an ε* solver."""

    eps_star: float
    """Largest ε whose bound meets the target (the first crossing above the scan start)."""
    mode: str
    quality: QualityParams
    """The parameters asked about: σ, δ/ε, ρ_f, L_i, λ and the target."""
    residual: float
    """bound(ε*)/target(ε*) − 1 (zero up to the root finder's tolerance)."""
    iterations: int
    bracket: tuple[float, float]
    """The scan cell in which the root was found."""
    method: str
    """How the bound was evaluated: "chain", "closed form" or "optimizer"."""
    claim: str
    """Strength of the result: a word of :mod:`vorobound.bounds.claims`."""
    maximizer: GuideConfiguration | None = None
    """For the tight mode: the worst guide triangle at ε*."""
    proven_lower_bound: float | None = None
    """When the claim is numerical: an ε* proven by the closed form to be admissible (a lower
    bound on the tight ε*), or None."""

    @property
    def params(self) -> SamplingParams:
        """The quality parameters at ε*."""
        return self.quality.at(self.eps_star)

    @property
    def target(self) -> str:
        """Which target ε* is for: additive (R − R̂ ≤ (ρ_f − 1)δL_i) or ratio (R ≤ ρ_f·R̂)."""
        return self.quality.target.value

    @property
    def lipschitz(self) -> float | None:
        """The Lipschitz constant of the constraint set (tight mode), if any."""
        return self.quality.lipschitz


def feasible_start(quality: QualityParams, mode: str) -> float:
    """The ε from which guide triangles exist (0 for σ ≤ √3); raise if there is none at all.

    For σ > √3 the constraint set is empty below 1 − √3/σ (:func:`constraints.empty_below`):
    every bound holds there vacuously, so ε* is sought above it.
    """
    start = constraints.empty_below(quality.sigma)
    if start * (1 + EMPTY_START_RTOL) >= EPS_RANGE[1]:
        raise EmptyConstraintSet(
            f"sigma = {quality.sigma:g}: no guide triangle satisfies the sparsity conditions "
            f"(34)-(36) together with H3 for any supported eps, so the {mode} bound has no eps*"
        )
    return start


def feasible_grid(grid, start: float) -> np.ndarray:
    """The scan grid restricted to ε above ``start`` (starting just above it when it is > 0)."""
    grid = np.asarray(grid, dtype=float)
    if start <= 0:
        return grid
    first = start * (1 + EMPTY_START_RTOL)
    return np.concatenate([[first], grid[grid > first]])


def chain_gap(chain, target: Target | str) -> np.ndarray:
    """bound/allowance − 1 of a chain for ``target`` (NaN where the chain is undefined)."""
    if Target(target) is Target.ratio:
        return chain.share_bound / chain.share_allowance - 1
    return chain.bound / chain.gap_allowance - 1


def relative_gap_function(quality: QualityParams, mode: Mode | str) -> Callable:
    """ε ↦ bound(ε)/target(ε) − 1 for the closed-form chains (vectorized; NaN where undefined).

    For the ratio target the bound is the chain's bound on (R − R̂)/R (eq. (30)) and the
    target 1 − 1/ρ_f (R ≤ ρ_f·R̂, eq. (54)); for the additive target R − R̂ against
    (ρ_f − 1)δL_i.
    """

    def gap(eps):
        chain = chain_arrays(
            eps, quality.sigma, quality.delta_ratio, quality.lfs, quality.rho_f, mode
        )
        return chain_gap(chain, quality.target)

    return gap


DOMAIN_EDGE_STEPS = 64
"""Halvings that locate where a chain stops being defined inside one scan cell."""


def _domain_edges(gap: Callable, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Largest ε in each [lo, hi] (lo defined, hi not) at which ``gap`` is still defined."""
    lo, hi = np.array(lo, dtype=float), np.array(hi, dtype=float)
    for _ in range(DOMAIN_EDGE_STEPS):
        mid = 0.5 * (lo + hi)
        with np.errstate(invalid="ignore"):
            defined = ~np.isnan(gap(mid))
        lo, hi = np.where(defined, mid, lo), np.where(defined, hi, mid)
    return lo


def crossing_bracket(gap: Callable, values: np.ndarray, grid: np.ndarray, mode: str):
    """(lo, hi) with gap(lo) ≤ 0 < gap(hi) around the first crossing; raise if there is none.

    ``values`` are gap(ε) on ``grid``: negative inside the target, NaN where undefined. The
    bound rises with ε where it is defined, so when it becomes undefined inside a scan cell the
    crossing, if any, lies below the edge of its domain, which is located by bisection.
    """
    positive = np.flatnonzero(values > 0)
    undefined = np.flatnonzero(np.isnan(values))
    if positive.size and positive[0] == 0:
        raise NoAdmissibleEps(
            f"the {mode} bound exceeds the target already at eps = {grid[0]:g}, the smallest "
            "eps at which a guide triangle exists or is supported: no admissible eps"
        )
    if undefined.size and (not positive.size or undefined[0] < positive[0]):
        cell = int(undefined[0])
        if cell > 0:
            edge = float(_domain_edges(gap, grid[cell - 1 : cell], grid[cell : cell + 1])[0])
            if gap(edge) > 0:
                return float(grid[cell - 1]), edge
        raise NoCrossing(
            f"the {mode} bound stays within the target up to eps = {grid[max(cell - 1, 0)]:.6g}, "
            f"where it stops being defined: no crossing, so no eps*"
        )
    if not positive.size:
        raise NoCrossing(
            f"the {mode} bound stays within the target for every eps up to {grid[-1]:g}: "
            "no crossing, so no eps*"
        )
    return float(grid[positive[0] - 1]), float(grid[positive[0]])


def find_eps_star(
    gap: Callable,
    mode: str,
    quality: QualityParams,
    claim: str,
    grid=SCAN_GRID,
    method: str = "chain",
) -> EpsStar:
    """Scan ``grid`` for the first ε where ``gap`` turns positive, then refine the crossing
    with :func:`vorobound.bounds.roots.largest_root` (the largest ε whose gap is ≤ 0).

    ``gap`` must accept an array of ε (for the scan) and a float (for the refinement).
    """
    grid = np.asarray(grid, dtype=float)
    with np.errstate(invalid="ignore"):
        values = np.asarray(gap(grid), dtype=float)
    lo, hi = crossing_bracket(gap, values, grid, mode)
    root, steps = largest_root(lambda x: float(gap(x)), lo, hi, rtol=RTOL)
    return EpsStar(
        eps_star=float(root),
        mode=mode,
        quality=quality,
        residual=float(gap(root)),
        iterations=steps,
        bracket=(lo, hi),
        method=method,
        claim=claim,
    )


def solve_eps_star(quality: QualityParams, mode: Mode | str = Mode.paper) -> EpsStar:
    """Largest ε keeping a chain's bound within the target.

    Parameters
    ----------
    quality : QualityParams
        σ, δ/ε, ρ_f, L_i and the target: R − R̂ ≤ (ρ_f − 1)δL_i, or R ≤ ρ_f·R̂ (eq. (54))
        through eq. (30). The chains have no Lipschitz condition.
    mode : {"paper", "rigorous"}
        Which chain; the tight mode lives in :mod:`vorobound.bounds.tight`.

    Raises
    ------
    NoAdmissibleEps
        When the bound exceeds the target at the smallest supported ε, when σ ≥ 2, or (as
        :class:`NoCrossing`) when it never reaches the target where it is defined.

    References
    ----------
    Eq. (29), (33)–(55); Figure 3.
    """
    mode = Mode(mode)
    if mode is Mode.tight:
        raise InputError("solve_eps_star handles the chains; use vorobound.bounds.tight")
    start = feasible_start(quality, mode.value)
    gap = relative_gap_function(quality, mode)
    grid = feasible_grid(SCAN_GRID, start)
    return find_eps_star(gap, mode.value, quality, CHAIN_CLAIM[mode.value], grid=grid)


BATCH_SCAN_GRID = np.geomspace(EPS_RANGE[0], EPS_RANGE[1], 200)
"""Coarser scan for the batched solver; bound/target rises monotonically in ε for the chains,
so the first crossing is the same (checked against :func:`solve_eps_star` in the tests)."""

NO_EPS_STAR: tuple[type[NoAdmissibleEps], ...] = (NoAdmissibleEps, NoCrossing, EmptyConstraintSet)
"""The batch solver's status codes: 0 is an ε*, code k > 0 is the error NO_EPS_STAR[k − 1] that
:func:`solve_eps_star` raises for such a row (the one representation of "no ε*")."""
STATUS_OK = 0
STATUS_EXCEEDS_AT_START = 1 + NO_EPS_STAR.index(NoAdmissibleEps)
"""The bound exceeds the target at the smallest supported ε."""
STATUS_NO_CROSSING = 1 + NO_EPS_STAR.index(NoCrossing)
"""The bound stays within the target wherever it is defined."""
STATUS_EMPTY = 1 + NO_EPS_STAR.index(EmptyConstraintSet)
"""No feasible guide triangle at any supported ε (σ(1 − ε) > √3 up to ε = 0.999)."""
STATUS_REASONS = {code: error.reason for code, error in enumerate(NO_EPS_STAR, start=1)}
"""Why a batch row has no ε* (for the empty cells of a sweep): the error's reason."""


def solve_eps_star_batch(
    sigma,
    delta_ratio,
    rho_f,
    mode: Mode | str,
    grid=BATCH_SCAN_GRID,
    target: Target | str = Target.additive,
) -> tuple[np.ndarray, np.ndarray]:
    """ε* for many parameter sets at once (closed-form chains).

    Same definition as :func:`solve_eps_star`, found by a vectorized scan of ``grid`` and
    bisection of each row's bracket to full precision. ε* does not depend on L_i. The caller
    validates the parameters (e.g. through :class:`QualityParams`). Where σ > √3 the
    constraint set is empty below 1 − √3/σ and the bound counts as met there (vacuously).

    Parameters
    ----------
    sigma, delta_ratio, rho_f : array_like
        Broadcast together; one ε* per element.
    mode : {"paper", "rigorous"}
    target : {"additive", "ratio"}

    Returns
    -------
    eps_star : numpy.ndarray
        NaN where there is none.
    status : numpy.ndarray of int
        ``STATUS_OK`` or the reason (a key of ``STATUS_REASONS``).
    """
    sigma, ratio, rho_f = np.broadcast_arrays(
        *(np.asarray(x, dtype=float) for x in (sigma, delta_ratio, rho_f))
    )
    shape = sigma.shape
    s, r, q = (x.reshape(-1, 1) for x in (sigma, ratio, rho_f))
    start = np.vectorize(constraints.empty_below, otypes=[float])(s)
    first_eps = np.where(start > 0, start * (1 + EMPTY_START_RTOL), grid[0])

    def gap_rows(eps, index):
        chain = chain_arrays(eps, s[index], r[index], 1.0, q[index], mode)
        values = chain_gap(chain, target)
        return np.where(np.asarray(eps) < first_eps[index], -1.0, values)  # vacuous below

    with np.errstate(invalid="ignore"):
        values = gap_rows(grid[None, :], slice(None))
    positive = values > 0
    undefined = np.isnan(values)
    first_pos = np.where(positive.any(axis=1), np.argmax(positive, axis=1), grid.size)
    first_nan = np.where(undefined.any(axis=1), np.argmax(undefined, axis=1), grid.size)
    first = np.minimum(first_pos, grid.size - 1)
    lo = grid[np.maximum(first - 1, 0)].copy()
    hi = grid[first].copy()
    f_lo = values[np.arange(len(first)), np.maximum(first - 1, 0)]
    f_hi = values[np.arange(len(first)), first]
    status = np.full(first_pos.shape, STATUS_OK)
    status[first_pos == grid.size] = STATUS_NO_CROSSING

    def gap_at(eps, index):
        return gap_rows(eps[:, None], index)[:, 0]

    # Rows that stop being defined first: the crossing, if any, lies below the domain edge.
    edge_rows = np.flatnonzero((first_nan < first_pos) & (first_nan > 0))
    if edge_rows.size:
        cell = first_nan[edge_rows]
        edges = _domain_edges(lambda eps: gap_at(eps, edge_rows), grid[cell - 1], grid[cell])
        with np.errstate(invalid="ignore"):
            at_edge = gap_at(edges, edge_rows)
        crosses = at_edge > 0
        status[edge_rows[~crosses]] = STATUS_NO_CROSSING
        found = edge_rows[crosses]
        status[found] = STATUS_OK
        lo[found], hi[found] = grid[cell[crosses] - 1], edges[crosses]
        f_lo[found], f_hi[found] = values[found, cell[crosses] - 1], at_edge[crosses]
    status[first_nan == 0] = STATUS_NO_CROSSING
    status[first_pos == 0] = STATUS_EXCEEDS_AT_START
    # Rows with an empty start: is the bound already above the target at the first ε with
    # guide triangles? Then there is no admissible ε (the vacuous range below is not one).
    late = np.flatnonzero((start[:, 0] > 0) & (status == STATUS_OK))
    if late.size:
        with np.errstate(invalid="ignore"):
            at_start = gap_at(first_eps[late, 0], late)
        status[late[at_start > 0]] = STATUS_EXCEEDS_AT_START
        # Bracket from the first feasible ε (the scan's lower end may lie in the empty range).
        raise_lo = late[(at_start <= 0) & (lo[late] < first_eps[late, 0])]
        lo[raise_lo] = first_eps[raise_lo, 0]
        f_lo[raise_lo] = gap_at(first_eps[raise_lo, 0], raise_lo)
    status[first_eps[:, 0] >= EPS_RANGE[1]] = STATUS_EMPTY
    ok = status == STATUS_OK
    rows = np.flatnonzero(ok)
    lo[rows] = bracketed_roots(gap_at, lo[rows], hi[rows], f_lo[rows], f_hi[rows], rows)[0]
    stars = np.where(ok, lo, np.nan).reshape(shape)
    return stars, status.reshape(shape)
