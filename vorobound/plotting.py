"""Figures. The only module that imports matplotlib (object-oriented API, no display needed)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from .files import atomic_path, ensure_folder, write_set
from .reports.figure_data import (
    Figure3Data,
    TargetFigureData,
    gap_counts_data,
    gap_histogram_data,
)

if TYPE_CHECKING:  # matplotlib's own annotations (3.8+); nothing is imported at run time
    from matplotlib.typing import LineStyleType, RcKeyType

COLUMN_WIDTH_IN = 3.5
"""One column of a two-column paper, in inches."""
FIGURE_HEIGHT_IN = 2.6
"""Height of every figure, in inches."""
DPI = 200
"""Resolution of raster formats."""
TICKS = 6
"""At most this many intervals between major ticks on each axis (fixed: see _fixed_ticks)."""
TICK_STEPS = (1, 2, 5, 10)
"""Tick spacings allowed (times a power of ten): round labels such as 0.002, not 0.0015."""
LEGEND_COLUMNS = 2
"""Columns of the legend of Figure 3, which sits below the axes (never over the data); the
other figures' longer labels take one column."""
LEGEND_ROW_IN = 0.16
"""Height added to a figure per legend row, in inches (7-point text and its spacing)."""
POINT_MASS_WIDTH = 0.012
"""Width of the bar of a point mass in the gap histogram, as a share of the shown range."""
_STYLE: dict[RcKeyType, object] = {
    "font.size": 8,
    "axes.labelsize": 8,
    "legend.fontsize": 7,
    "lines.linewidth": 1.2,
    "svg.hashsalt": "vorobound",  # fixed SVG ids: the same figure gives the same file
}
_NO_DATES = {"pdf": {"CreationDate": None}, "svg": {"Date": None}}
"""Metadata that drops time stamps, so a figure's file depends only on its data."""


def _write(fig, path, fmt: str, dpi: int) -> None:
    import matplotlib

    with matplotlib.rc_context(_STYLE):
        fig.savefig(path, format=fmt, dpi=dpi, metadata=_NO_DATES.get(fmt))


def _axes(ax, legend_rows: int = 0):
    """The given axes and its figure, or a new one-column figure with room for a legend of
    ``legend_rows`` below the axes. The constrained layout keeps every label and tick label
    inside the figure."""
    from matplotlib.figure import Figure

    if ax is not None:
        return ax.figure, ax
    height = FIGURE_HEIGHT_IN + legend_rows * LEGEND_ROW_IN
    fig = Figure(figsize=(COLUMN_WIDTH_IN, height), layout="constrained")
    return fig, fig.add_subplot()


def style():
    """The settings every figure is drawn with, as a context manager (``with style(): ...``)."""
    import matplotlib

    return matplotlib.rc_context(_STYLE)


def rendered(fig):
    """Draw ``fig`` as it is written (style and layout applied) and return the renderer, whose
    extents (``get_window_extent``) say where each label, legend and line ended up. Query
    them inside :func:`style` too: tick labels are made again from the settings in force."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    with style():
        canvas = FigureCanvasAgg(fig)
        canvas.draw()
    return canvas.get_renderer()


def _fixed_ticks(ax) -> None:
    """Tick positions that do not depend on the axes' size. Automatic ones are chosen again
    after the layout has shrunk the axes, and a new last label can then stick out of the
    figure (the clipped last tick of Figure 3)."""
    from matplotlib.ticker import LogLocator, MaxNLocator

    for axis in (ax.xaxis, ax.yaxis):
        if axis.get_scale() == "log":
            axis.set_major_locator(LogLocator(numticks=TICKS))
        else:
            axis.set_major_locator(MaxNLocator(nbins=TICKS, steps=TICK_STEPS))


def plot_figure3(data: Figure3Data, ax=None):
    """Figure 3: the bound on |R − R̂| against ε (L_i = 1), both θ cases, target and markers.

    Returns the matplotlib Figure.

    References
    ----------
    Eq. (46)–(55); Figure 3.
    """
    import matplotlib

    from .rounding import format_down

    with matplotlib.rc_context(_STYLE):
        fig, ax = _axes(ax, legend_rows=3)
        ax.plot(data.eps, data.bound_acute, label=r"bound, $\theta \leq \pi/2$", color="C0")
        ax.plot(
            data.eps,
            data.bound_obtuse,
            label=r"bound, $\theta > \pi/2$",
            color="C1",
            linestyle="--",
        )
        ax.plot(
            data.eps,
            data.target,
            label=r"target $(\rho_f-1)\,\delta L_i$",
            color="k",
            linestyle=":",
        )
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
        _fixed_ticks(ax)
        _legend_below(ax, ax.get_legend_handles_labels()[0], columns=LEGEND_COLUMNS)
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
LEGEND_CHARS = 52
"""Legend labels are wrapped at this many characters, so a legend fits a column's width."""


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


