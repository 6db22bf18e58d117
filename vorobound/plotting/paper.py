"""The paper's figures: Figure 3, both targets by mode (the comparison) and the ratio target."""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..reports.figure_data import Figure3Data, TargetFigureData
from .style import STYLE, axes_of, fixed_ticks, legend_below

if TYPE_CHECKING:  # matplotlib's own annotations (3.8+); nothing is imported at run time
    from matplotlib.typing import LineStyleType


LEGEND_COLUMNS = 2
"""Columns of the legend of Figure 3, which sits below the axes (never over the data); the
other figures' longer labels take one column."""


def plot_figure3(data: Figure3Data, ax=None):
    """Figure 3: the bound on |R − R̂| against ε (L_i = 1), both θ cases, target and markers.

    Returns the matplotlib Figure.

    References
    ----------
    Eq. (46)–(55); Figure 3.
    """
    import matplotlib

    from ..rounding import format_down

    with matplotlib.rc_context(STYLE):
        fig, ax = axes_of(ax, legend_rows=3)
        for values, label, color, style in (
            (data.bound_acute, r"bound, $\theta \leq \pi/2$", "C0", "-"),
            (data.bound_obtuse, r"bound, $\theta > \pi/2$", "C1", "--"),
            (data.target, r"target $(\rho_f-1)\,\delta L_i$", "k", ":"),
        ):
            ax.plot(data.eps, values, label=label, color=color, linestyle=style)
        for eps_mark, label, color in (
            (data.eps_baseline, r"$\epsilon = 1/500$", "C2"),
            (data.eps_star, rf"$\epsilon^* = {format_down(data.eps_star)}$", "C3"),
        ):
            ax.axvline(eps_mark, color=color, linewidth=0.8, label=label)
        ax.set_xlabel(r"sampling density $\epsilon$")
        ax.set_ylabel(r"bound on $|R - \hat R|$  [units of $L_i$]")
        ax.set_title(f"Figure 3 ({data.mode} chain)")
        ax.set_xlim(0, data.eps[-1])
        ax.set_ylim(0, None)
        fixed_ticks(ax)
        legend_below(ax, ax.get_legend_handles_labels()[0], columns=LEGEND_COLUMNS)
        ax.grid(alpha=0.3)
    return fig


MODE_STYLE = {"paper": "C0", "rigorous": "C1", "tight": "C2", "tight, λ = 1": "C3"}
"""One colour per mode in every figure of both targets."""
TARGET_LINES: dict[str, LineStyleType] = {"additive": "-", "ratio": "--"}
"""One line style per target in the comparison."""
TARGET_WORDS = {
    "additive": r"additive: $R - \hat R \leq (\rho_f - 1)\,\delta L_i$",
    "ratio": r"ratio: $R \leq \rho_f \hat R$, eq. (54)",
}
FRACTION_YLIM = (1e-2, 20.0)
"""The comparison shows fractions of the target in this range (log scale)."""
RATIO_YLIM_FACTOR = 2.5
"""The ratio figure shows R/R̂ up to 1 + this multiple of ρ_f − 1."""
STAR_MARKERS = {"additive": "o", "ratio": "s"}


def _colour(mode: str) -> str:
    return MODE_STYLE.get(mode, "C4")


def _drawn(curve, values):
    """(ε, values) split where the tight closed form is a proven bound only: the exact part
    (solid) and the upper-bound-only part (NaN elsewhere), each a drawable array."""
    import numpy as np

    exact = np.where(curve.upper_only, np.nan, values)
    upper = np.where(curve.upper_only, values, np.nan)
    # join the pieces: each also takes its neighbour's first point
    edges = np.flatnonzero(np.diff(curve.upper_only.astype(int)) != 0)
    for edge in edges:
        upper[edge] = values[edge]
        upper[edge + 1] = values[edge + 1]
    return exact, upper


def _upper_and_star(ax, curve, upper, colour, upper_label: str, star: tuple) -> bool:
    """A curve's upper-bound-only part (dotted; see :func:`_drawn`) and its ε* marker, ``star``
    = (height, marker, label); True when there was an upper-bound-only part to draw."""
    import numpy as np

    drawn = bool(np.isfinite(upper).any())
    if drawn:
        ax.plot(curve.eps, upper, color=colour, linestyle=":", linewidth=0.9, label=upper_label)
    if curve.eps_star is not None:
        height, marker, label = star
        ax.plot([curve.eps_star], [height], marker, color=colour, markersize=3.5, label=label)
    return drawn


def _star_label(curve) -> str:
    from ..rounding import format_down

    if curve.eps_star is None:
        return "no ε*"
    return f"ε* = {format_down(curve.eps_star)}"


