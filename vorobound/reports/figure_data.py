"""The data behind the figures: Figure 3 of the paper and the comparison of modes."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..bounds.chain import chain_bounds
from ..bounds.eps_star import EpsStar, solve_eps_star
from ..bounds.params import Mode, QualityParams, Target
from ..constants import BASELINE_EPS
from ..progress import Counter, Progress

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


@dataclass(frozen=True)
class ModeCurve:
    """bound(ε)/(ε L_i) for one mode, and its ε*."""

    mode: str
    eps: np.ndarray
    bound_over_eps: np.ndarray
    eps_star: float


@dataclass(frozen=True)
class ComparisonData:
    curves: tuple[ModeCurve, ...]
    target_over_eps: float
    """(ρ_f − 1)·(δ/ε): the target divided by ε L_i, constant in ε."""


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


COMPARISON_EPS = np.geomspace(1e-4, 0.1, 300)
"""ε grid of the comparison figure (closed-form chains)."""
TIGHT_CURVE_POINTS = 7
"""Points per tight curve (markers; the closed form makes each cheap, the optimizer where it
is not proven exact takes about a second per point)."""
TIGHT_CURVE_SPAN = (1 / 20, 3.0)
"""The tight curve runs from ε*/20 to 3ε* (at most ``TIGHT_CURVE_EPS_MAX``)."""
TIGHT_CURVE_EPS_MAX = 0.5


def chain_curve(quality: QualityParams, mode: Mode | str, eps=COMPARISON_EPS) -> ModeCurve:
    """bound(ε)/(ε L_i) of a chain on ``eps``, and its ε* (additive target)."""
    quality = quality.but(target=Target.additive, lipschitz=None)
    star = solve_eps_star(quality, mode)
    chain = chain_bounds(quality.at(float(eps[0])), mode, eps=eps)
    return ModeCurve(Mode(mode).value, eps, chain.bound / (eps * quality.lfs), star.eps_star)


def tight_curve(star: EpsStar, progress: Progress | None = None) -> ModeCurve:
    """Tight supremum / (ε L_i) at a few ε around a tight additive ε* (its parameters, λ
    included)."""
    from ..bounds.tight.method import tight_bound

    low, high = TIGHT_CURVE_SPAN
    eps = np.geomspace(
        star.eps_star * low, min(high * star.eps_star, TIGHT_CURVE_EPS_MAX), TIGHT_CURVE_POINTS
    )
    quality, lipschitz = star.quality, star.lipschitz
    name = "tight" if lipschitz is None else f"tight, λ = {lipschitz:g}"
    counter = Counter(progress, f"{name} curve", len(eps))
    values = []
    for e in eps:
        values.append(tight_bound(quality.at(float(e))).value)
        counter.step()
    return ModeCurve(name, eps, np.array(values) / (eps * quality.lfs), star.eps_star)


def comparison_data(curves: list[ModeCurve], quality: QualityParams) -> ComparisonData:
    """The comparison figure's data: every mode's curve and the target over ε L_i."""
    return ComparisonData(tuple(curves), (quality.rho_f - 1) * quality.delta_ratio)


TIGHT_SETTINGS = (None, 1.0)
"""Tight-mode variants shown: the paper's constraints, and with the 1-Lipschitz condition."""


def figure_set_data(
    quality: QualityParams, tight_stars: list[EpsStar], progress: Progress | None = None
) -> tuple[Figure3Data, ComparisonData]:
    """The data of every figure: Figure 3 and the comparison of modes.

    ``tight_stars`` are the tight additive ε* to draw (one curve each); empty for none.
    """
    curves = [chain_curve(quality, mode) for mode in ("paper", "rigorous")]
    for star in tight_stars:
        curves.append(tight_curve(star, progress))
    return figure3_data(quality), comparison_data(curves, quality)


HISTOGRAM_BINS = 120
"""Bins of the gap histogram across the shown range."""
HISTOGRAM_MARGIN = 0.04
"""Share of the shown range left empty left of the data and right of the last mark, so that no
bar or line lies on the frame."""


@dataclass(frozen=True)
class GapHistogramData:
    """What the gap histogram of ``vorobound check`` shows (realized (R − R̂)/(εL_i)).

    When every triangle falls in one bin (a point mass: constant L gives R − R̂ = 0 exactly)
    there are no bins; ``point_mass`` holds the value and ``note`` says it in words.

    References
    ----------
    Theorem 1, eq. (29); the bounds of eq. (33)–(53).
    """

    values: np.ndarray
    """The finite gaps, in units of εL_i."""
    count: int
    """Guide triangles, including any without a finite gap."""
    bins: np.ndarray | None
    """Bin edges, or None for a point mass."""
    point_mass: float | None
    """The common value when every finite gap falls in one bin (its centre if they differ)."""
    note: str | None
    """The point mass in words, e.g. "all 1,234 triangles have R − R̂ = 0"."""
    marks: tuple[tuple[str, float, str], ...]
    """(mode, bound over εL_i, claim) of every mode with a finite bound."""
    xlim: tuple[float, float]


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
    if len(values) and float(np.ptp(values)) <= width:
        return GapHistogramData(
            values,
            len(gap_ratio),
            None,
            *_point_mass(values, len(gap_ratio)),
            shown,
            xlim,
        )
    bins = np.linspace(low, high + width, HISTOGRAM_BINS + 2) if len(values) else None
    return GapHistogramData(values, len(gap_ratio), bins, None, None, shown, xlim)


def _point_mass(values: np.ndarray, count: int) -> tuple[float, str]:
    """The value of a point mass and the sentence that states it (exact equality is the
    point: constant L gives R − R̂ = 0 with no rounding)."""
    smallest, largest = float(values.min()), float(values.max())
    with_value = " with a value" if len(values) < count else ""
    if len(values) == 1:
        everyone = f"the one triangle{with_value} has"
    else:
        everyone = f"all {len(values):,} triangles{with_value} have"
    if smallest == largest == 0.0:
        return 0.0, f"{everyone} R − R̂ = 0"
    if smallest == largest:
        return smallest, f"{everyone} (R − R̂)/(εL_i) = {smallest:.6g}"
    middle = 0.5 * (smallest + largest)
    return middle, f"{everyone} (R − R̂)/(εL_i) in [{smallest:.6g}, {largest:.6g}]"