def _star_label(curve) -> str:
    from .rounding import format_down

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
    import numpy as np
    from matplotlib.lines import Line2D

    modes = list(dict.fromkeys(c.mode for c in data.curves))
    with matplotlib.rc_context(_STYLE):
        fig, ax = _axes(ax, legend_rows=len(modes) + 3)
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
            if np.isfinite(upper).any():
                upper_drawn = True
                ax.plot(
                    curve.eps,
                    upper,
                    color=colour,
                    linestyle=":",
                    linewidth=0.9,
                    label=f"_{curve.mode} {curve.target} upper bound",
                )
            if curve.eps_star is not None:
                ax.plot(
                    [curve.eps_star],
                    [1.0],
                    STAR_MARKERS[curve.target],
                    color=colour,
                    markersize=3.5,
                    label=f"_{curve.mode} {curve.target} ε*",
                )
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
        _fixed_ticks(ax)
        _legend_below(ax, handles, columns=1)
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
    with matplotlib.rc_context(_STYLE):
        fig, ax = _axes(ax, legend_rows=len(curves) + 2)
        for curve in curves:
            colour = _colour(curve.mode)
            value = np.where(np.isinf(curve.value), 2 * top, curve.value)  # off the top
            exact, upper = _drawn(curve, value)
            claim = f", {curve.claim}" if curve.claim else ""
            ax.plot(
                curve.eps, exact, color=colour, label=f"{curve.mode}: {_star_label(curve)}{claim}"
            )
            if np.isfinite(upper).any():
                ax.plot(
                    curve.eps,
                    upper,
                    color=colour,
                    linestyle=":",
                    linewidth=0.9,
                    label=f"{curve.mode}: proven upper bound only",
                )
            if curve.eps_star is not None:
                ax.plot(
                    [curve.eps_star],
                    [data.rho_f],
                    "o",
                    color=colour,
                    markersize=3.5,
                    label=f"_{curve.mode} ε*",
                )
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
        _fixed_ticks(ax)
        _legend_below(ax, ax.get_legend_handles_labels()[0], columns=1)
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


def _wrapped(label: str, width: int = LEGEND_CHARS) -> str:
    """A legend label on lines of at most ``width`` characters (mathtext kept whole)."""
    import textwrap

    if "$" in label or len(label) <= width:
        return label
    return "\n".join(textwrap.wrap(label, width, break_long_words=False))


def _legend_below(ax, handles, columns: int = 1) -> None:
    """``handles`` as the legend of ``ax``, outside its axes so that it never covers data:
    below it in a figure of its own (the constrained layout makes room; labels are wrapped to
    the column so that the legend stays inside the figure), else to its right."""
    from matplotlib.layout_engine import ConstrainedLayoutEngine

    for handle in handles:
        handle.set_label(_wrapped(handle.get_label()))
    labels = [h.get_label() for h in handles]
    fig = ax.figure
    if len(fig.axes) == 1 and isinstance(fig.get_layout_engine(), ConstrainedLayoutEngine):
        fig.legend(handles, labels, loc="outside lower center", ncols=columns)
    else:
        ax.legend(handles, labels, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0)


def save(fig, out_dir: str | Path, stem: str, fmt: str = "png", dpi: int = DPI) -> Path:
    """Write ``fig`` to ``out_dir/stem.fmt`` atomically (temporary file, then rename)."""
    path = ensure_folder(out_dir) / f"{stem}.{fmt}"
    with atomic_path(path) as temp:
        _write(fig, temp, fmt, dpi)
    return path


def figure_writer(fig, fmt: str = "png", dpi: int = DPI):
    """A writer for :func:`vorobound.files.write_set`: draws ``fig`` into the path it is given."""
    return lambda temp: _write(fig, temp, fmt, dpi)


