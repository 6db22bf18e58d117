"""Depth-first interval branch-and-bound: a certificate for every ε ≤ ε_max, or a counterexample.

Each box is closed if a constraint fails on all of it (``infeasible``) or an enclosure of
(R − R̂)/target stays ≤ 1 on it (``bound``); otherwise it is halved along its widest coordinate
(relative to the root box). The search keeps only the pending right halves (memory ∝ depth) and
writes the bisection tree in pre-order, which is what a certificate stores.

Before that, the worst vertex of the closed form (:mod:`vorobound.bounds.tight.closed_form`),
moved into the interior by :data:`NUDGE`, is tried as a counterexample: above the true ε* the
search then stops at once with a configuration whose R − R̂ exceeds the target, instead of
bisecting the region where no bound can hold down to the depth limit. A box that reaches a
limit has its midpoint tried as well. Either point is reported only after checks in interval
arithmetic (at the exact float point) and in floating point (the geometry core).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

from flint import arb

from ...errors import EmptyConstraintSet, InputError, NotCertified
from ...progress import Progress, silent
from . import interval
from .interval import Box, Setting, nearest_float

MAX_DEPTH = 120
"""Deepest bisection before giving up on a box (each coordinate then halved ~20 times; enough
for about 0.999999·ε*, benchmarks/bench_certify.py --fraction)."""
BOUND_SLACK_REL = 2.0**-20
BOUND_SLACK_ABS = 2.0**-40
"""A stored bound exceeds its enclosure by this share of the enclosure's radius plus this
absolute amount, so that a checker whose ball arithmetic rounds differently (another
python-flint or FLINT version) still finds the enclosure below it."""
NUDGE = 1e-9
"""Relative step that moves the worst vertex off the constraints it makes active, so that
interval arithmetic can prove it feasible."""
MAX_BOXES = 20_000_000
"""Default budget of boxes examined (benchmarks/bench_certify.py: the paper's parameters
need about 10⁴ at 0.999·ε*, with λ = 1 about 6·10⁴)."""
PROGRESS_EVERY = 4096
"""Boxes between two progress reports."""
PROGRESS_TOTAL = 1_000_000
"""Progress is reported as the closed share of the root box's volume, in millionths."""
PROGRESS_TASK = "certifying (closed volume, ppm)"


@dataclass(frozen=True)
class Leaf:
    """Why a box is closed."""

    reason: str
    """``"infeasible"`` or ``"bound"``."""
    name: str
    """The constraint that fails everywhere, or the enclosure that stays ≤ 1."""
    bound: float | None = None
    """For ``bound``: a float ≥ the enclosure's upper end and ≤ 1."""


Node = int | Leaf
"""A pre-order node: a split coordinate (index into DIMENSIONS) or a leaf."""


@dataclass(frozen=True)
class Counterexample:
    """A feasible configuration that breaks the target, checked in intervals."""

    point: tuple[float, ...]
    """(ε, b/(εL_i), c/(εL_i), cos θ, (L_j/L_i − 1)/ε, (L_k/L_i − 1)/ε); exact floats."""
    ratio_lower: float
    """Lower end of the interval enclosure of the target's fraction at the point (> 1):
    (R − R̂)/((ρ_f − 1)δL_i), or ((R − R̂)/R)/(1 − 1/ρ_f) for the ratio target."""
    ratio_upper: float
    ratio_float: float
    """The same ratio in floating point (geometry core), for comparison."""


@dataclass(frozen=True)
class SearchResult:
    """A finished bisection tree: every leaf closed."""

    setting: Setting
    nodes: tuple[Node, ...]
    boxes: int
    """Boxes examined (= len(nodes))."""
    max_depth: int
    seconds: float


def close(box: Box, setting: Setting) -> Leaf | None:
    """The reason ``box`` is closed, or None if neither test closes it."""
    point = interval.scaled(interval.balls(box))
    name = interval.violated_constraint(point, setting)
    if name is not None:
        return Leaf("infeasible", name)
    name, value = interval.best_enclosure(point, setting)
    stored = stored_bound(value)
    return None if stored is None else Leaf("bound", name, stored)