def plot_comparison(data: TargetFigureData, ax=None):
    """Every mode's bound as a fraction of each target's allowance, against ε: solid for the
    additive target, dashed for the ratio target; a curve meets its target below 1, and its
    ε* (marked) is where it crosses 1.

    Returns the matplotlib Figure.

    References
    ----------
    Eq. (29)–(30), (33)–(55); docs/tight.md.
    """
    import matplotlib
    from matplotlib.lines import Line2D

    modes = list(dict.fromkeys(c.mode for c in data.curves))
    with matplotlib.rc_context(STYLE):
        fig, ax = axes_of(ax, legend_rows=len(modes) + 3)
        upper_drawn = False
        for curve in data.curves:
            colour, style = _colour(curve.mode), TARGET_LINES[curve.target]
            exact, upper = _drawn(curve, curve.fraction)
            ax.plot(
                curve.eps,
                exact,
                color=colour,
                linestyle=style,
                label=f"_{curve.mode} {curve.target}",
            )
            name = f"_{curve.mode} {curve.target}"
            star = (1.0, STAR_MARKERS[curve.target], f"{name} ε*")
            upper_drawn |= _upper_and_star(ax, curve, upper, colour, f"{name} upper bound", star)
        ax.axhline(1.0, color="k", linewidth=0.8, label="_target met below 1")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlim(data.curves[0].eps[0], data.curves[0].eps[-1])
        ax.set_ylim(*FRACTION_YLIM)
        ax.set_xlabel(r"sampling density $\epsilon$")
        ax.set_ylabel("bound / target's allowance")
        ax.set_title("Both targets by mode (met below 1)")
        handles = []
        for mode in modes:
            stars = {c.target: c for c in data.curves if c.mode == mode}
            text = f"{mode}: ε* = " + ", ".join(
                f"{_star_label(stars[t])[5:]} ({t[:3]}.)"
                for t in ("additive", "ratio")
                if t in stars
            )
            handles.append(Line2D([], [], color=_colour(mode), label=text))
        for target, words in TARGET_WORDS.items():
            handles.append(
                Line2D(
                    [],
                    [],
                    color="0.3",
                    linestyle=TARGET_LINES[target],
                    marker=STAR_MARKERS[target],
                    markersize=3.5,
                    label=words,
                )
            )
        if upper_drawn:
            handles.append(
                Line2D(
                    [],
                    [],
                    color="0.3",
                    linestyle=":",
                    label="tight closed form: proven upper bound only",
                )
            )
        fixed_ticks(ax)
        legend_below(ax, handles, columns=1)
        ax.grid(alpha=0.3, which="both")
    return fig


def plot_ratio(data: TargetFigureData, ax=None):
    """The ratio target: each mode's bound on R/R̂ against ε, ρ_f, the paper's ε and every
    mode's ε* of the ratio target (where its curve meets ρ_f).

    Returns the matplotlib Figure.

    References
    ----------
    Eq. (30), (54); docs/tight.md, "The ratio target".
    """
    import matplotlib
    import numpy as np

    curves = data.of_target("ratio")
    top = 1 + RATIO_YLIM_FACTOR * (data.rho_f - 1)
    with matplotlib.rc_context(STYLE):
        fig, ax = axes_of(ax, legend_rows=len(curves) + 2)
        for curve in curves:
            colour = _colour(curve.mode)
            value = np.where(np.isinf(curve.value), 2 * top, curve.value)  # off the top
            exact, upper = _drawn(curve, value)
            claim = f", {curve.claim}" if curve.claim else ""
            ax.plot(
                curve.eps, exact, color=colour, label=f"{curve.mode}: {_star_label(curve)}{claim}"
            )
            star = (data.rho_f, "o", f"_{curve.mode} ε*")
            _upper_and_star(
                ax, curve, upper, colour, f"{curve.mode}: proven upper bound only", star
            )
            if curve.eps_star is not None:
                ax.axvline(
                    curve.eps_star,
                    color=colour,
                    linewidth=0.6,
                    linestyle="--",
                    label=f"_{curve.mode} ε* line",
                )
        ax.axhline(
            data.rho_f,
            color="k",
            linestyle=":",
            label=rf"$\rho_f = {data.rho_f:g}$ ($R \leq \rho_f \hat R$ below)",
        )
        ax.axvline(
            data.paper_eps,
            color="0.4",
            linewidth=1.0,
            linestyle="-.",
            label=f"the paper's ε = {data.paper_eps:g}",
        )
        ax.set_xscale("log")
        ax.set_xlim(*_ratio_span(curves, data.paper_eps))
        ax.set_ylim(1.0, top)
        ax.set_xlabel(r"sampling density $\epsilon$")
        ax.set_ylabel(r"bound on $R\,/\,\hat R$")
        ax.set_title(r"Ratio target $R \leq \rho_f \hat R$ (eq. (54))")
        fixed_ticks(ax)
        legend_below(ax, ax.get_legend_handles_labels()[0], columns=1)
        ax.grid(alpha=0.3, which="both")
    return fig


RATIO_SPAN = 4.0
"""The ratio figure spans ε from a fourth of the smallest marked ε to four times the largest."""


def _ratio_span(curves, paper_eps: float) -> tuple[float, float]:
    """The ε range of the ratio figure: every ε* and the paper's ε with room on both sides,
    within the computed grid."""
    marked = [c.eps_star for c in curves if c.eps_star is not None] + [paper_eps]
    grid = curves[0].eps
    return max(grid[0], min(marked) / RATIO_SPAN), min(grid[-1], max(marked) * RATIO_SPAN)