def save_set(figures: dict, out_dir: str | Path, fmt: str = "png", dpi: int = DPI) -> list[Path]:
    """Write ``{stem: figure}`` into ``out_dir`` as one set: all files or none are replaced."""
    out = ensure_folder(out_dir)
    return write_set(
        {out / f"{stem}.{fmt}": figure_writer(fig, fmt, dpi) for stem, fig in figures.items()}
    )


def plot_gap_histogram(gap_ratio, marks, title: str, ax=None):
    """Histogram of the realized (R − R̂)/(εL_i) of real guide triangles, each mode's bound marked.

    ``marks`` holds (mode, bound over εL_i, claim); non-finite bounds are left out. Counts are
    on a log scale (a few extreme triangles stay visible). A point mass on the scale of the
    bounds (every triangle in one bin) is drawn on its own scale, the bounds beyond it listed
    as off the scale, and the title says so; when every triangle has the same gap (constant L
    gives R − R̂ = 0 exactly) the figure shows one bar there, clear of the frame. Returns the
    matplotlib Figure.

    References
    ----------
    Theorem 1, eq. (29); the bounds of eq. (33)–(53).
    """
    import matplotlib

    data = gap_histogram_data(gap_ratio, marks)
    entries = len(data.marks) + len(data.off_scale)
    with matplotlib.rc_context(_STYLE):
        fig, ax = _axes(ax, legend_rows=entries + 1)
        if data.point_mass is not None:
            ax.bar(
                [data.point_mass],
                [len(data.values)],
                width=POINT_MASS_WIDTH * (data.xlim[1] - data.xlim[0]),
                color="0.35",
                label="_point mass",
            )
            ax.set_ylim(0, 1.15 * len(data.values))
        elif data.bins is not None:
            ax.hist(data.values, bins=data.bins, color="0.5", log=True)
            ax.set_ylim(bottom=0.5)  # a bin of one triangle stays visible
        heading = f"{title}: {data.count:,} guide triangles"
        if data.note is not None:
            heading += f"\n{data.note}"
        _gap_axes(ax, data.marks, data.xlim, heading, data.off_scale)
    return fig


def plot_gap_counts(edges, counts, gap_range, marks, title: str, ax=None):
    """The same histogram from counts on fixed bins (a tiled check's merged histogram).

    ``counts`` has one entry below ``edges[0]``, one per bin, and one at or above
    ``edges[-1]``; ``gap_range`` is (min, max) of the data. Bins are grouped to about 120 bars
    over the range shown (:func:`vorobound.reports.figure_data.gap_counts_data`). A point mass
    (every value within one bar) is one bar over the data's exact range on its own scale, the
    bounds beyond it listed as off the scale, and the title says that the tiles' fixed bins
    do not show the spread inside it. Returns the matplotlib Figure.
    """
    import matplotlib

    data = gap_counts_data(edges, counts, gap_range, marks)
    with matplotlib.rc_context(_STYLE):
        rows = len(data.marks) + len(data.off_scale) + (data.note is not None)
        fig, ax = _axes(ax, legend_rows=rows)
        if data.point_mass is not None:
            ax.bar(
                [data.point_mass],
                [data.total],
                width=POINT_MASS_WIDTH * (data.xlim[1] - data.xlim[0]),
                color="0.35",
                label="_point mass",
            )
        elif len(data.heights):
            widths = data.rights - data.lefts
            ax.bar(data.lefts, data.heights, width=widths, align="edge", color="0.5", log=data.log)
        if data.log:
            if data.total:
                ax.set_ylim(bottom=0.5)  # a bin of one triangle stays visible
        else:
            ax.set_ylim(0, 1.15 * data.total)
        heading = f"{title}: {data.total:,} guide triangles"
        if data.note is not None:
            heading += f"\n{data.note}"
        _gap_axes(ax, data.marks, data.xlim, heading, data.off_scale)
    return fig


TITLE_CHARS = 46
"""Titles are wrapped at this many characters, so a title fits a column's width."""