def stored_bound(value: arb) -> float | None:
    """A float above the upper end of ``value`` by :data:`BOUND_SLACK_REL` of its radius plus
    :data:`BOUND_SLACK_ABS`, or None if that exceeds 1 (the box is then not closed)."""
    if not value.is_finite() or not value <= 1:
        return None
    margin = value.rad() * BOUND_SLACK_REL + BOUND_SLACK_ABS
    target = value.upper() + margin
    upper = float(target.upper())
    while not target <= arb(upper):
        upper = math.nextafter(upper, math.inf)
    return upper if upper <= 1 else None


def counterexample_at(point: tuple[float, ...], setting: Setting) -> Counterexample | None:
    """``point`` (box coordinates, floats) if it is a feasible configuration above the target.

    Decided twice: in interval arithmetic at the exact float point (every constraint holds on
    the whole enclosure, and the exact ratio's enclosure lies above 1), and in floating point
    by the geometry core and :func:`vorobound.bounds.configurations.feasible_mask`.
    """
    values = [arb(x) for x in point]
    if not interval.constraints_hold(interval.scaled(values), setting):
        return None
    ratio = interval.exact_ratio_at(values, setting)
    if not ratio > 1:
        return None
    float_ratio = _float_ratio(point, setting)
    if float_ratio is None or not float_ratio > 1:
        return None
    return Counterexample(point, float(ratio.lower()), float(ratio.upper()), float_ratio)


def _float_ratio(point: tuple[float, ...], setting: Setting) -> float | None:
    """The target's fraction at ``point`` in floats, or None if ``feasible_mask`` rejects it."""
    from ..configurations import feasible_mask
    from ..params import QualityParams, Target

    eps, edge_b, edge_c, cos_theta, excess_j, excess_k = point
    quality = QualityParams(
        nearest_float(setting.sigma),
        nearest_float(setting.delta_ratio),
        nearest_float(setting.rho_f),
        lipschitz=None if setting.lipschitz is None else nearest_float(setting.lipschitz),
        target=Target(setting.target),
    )
    params = quality.at(eps)
    tri = absolute_configuration(point)
    if not feasible_mask(tri, params)[0]:
        return None
    gap = float(tri.radius_gap(params)[0])
    if setting.target == "ratio":
        return gap / float(tri.circumradius[0]) / params.share_allowance
    return gap / params.gap_allowance


def absolute_configuration(point: tuple[float, ...]):
    """The guide triangle (L_i = 1) of box coordinates ``point``, as ``GuideTriangles``."""
    from ..configurations import GuideTriangles

    eps, edge_b, edge_c, cos_theta, excess_j, excess_k = point
    theta = math.acos(cos_theta)
    return GuideTriangles.of(eps * edge_b, eps * edge_c, theta, eps * excess_j, eps * excess_k)


def worst_vertex(setting: Setting) -> tuple[float, ...] | None:
    """The closed form's worst vertex at ε_max, moved into the interior by :data:`NUDGE`.

    b = c = σεL_i(1 + η), the excess (1 − η) times the vertex's, and θ below the angle at
    which R reaches ε/(1−ε)·L_i: cos(θ/2) = (1 + η)·(b/εL_i)(1−ε)/2. None where the closed
    form finds no guide triangle at all.
    """
    from ..tight.closed_form import tight_supremum_closed_form

    eps, sigma = nearest_float(setting.eps_max), nearest_float(setting.sigma)
    lam = None if setting.lipschitz is None else nearest_float(setting.lipschitz)
    try:
        vertex = tight_supremum_closed_form(
            eps, sigma, nearest_float(setting.delta_ratio), 1.0, lam
        )
    except (InputError, EmptyConstraintSet):
        return None
    edge = sigma * (1 + NUDGE)
    half_cos = min(1.0, (1 + NUDGE) * edge * (1 - eps) / 2)
    excess = vertex.maximizer.excess_j * (1 - NUDGE) / eps
    return (eps, edge, edge, 2 * half_cos * half_cos - 1, excess, excess)


