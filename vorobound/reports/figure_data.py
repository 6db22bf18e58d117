"""The data behind the figures: Figure 3 of the paper, both targets' bounds per mode (the
comparison and the ratio figure) and the gap histogram of a check, whole or tiled."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..bounds.chain import chain_bounds
from ..bounds.eps_star import solve_eps_star
from ..bounds.params import Mode, QualityParams, Target
from ..constants import BASELINE_EPS, PAPER_EPS
from ..rounding import format_down, format_up

FIGURE3_POINTS = 400
"""ε values on the Figure 3 curves."""
FIGURE3_RANGE_FACTOR = 1.5
"""Figure 3 spans ε up to this factor times the larger of ε* and 1/500."""


@dataclass(frozen=True)
class Figure3Data:
    """Bound on |R − R̂| against ε for L_i = ``quality.lfs`` (Figure 3, paper mode)."""

    eps: np.ndarray
    bound_acute: np.ndarray
    """θ ≤ π/2 case of the chain, eq. (46), (50)–(51)."""
    bound_obtuse: np.ndarray
    """θ > π/2 case of the chain, eq. (46), (52)–(53)."""
    target: np.ndarray
    """(ρ_f − 1)·δ·L_i, eq. (55)."""
    eps_baseline: float
    eps_star: float
    mode: str


def figure3_data(
    quality: QualityParams, mode: Mode | str = Mode.paper, points: int = FIGURE3_POINTS
) -> Figure3Data:
    """Curves of Figure 3 on ε ∈ (0, 1.5·max(ε*, 1/500)], both θ cases, and the markers (the
    paper's additive target)."""
    quality = quality.but(target=Target.additive, lipschitz=None)
    star = solve_eps_star(quality, mode)
    top = FIGURE3_RANGE_FACTOR * max(star.eps_star, BASELINE_EPS)
    eps = np.linspace(top / points, top, points)
    chain = chain_bounds(quality.at(top), mode, eps=eps)
    return Figure3Data(
        eps=eps,
        bound_acute=chain.bound_acute,
        bound_obtuse=chain.bound_obtuse,
        target=chain.gap_allowance,
        eps_baseline=BASELINE_EPS,
        eps_star=star.eps_star,
        mode=Mode(mode).value,
    )


TARGET_EPS = np.geomspace(1e-4, 0.3, 600)
"""ε grid of the comparison and ratio figures: every mode in closed form (the chains, and the
tight supremum, proven where the worst vertex is feasible), so the curves are smooth."""
TIGHT_SETTINGS = (None, 1.0)
"""Tight-mode variants shown: the paper's constraints, and with the 1-Lipschitz condition."""


@dataclass(frozen=True)
class TargetCurve:
    """One mode's bound against ε for one target.

    References
    ----------
    Eq. (29)–(30), (33)–(55); the tight closed forms of docs/tight.md.
    """

    mode: str
    """"paper", "rigorous", "tight" or "tight, λ = 1"."""
    target: str
    """"additive" (R − R̂ ≤ (ρ_f − 1)δL_i) or "ratio" (R ≤ ρ_f·R̂, eq. (54))."""
    eps: np.ndarray
    value: np.ndarray
    """The bound: on (R − R̂)/(εL_i) (additive) or on R/R̂ (ratio; inf where there is none)."""
    fraction: np.ndarray
    """The bound as a fraction of the target's allowance, ≤ 1 where the target is met:
    bound/((ρ_f − 1)δL_i), or the bound on (R − R̂)/R over 1 − 1/ρ_f."""
    upper_only: np.ndarray
    """True where the value is a proven upper bound only (the tight closed form where its
    worst vertex is infeasible); False everywhere for the chains."""
    eps_star: float | None
    """This mode's ε* for this target (None when none exists in the supported range)."""
    claim: str
    """The claim of ε*: proven, numerical or invalid."""


@dataclass(frozen=True)
class TargetFigureData:
    """Every mode's bound against ε for both targets: the comparison and the ratio figures."""

    curves: tuple[TargetCurve, ...]
    rho_f: float
    additive_over_eps: float
    """(ρ_f − 1)·(δ/ε): the additive target over εL_i, constant in ε."""
    paper_eps: float
    """The paper's ε = 0.0047, marked."""

    def of_target(self, target: str) -> tuple[TargetCurve, ...]:
        return tuple(c for c in self.curves if c.target == target)


def mode_label(mode: str, lipschitz: float | None) -> str:
    """The name of a mode in the figures: "tight, λ = 1" for the tight mode with λ."""
    return mode if lipschitz is None else f"{mode}, λ = {lipschitz:g}"


def chain_target_curves(
    quality: QualityParams, mode: Mode | str, stars: dict, eps=TARGET_EPS
) -> list[TargetCurve]:
    """A chain's bound on ``eps`` for both targets (``stars``: target ↦ EpsStar or None)."""
    chain = chain_bounds(quality.but(lipschitz=None).at(float(eps[0])), mode, eps=eps)
    exact = np.zeros(len(eps), dtype=bool)
    name = Mode(mode).value
    return [
        _curve(
            name,
            "additive",
            eps,
            chain.bound / (eps * quality.lfs),
            chain.bound / chain.gap_allowance,
            exact,
            stars.get("additive"),
        ),
        _curve(
            name,
            "ratio",
            eps,
            chain.ratio_bound,
            chain.share_bound / chain.share_allowance,
            exact,
            stars.get("ratio"),
        ),
    ]


def tight_target_curves(
    quality: QualityParams, lipschitz: float | None, stars: dict, eps=TARGET_EPS
) -> list[TargetCurve]:
    """The tight supremum in closed form on ``eps`` for both targets: exact where the worst
    vertex is feasible, a proven upper bound elsewhere (``upper_only``); NaN where no guide
    triangle exists (σ(1 − ε) > √3)."""
    from ..bounds.constraints import is_empty
    from ..bounds.tight.closed_form import closed_form_is_exact, weight_ratio

    sigma, ratio, rho_f = quality.sigma, quality.delta_ratio, quality.rho_f
    share = np.minimum(1.0, weight_ratio(eps, sigma, ratio, lipschitz))
    share = np.where([is_empty(e, sigma) for e in eps], np.nan, share)
    upper = np.array([not closed_form_is_exact(e, sigma, ratio, lipschitz) for e in eps])
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio_value = np.where(share < 1, 1 / (1 - share), np.inf)
    ratio_value = np.where(np.isnan(share), np.nan, ratio_value)
    gap_over_eps = share / (1 - eps)
    name = mode_label("tight", lipschitz)
    return [
        _curve(
            name,
            "additive",
            eps,
            gap_over_eps,
            gap_over_eps / ((rho_f - 1) * ratio),
            upper,
            stars.get("additive"),
        ),
        _curve(name, "ratio", eps, ratio_value, share / (1 - 1 / rho_f), upper, stars.get("ratio")),
    ]


def _curve(mode, target, eps, value, fraction, upper, star) -> TargetCurve:
    return TargetCurve(
        mode=mode,
        target=target,
        eps=eps,
        value=np.asarray(value, dtype=float),
        fraction=np.asarray(fraction, dtype=float),
        upper_only=np.asarray(upper, dtype=bool),
        eps_star=None if star is None else star.eps_star,
        claim="" if star is None else star.claim,
    )


def target_figure_data(
    quality: QualityParams, stars: list, tight: bool = True, eps=TARGET_EPS
) -> TargetFigureData:
    """Both targets' curves for paper, rigorous and (with ``tight``) each tight setting of
    :data:`TIGHT_SETTINGS`; ``stars`` are the ε* to mark (EpsStar of any mode, target and λ;
    a missing one is not marked)."""
    found = {(mode_label(s.mode, s.lipschitz), s.target): s for s in stars}

    def of(name):
        return {t: found.get((name, t)) for t in ("additive", "ratio")}

    curves = []
    for mode in ("paper", "rigorous"):
        curves += chain_target_curves(quality, mode, of(mode), eps)
    for lam in TIGHT_SETTINGS if tight else ():
        curves += tight_target_curves(quality, lam, of(mode_label("tight", lam)), eps)
    return TargetFigureData(
        tuple(curves), quality.rho_f, (quality.rho_f - 1) * quality.delta_ratio, PAPER_EPS
    )


def figure_set_data(
    quality: QualityParams, stars: list, tight: bool = True
) -> tuple[Figure3Data, TargetFigureData]:
    """The data of every figure: Figure 3, and both targets' curves (the comparison and the
    ratio figure). ``stars``: the ε* to mark (see :func:`target_figure_data`)."""
    return figure3_data(quality), target_figure_data(quality, stars, tight)


HISTOGRAM_BINS = 120
"""Bins of the gap histogram across the shown range."""
HISTOGRAM_MARGIN = 0.04
"""Share of the shown range left empty left of the data and right of the last mark, so that no
bar or line lies on the frame."""


@dataclass(frozen=True)
class GapHistogramData:
    """What the gap histogram of ``vorobound check`` shows (realized (R − R̂)/(εL_i)).

    When every triangle would fall in one bin on the scale of the bounds (a point mass:
    constant L gives R − R̂ = 0 exactly; a CAD part gives values within 10⁻⁵ of it beside
    bounds near 1), the histogram is drawn on the data's own scale instead (``zoomed``), the
    bounds beyond it are listed as off the scale, and ``note`` says so for the title. When
    every value is the same there is no distribution to draw: one bar at ``point_mass``.

    References
    ----------
    Theorem 1, eq. (29); the bounds of eq. (33)–(53).
    """

    values: np.ndarray
    """The finite gaps, in units of εL_i."""
    count: int
    """Guide triangles, including any without a finite gap."""
    bins: np.ndarray | None
    """Bin edges, or None for a point mass of one value."""
    point_mass: float | None
    """The common value when every finite gap is the same."""
    note: str | None
    """The point mass in words for the title, e.g. "point mass: all 1,234 have R − R̂ = 0"."""
    marks: tuple[tuple[str, float, str], ...]
    """(mode, bound over εL_i, claim) of every mode with a finite bound inside the range."""
    xlim: tuple[float, float]
    off_scale: tuple[tuple[str, float, str], ...] = ()
    """The marks beyond the range shown (a point mass drawn on its own scale)."""

    @property
    def zoomed(self) -> bool:
        """True when the histogram is drawn on the data's own scale, not the bounds'."""
        return self.note is not None and self.bins is not None


def gap_histogram_data(gap_ratio, marks) -> GapHistogramData:
    """The histogram's bins, or its point mass, and the range that shows the data and marks.

    ``marks`` holds (mode, bound over εL_i, claim); non-finite bounds are left out.
    """
    gap_ratio = np.asarray(gap_ratio, dtype=float).ravel()
    values = gap_ratio[np.isfinite(gap_ratio)]
    shown = tuple((m, float(v), c) for m, v, c in marks if np.isfinite(v))
    low = min(0.0, float(values.min())) if len(values) else 0.0
    high = max([float(values.max()) if len(values) else 0.0, *(v for _, v, _ in shown)])
    if high <= low:
        high = low + 1.0  # nothing to scale by: a unit range
    width = (high - low) / HISTOGRAM_BINS
    margin = HISTOGRAM_MARGIN * (high - low)
    xlim = (low - margin, high + margin)
    count = len(gap_ratio)
    if len(values) and float(np.ptp(values)) <= width:
        smallest, largest = float(values.min()), float(values.max())
        if smallest == largest:  # exact equality is the point: R − R̂ = 0 with no rounding
            note = _point_mass_note(smallest, len(values), count)
            return GapHistogramData(values, count, None, smallest, note, shown, xlim)
        own, inside, beyond = _own_scale(smallest, largest, shown)
        bins = np.linspace(smallest, largest, HISTOGRAM_BINS + 1)
        note = _interval_note(smallest, largest)
        return GapHistogramData(values, count, bins, None, note, inside, own, beyond)
    edges = np.linspace(low, high + width, HISTOGRAM_BINS + 2) if len(values) else None
    return GapHistogramData(values, count, edges, None, None, shown, xlim)


def _everyone(having: int, count: int) -> str:
    """Who has the value, short enough for a title ("all 1,234 have")."""
    with_value = " with a value" if having < count else ""
    if having == 1:
        return f"the one{with_value} has"
    return f"all {having:,}{with_value} have"


def _point_mass_note(value: float, having: int, count: int) -> str:
    """The sentence that states a point mass of one value."""
    if value == 0.0:
        return f"point mass: {_everyone(having, count)} R − R̂ = 0"
    return f"point mass: {_everyone(having, count)} (R − R̂)/(εL_i) = {value:.6g}"


def _interval_note(smallest: float, largest: float) -> str:
    """The range of a point mass beside the bounds, ends apart and rounded outward."""
    spread = largest - smallest
    size = max(abs(smallest), abs(largest))
    digits = min(12, max(3, math.ceil(math.log10(size / spread)) + 2))
    return (
        "a point mass beside the bounds, drawn on its own scale: every value in "
        f"[{format_down(smallest, digits)}, {format_up(largest, digits)}]"
    )


def _own_scale(smallest: float, largest: float, shown) -> tuple:
    """The range that shows [smallest, largest] with a margin, the marks inside it and the
    marks beyond it (listed as off the scale)."""
    pad = HISTOGRAM_MARGIN * (largest - smallest)
    own = (smallest - pad, largest + pad)
    inside = tuple(m for m in shown if own[0] <= m[1] <= own[1])
    return own, inside, tuple(m for m in shown if m not in inside)


COUNTS_BARS = 120
"""The fixed bins of a tiled check's histogram are grouped to about this many bars."""
TILED_NOTE = "the tiles count on fixed bins, so the spread inside is not shown"
"""Why the point mass of a tiled check is one bar over its range."""


@dataclass(frozen=True)
class GapCountsData:
    """What the gap histogram of a tiled check shows: counts on the tiles' fixed bins
    (:func:`vorobound.tiling.tally.gap_edges`) grouped into bars ``[lefts, rights)``.

    When every counted value falls within one bar (or the data's range is narrower than one
    bar on the bounds' scale: a point mass, as on a CAD part), the counts cannot show the
    distribution inside it; the figure then shows the exact range (min, max) of the data on
    its own scale: one bar spanning it, the bounds beyond listed as off the scale, and
    ``note`` says so. When min = max: a thin bar at ``point_mass``, on the bounds' scale.

    References
    ----------
    Theorem 1, eq. (29); the bounds of eq. (33)–(53).
    """

    lefts: np.ndarray
    rights: np.ndarray
    heights: np.ndarray
    """Guide triangles per bar (empty for a point mass of one value)."""
    total: int
    """Guide triangles counted (those with a finite gap)."""
    point_mass: float | None
    """The common value when min = max."""
    note: str | None
    marks: tuple[tuple[str, float, str], ...]
    """(mode, bound over εL_i, claim) of every mode with a finite bound inside the range."""
    xlim: tuple[float, float]
    off_scale: tuple[tuple[str, float, str], ...] = ()
    """The marks beyond the range shown (a point mass drawn on its own scale)."""

    @property
    def log(self) -> bool:
        """Counts on a log scale: everything but a point mass (one bar, drawn linear)."""
        return self.note is None


def gap_counts_data(edges, counts, gap_range, marks) -> GapCountsData:
    """The bars of a tiled check's gap histogram, or its point mass, and the range shown.

    ``counts`` has one entry below ``edges[0]``, one per bin, and one at or above
    ``edges[-1]``; ``gap_range`` is (min, max) of the data (None or non-finite when unknown).
    Bins are grouped to about :data:`COUNTS_BARS` bars over the range shown; the values below
    the first edge join the first bar and those above the last edge form one bar up to the
    maximum. ``marks`` holds (mode, bound over εL_i, claim); non-finite bounds are left out.
    """
    edges, counts = np.asarray(edges, dtype=float), np.asarray(counts, dtype=np.int64)
    data_min, data_max = (
        float(v) if v is not None and math.isfinite(v) else None for v in gap_range
    )
    low = min(0.0, data_min if data_min is not None else 0.0)
    total = int(counts.sum())
    shown = tuple((m, float(v), c) for m, v, c in marks if math.isfinite(v))
    top = data_max if data_max is not None else 0.0
    high = max([top, 1e-12, *(value for _, value, _ in shown)])
    margin = HISTOGRAM_MARGIN * (high - low)
    xlim = (low - margin, high + margin)
    empty = np.zeros(0)
    if not total:
        return GapCountsData(empty, empty, empty.astype(np.int64), 0, None, None, shown, xlim)
    shown_bins = min(len(edges) - 1, int(np.searchsorted(edges, high * 1.05)) + 1)
    group = max(1, -(-shown_bins // COUNTS_BARS))
    bins = counts[1 : shown_bins + 1]
    bins = np.add.reduceat(bins, np.arange(0, shown_bins, group))
    lefts = edges[0:shown_bins:group].copy()  # not a view: the caller's edges stay
    rights = np.append(lefts[1:], edges[min(shown_bins, len(edges) - 1)])
    bins[0] += counts[0]
    lefts[0] = min(lefts[0], low)
    rest = int(counts[shown_bins + 1 :].sum())
    if rest:
        lefts = np.append(lefts, rights[-1])
        rights = np.append(rights, max(top, rights[-1]))
        bins = np.append(bins, rest)
    width = (edges[1] - edges[0]) * group  # one bar on the bounds' scale
    one_bar = int(np.count_nonzero(bins)) == 1
    if data_min is not None and data_max is not None and (one_bar or data_max - data_min <= width):
        if data_min == data_max:  # exact equality: R − R̂ = 0 with no rounding
            note = _point_mass_note(data_min, total, total)
            return GapCountsData(empty, empty, empty, total, data_min, note, shown, xlim)
        own, inside, beyond = _own_scale(data_min, data_max, shown)
        note = f"{_interval_note(data_min, data_max)}; {TILED_NOTE}"
        return GapCountsData(
            np.array([data_min]),
            np.array([data_max]),
            np.array([total]),
            total,
            None,
            note,
            inside,
            own,
            beyond,
        )
    return GapCountsData(lefts, rights, bins, total, None, None, shown, xlim)