def _gap_axes(ax, marks, xlim, title: str, off_scale=()) -> None:
    """The bounds' lines, labels, ticks and legend of a gap histogram; ``off_scale`` are
    bounds beyond the range shown (listed in the legend, not drawn)."""
    import textwrap

    from matplotlib.lines import Line2D

    from .rounding import format_up

    for index, (mode, value, claim) in enumerate(marks):
        label = f"{mode} ({claim}): {format_up(value, 3)}"
        style = ("-", "--", "-.", ":")[index % 4]  # equal bounds stay visible
        ax.axvline(value, color=f"C{index}", linewidth=1.2, linestyle=style, label=label)
    handles = ax.get_legend_handles_labels()[0]
    for mode, value, claim in off_scale:
        label = f"{mode} ({claim}): {format_up(value, 3)}, off the scale →"
        handles.append(Line2D([], [], color="0.6", linestyle="none", marker=">", label=label))
    ax.set_xlim(*xlim)
    ax.set_xlabel(r"realized $(R - \hat R)\,/\,(\epsilon L_i)$")
    ax.set_ylabel("guide triangles")
    lines = [row for part in title.split("\n") for row in textwrap.wrap(part, TITLE_CHARS)]
    ax.set_title("\n".join(lines), fontsize=8)
    _fixed_ticks(ax)
    if handles:
        _legend_below(ax, handles, columns=1)
    ax.grid(alpha=0.3)


def plot_reconstruct_quality(distributions: dict, title: str):
    """Histograms of M̂'s facets: one panel per measured quantity (label ↦ per-facet values).

    Returns the matplotlib Figure.
    """
    import matplotlib
    import numpy as np
    from matplotlib.figure import Figure

    with matplotlib.rc_context(_STYLE):
        rows = (len(distributions) + 1) // 2
        fig = Figure(figsize=(2 * COLUMN_WIDTH_IN, FIGURE_HEIGHT_IN * rows), layout="constrained")
        axes = fig.subplots(rows, 2, squeeze=False).reshape(-1)
        for ax, (label, values) in zip(axes, distributions.items(), strict=False):
            values = np.asarray(values, dtype=float)
            values = values[np.isfinite(values)]
            if len(values):
                ax.hist(values, bins=80, color="0.5", log=True)
            ax.set_xlabel(label)
            ax.set_ylabel("facets")
            ax.grid(alpha=0.3)
        for ax in axes[len(distributions) :]:
            ax.set_visible(False)
        fig.suptitle(title)
    return fig


def plot_reconstruct_sweep(eps, panels: dict, correct, marks, title: str):
    """M̂'s measurements against ε, one panel per quantity (label ↦ values per ε), filled
    markers where M̂ has the right topology and crosses where it does not, and every bound's ε*
    as a vertical line (``marks``: (label, target, ε*) triples).

    Returns the matplotlib Figure.
    """
    import matplotlib
    import numpy as np
    from matplotlib.figure import Figure

    eps = np.asarray(eps, dtype=float)
    correct = np.asarray(correct, dtype=bool)
    with matplotlib.rc_context(_STYLE):
        count = len(panels)
        fig = Figure(
            figsize=(2 * COLUMN_WIDTH_IN, 0.8 * FIGURE_HEIGHT_IN * count + 0.6),
            layout="constrained",
        )
        axes = fig.subplots(count, 1, sharex=True, squeeze=False)[:, 0]
        for ax, (label, values) in zip(axes, panels.items(), strict=True):
            values = np.array([np.nan if v is None else v for v in values], dtype=float)
            ax.plot(eps, values, color="0.6", linewidth=0.8)
            ax.plot(eps[correct], values[correct], "o", color="C0", markersize=3.5)
            wrong = ~correct & np.isfinite(values)  # a cross at the wrong M̂'s own value
            if wrong.any():
                ax.plot(eps[wrong], values[wrong], "x", color="C3", markersize=6)
            blank = ~correct & ~np.isfinite(values)  # no value to plot: a cross on the axis
            if blank.any():  # (an empty unclipped line would upset the layout's extents)
                ax.plot(
                    eps[blank],
                    np.zeros(int(blank.sum())),
                    "x",
                    color="C3",
                    markersize=6,
                    clip_on=False,
                    transform=ax.get_xaxis_transform(),
                )
            ax.set_ylabel(label)
        _eps_axes(fig, axes, marks, f"{title}\no: right topology, x: wrong (on the axis: no value)")
    return fig


