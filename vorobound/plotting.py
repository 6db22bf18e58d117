"""Figures. The only module that imports matplotlib (object-oriented API, no display needed)."""

from __future__ import annotations

from pathlib import Path

from .files import atomic_path, ensure_folder, write_set
from .reports.figure_data import (
    HISTOGRAM_MARGIN,
    ComparisonData,
    Figure3Data,
    gap_histogram_data,
)

COLUMN_WIDTH_IN = 3.5
"""One column of a two-column paper, in inches."""
FIGURE_HEIGHT_IN = 2.6
"""Height of every figure, in inches."""
DPI = 200
"""Resolution of raster formats."""
COMPARISON_YLIM_FACTOR = 2.5
"""The comparison figure shows bounds up to this multiple of the target."""
TICKS = 6
"""At most this many intervals between major ticks on each axis (fixed: see _fixed_ticks)."""
TICK_STEPS = (1, 2, 5, 10)
"""Tick spacings allowed (times a power of ten): round labels such as 0.002, not 0.0015."""
LEGEND_COLUMNS = 2
"""Columns of the legends of Figure 3 and the comparison, which sit below the axes (never over
the data); the gap histogram's longer labels take one column."""
LEGEND_ROW_IN = 0.16
"""Height added to a figure per legend row, in inches (7-point text and its spacing)."""
POINT_MASS_WIDTH = 0.012
"""Width of the bar of a point mass in the gap histogram, as a share of the shown range."""
_STYLE = {
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


def _legend_outside(ax, columns: int = LEGEND_COLUMNS, first: str | None = None) -> None:
    """The legend of ``ax`` outside its axes, so that it never covers data: below it in a
    figure of its own (the constrained layout makes room), else to its right. The entry
    labelled ``first`` leads."""
    from matplotlib.layout_engine import ConstrainedLayoutEngine

    handles, labels = ax.get_legend_handles_labels()
    if first in labels:
        lead = labels.index(first)
        handles.insert(0, handles.pop(lead))
        labels.insert(0, labels.pop(lead))
    fig = ax.figure
    if len(fig.axes) == 1 and isinstance(fig.get_layout_engine(), ConstrainedLayoutEngine):
        fig.legend(handles, labels, loc="outside lower center", ncols=columns)
    else:
        ax.legend(handles, labels, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0)


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
            (data.eps_star, rf"$\epsilon^* = {data.eps_star:.4f}$", "C3"),
        ):
            ax.axvline(eps_mark, color=color, linewidth=0.8, label=label)
        ax.set_xlabel(r"sampling density $\epsilon$")
        ax.set_ylabel(r"bound on $|R - \hat R|$  [units of $L_i$]")
        ax.set_title(f"Figure 3 ({data.mode} chain)")
        ax.set_xlim(0, data.eps[-1])
        ax.set_ylim(0, None)
        _fixed_ticks(ax)
        _legend_outside(ax)
        ax.grid(alpha=0.3)
    return fig