def search(
    setting: Setting,
    *,
    max_depth: int = MAX_DEPTH,
    max_boxes: int = MAX_BOXES,
    progress: Progress | None = None,
) -> SearchResult:
    """Close the root box of ``setting`` by bisection, depth first.

    Parameters
    ----------
    setting : Setting
        Parameters and ε_max.
    max_depth, max_boxes : int
        Limits; reaching one raises :class:`NotCertified` (no endless loops).
    progress : Progress, optional
        Receives (:data:`PROGRESS_TASK`, closed volume in millionths, 1 000 000).

    Returns
    -------
    SearchResult
        The pre-order tree.

    Raises
    ------
    NotCertified
        With a counterexample if one was found, else with the box that could not be closed.
    """
    report = progress or silent
    root = setting.root_box()
    with interval.working_precision():
        vertex = worst_vertex(setting)
        found = None if vertex is None else counterexample_at(vertex, setting)
        if found is not None:
            raise NotCertified(_refuted(setting, found), found, None)
    scales = [hi - lo for lo, hi in root]
    stack: list[tuple[Box, int]] = [(root, 0)]
    nodes: list[Node] = []
    closed_volume, deepest = 0.0, 0
    start = time.perf_counter()
    report(PROGRESS_TASK, 0, PROGRESS_TOTAL)
    with interval.working_precision():
        while stack:
            box, depth = stack.pop()
            deepest = max(deepest, depth)
            leaf = close(box, setting)
            if leaf is not None:
                nodes.append(leaf)
                closed_volume += 2.0**-depth
            else:
                if depth >= max_depth or len(nodes) >= max_boxes:
                    _fail(box, setting, max_depth if depth >= max_depth else None, max_boxes)
                dim = widest(box, scales)
                nodes.append(dim)
                left, right = interval.split(box, dim)
                stack += [(right, depth + 1), (left, depth + 1)]
            if len(nodes) % PROGRESS_EVERY == 0:
                report(PROGRESS_TASK, int(closed_volume * PROGRESS_TOTAL), PROGRESS_TOTAL)
    report(PROGRESS_TASK, PROGRESS_TOTAL, PROGRESS_TOTAL)
    return SearchResult(setting, tuple(nodes), len(nodes), deepest, time.perf_counter() - start)


def widest(box: Box, scales) -> int:
    """The coordinate with the largest width relative to the root box (a root width of 0,
    λ = 0, is never split)."""
    return max(
        (i for i in range(len(box)) if scales[i] > 0),
        key=lambda i: (box[i][1] - box[i][0]) / scales[i],
    )


def _refuted(setting: Setting, found: Counterexample) -> str:
    if setting.target == "ratio":
        what = "(R - R^)/R at least {:.9f} times 1 - 1/rho_f, so R > rho_f R^"
    else:
        what = "(R - R^) at least {:.9f} times (rho_f - 1) delta L_i"
    return (
        f"eps_max = {nearest_float(setting.eps_max):.17g} is not certifiable for the "
        f"{setting.target} target: a feasible guide triangle has {what.format(found.ratio_lower)}"
    )


def _fail(box: Box, setting: Setting, max_depth: int | None, max_boxes: int) -> None:
    """Raise NotCertified for a box at a limit: with its midpoint if that is a counterexample."""
    found = counterexample_at(tuple(nearest_float((lo + hi) / 2) for lo, hi in box), setting)
    if found is not None:
        raise NotCertified(_refuted(setting, found), found, box)
    limit = f"depth {max_depth}" if max_depth is not None else f"{max_boxes} boxes"
    raise NotCertified(
        f"could not certify eps_max = {nearest_float(setting.eps_max):.17g} within {limit} "
        "and found no counterexample; the unresolved box is reported",
        None,
        box,
    )