def _eps_axes(fig, axes, marks, title: str) -> None:
    """Shared ε axis (log) of a figure against ε: grid, every bound's ε* as a vertical line
    (``marks``: (label, target, ε*) triples; additive dashed, ratio solid; ε* rounded down,
    numbered, tags of near-coincident lines on separate rows), title, legend."""
    from .rounding import format_down

    colours = {name: f"C{i}" for i, name in enumerate(dict.fromkeys(m[0] for m in marks))}
    styles = {"additive": "--", "ratio": "-"}
    for ax in axes:
        ax.grid(alpha=0.3, which="both")
        for name, target, star in marks:
            ax.axvline(
                star,
                color=colours[name],
                linewidth=0.9,
                linestyle=styles.get(target, ":"),
                label=f"{name}, {target}: ε* = {format_down(star)}",
            )
    axes[-1].set_xscale("log")
    axes[-1].set_xlabel(r"sampling density $\epsilon$")
    axes[0].set_title(title)
    _tag_lines(axes[0], [star for _, _, star in marks])
    handles, labels = axes[0].get_legend_handles_labels()
    labels = [f"{index}  {label}" for index, label in enumerate(labels, start=1)]
    if handles:
        fig.legend(handles, labels, loc="outside right upper", fontsize=6)


def plot_reconstruct_draws(eps, share_correct, spreads: dict, band, marks, title: str):
    """M̂ over many draws against ε: the share of draws with the right topology (the
    transition band shaded between the largest ε where every draw was right and the smallest
    where none was), then one panel per measurement (label ↦ (medians, maxima) per ε), and
    every bound's ε* as a vertical line.

    Returns the matplotlib Figure.
    """
    import matplotlib
    import numpy as np
    from matplotlib.figure import Figure

    eps = np.asarray(eps, dtype=float)

    def values(seq):
        return np.array([np.nan if v is None else v for v in seq], dtype=float)

    with matplotlib.rc_context(_STYLE):
        count = 1 + len(spreads)
        fig = Figure(
            figsize=(2 * COLUMN_WIDTH_IN, 0.8 * FIGURE_HEIGHT_IN * count + 0.6),
            layout="constrained",
        )
        axes = fig.subplots(count, 1, sharex=True, squeeze=False)[:, 0]
        axes[0].plot(eps, values(share_correct), "o-", color="C0", markersize=3.5)
        axes[0].set_ylim(-0.05, 1.05)
        axes[0].set_ylabel("share of draws right")
        low, high = band
        if low is not None and high is not None and low < high:
            axes[0].axvspan(low, high, color="C1", alpha=0.15, linewidth=0)
        for ax, (label, (median, largest)) in zip(axes[1:], spreads.items(), strict=True):
            ax.plot(eps, values(median), "o-", color="C0", markersize=3.5, label="median")
            ax.plot(eps, values(largest), "^--", color="C3", markersize=3.5, label="max")
            ax.set_ylabel(label)
            ax.legend(fontsize=6, loc="upper left")
        _eps_axes(fig, axes, marks, f"{title}: shaded, the transition band")
    return fig


TAG_GAP = 0.045
"""Tags of vertical lines closer than this share of the axes' width go on separate rows."""
TAG_ROW = 0.1
"""Height of a row of tags, as a share of the axes' height."""


def _tag_lines(ax, positions) -> None:
    """Number the vertical lines at ``positions`` (1, 2, ... in the order of the legend) with
    small tags inside the top of ``ax``; tags of lines too close to read apart are put on
    rows one below the other, so that near-coincident lines stay distinguishable."""
    import numpy as np

    if not positions:
        return
    low, high = ax.get_xlim()
    log = ax.get_xscale() == "log"

    def scale(value):
        return np.log10(value) if log else value

    span = scale(high) - scale(low)
    rows: list[float] = []  # the right-most tag position on each row
    for index in np.argsort(positions, kind="stable"):
        where = (scale(positions[index]) - scale(low)) / span
        row = next((r for r, last in enumerate(rows) if where - last >= TAG_GAP), len(rows))
        if row == len(rows):
            rows.append(where)
        rows[row] = where
        ax.text(
            positions[index],
            0.97 - TAG_ROW * row,
            str(index + 1),
            transform=ax.get_xaxis_transform(),
            ha="center",
            va="top",
            fontsize=6,
            bbox={
                "boxstyle": "round,pad=0.15",
                "facecolor": "white",
                "edgecolor": "0.6",
                "lw": 0.5,
            },
        )