def plot_comparison(data: ComparisonData, ax=None):
    """bound(ε)/ε for every mode, the target (ρ_f − 1)·δ/ε·L_i, and each mode's ε*.

    Returns the matplotlib Figure.
    """
    import matplotlib

    with matplotlib.rc_context(_STYLE):
        fig, ax = _axes(ax, legend_rows=-(-(len(data.curves) + 1) // LEGEND_COLUMNS))
        for index, curve in enumerate(data.curves):
            color = f"C{index}"
            ax.plot(
                curve.eps,
                curve.bound_over_eps,
                color=color,
                label=rf"{curve.mode}: $\epsilon^* = {curve.eps_star:.4g}$",
                marker="o" if curve.mode.startswith("tight") else None,
                markersize=2.5,
            )
            ax.axvline(curve.eps_star, color=color, linewidth=0.6, linestyle="--")
        ax.axhline(
            data.target_over_eps,
            color="k",
            linestyle=":",
            label=rf"target $(\rho_f-1)\,\delta/\epsilon = {data.target_over_eps:.2f}$",
        )
        ax.set_xscale("log")
        ax.set_xlabel(r"sampling density $\epsilon$")
        ax.set_ylabel(r"bound on $(R - \hat R)\,/\,(\epsilon L_i)$")
        ax.set_title("Bounds on R − R̂ by mode")
        ax.set_ylim(0, COMPARISON_YLIM_FACTOR * data.target_over_eps)
        _fixed_ticks(ax)
        _legend_outside(ax)
        ax.grid(alpha=0.3, which="both")
    return fig


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
    on a log scale (a few extreme triangles stay visible). When every triangle has the same
    gap (constant L gives R − R̂ = 0 exactly) the figure shows one labelled bar there, clear of
    the frame, instead of a histogram. Returns the matplotlib Figure.

    References
    ----------
    Theorem 1, eq. (29); the bounds of eq. (33)–(53).
    """
    import matplotlib

    data = gap_histogram_data(gap_ratio, marks)
    entries = len(data.marks) + (data.point_mass is not None)
    with matplotlib.rc_context(_STYLE):
        fig, ax = _axes(ax, legend_rows=entries)
        if data.point_mass is not None:
            ax.bar(
                [data.point_mass],
                [len(data.values)],
                width=POINT_MASS_WIDTH * (data.xlim[1] - data.xlim[0]),
                color="0.35",
                label=data.note,
            )
            ax.set_ylim(0, 1.15 * len(data.values))
        elif data.bins is not None:
            ax.hist(data.values, bins=data.bins, color="0.5", log=True)
            ax.set_ylim(bottom=0.5)  # a bin of one triangle stays visible
        _gap_axes(ax, data.marks, data.xlim, f"{title}: {data.count:,}", data.note)
    return fig


def plot_gap_counts(edges, counts, gap_range, marks, title: str, ax=None):
    """The same histogram from counts on fixed bins (a tiled check's merged histogram).

    ``counts`` has one entry below ``edges[0]``, one per bin, and one at or above
    ``edges[-1]``; ``gap_range`` is (min, max) of the data. Bins are grouped to about 120 bars
    over the range shown; the values below the first edge join the first bar and those above
    the last edge form one bar up to the maximum.
    """
    import math

    import matplotlib
    import numpy as np

    edges, counts = np.asarray(edges, dtype=float), np.asarray(counts, dtype=np.int64)
    data_min, data_max = gap_range
    low = min(0.0, data_min)
    total = int(counts.sum())
    shown = tuple((m, float(v), c) for m, v, c in marks if math.isfinite(v))
    high = max([data_max, 1e-12, *(value for _, value, _ in shown)])
    with matplotlib.rc_context(_STYLE):
        fig, ax = _axes(ax, legend_rows=len(shown))
        if total:
            shown_bins = min(len(edges) - 1, int(np.searchsorted(edges, high * 1.05)) + 1)
            group = max(1, -(-shown_bins // 120))
            bins = counts[1 : shown_bins + 1]
            bins = np.add.reduceat(bins, np.arange(0, shown_bins, group))
            lefts = edges[0:shown_bins:group]
            rights = np.append(lefts[1:], edges[min(shown_bins, len(edges) - 1)])
            bins[0] += counts[0]
            lefts[0] = min(lefts[0], low)
            rest = int(counts[shown_bins + 1 :].sum())
            if rest:
                lefts, rights = (
                    np.append(lefts, rights[-1]),
                    np.append(rights, max(data_max, rights[-1])),
                )
                bins = np.append(bins, rest)
            ax.bar(lefts, bins, width=rights - lefts, align="edge", color="0.5", log=True)
            ax.set_ylim(bottom=0.5)
        margin = HISTOGRAM_MARGIN * (high - low)
        _gap_axes(ax, shown, (low - margin, high + margin), f"{title}: {total:,}", None)
    return fig


def _gap_axes(ax, marks, xlim, title: str, note: str | None) -> None:
    """The bounds' lines, labels, ticks and legend of a gap histogram."""
    for index, (mode, value, claim) in enumerate(marks):
        label = f"{mode} ({claim}): {value:.3g}"
        style = ("-", "--", "-.", ":")[index % 4]  # equal bounds stay visible
        ax.axvline(value, color=f"C{index}", linewidth=1.2, linestyle=style, label=label)
    ax.set_xlim(*xlim)
    ax.set_xlabel(r"realized $(R - \hat R)\,/\,(\epsilon L_i)$")
    ax.set_ylabel("guide triangles")
    ax.set_title(f"{title} guide triangles")
    _fixed_ticks(ax)
    if len(marks) + (note is not None):
        _legend_outside(ax, columns=1, first=note)
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
            wrong = eps[~correct]  # crosses on the axis: a wrong M̂ may have no value to plot
            ax.plot(
                wrong,
                np.full(len(wrong), 0.04),
                "x",
                color="C3",
                markersize=6,
                transform=ax.get_xaxis_transform(),
            )
            ax.set_ylabel(label)
        _eps_axes(fig, axes, marks, f"{title}: o right topology, x wrong")
    return fig


def _eps_axes(fig, axes, marks, title: str) -> None:
    """Shared ε axis (log) of a figure against ε: grid, every bound's ε* as a vertical line
    (``marks``: (label, target, ε*) triples; additive dashed, ratio solid), title, legend."""
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
                label=f"{name}, {target}: ε* = {star:.3g}",
            )
    axes[-1].set_xscale("log")
    axes[-1].set_xlabel(r"sampling density $\epsilon$")
    axes[0].set_title(title)
    handles, labels = axes[0].get_legend_handles_labels()
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
