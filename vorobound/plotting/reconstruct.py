"""The figures of VoroCrust's M̂: its facets' quality, and its measurements against ε (one
draw, or many) with every bound's ε*."""

from __future__ import annotations

from .style import COLUMN_WIDTH_IN, FIGURE_HEIGHT_IN, STYLE


def plot_reconstruct_quality(distributions: dict, title: str):
    """Histograms of M̂'s facets: one panel per measured quantity (label ↦ per-facet values).

    Returns the matplotlib Figure.
    """
    import matplotlib
    import numpy as np
    from matplotlib.figure import Figure

    with matplotlib.rc_context(STYLE):
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
    with matplotlib.rc_context(STYLE):
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
    from ..rounding import format_down

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

    with matplotlib.rc_context(STYLE):
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
