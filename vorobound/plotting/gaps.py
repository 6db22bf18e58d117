"""The gap histogram of a check: realized (R − R̂)/(εL_i) of the guide triangles, whole
(the values) or tiled (counts on fixed bins), each mode's bound marked."""

from __future__ import annotations

from ..reports.figure_data import gap_counts_data, gap_histogram_data
from .style import STYLE, axes_of, fixed_ticks, legend_below

POINT_MASS_WIDTH = 0.012
"""Width of the bar of a point mass in the gap histogram, as a share of the shown range."""


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
    with matplotlib.rc_context(STYLE):
        fig, ax = axes_of(ax, legend_rows=entries + 1)
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
    with matplotlib.rc_context(STYLE):
        rows = len(data.marks) + len(data.off_scale) + (data.note is not None)
        fig, ax = axes_of(ax, legend_rows=rows)
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

    from ..rounding import format_up

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
    fixed_ticks(ax)
    if handles:
        legend_below(ax, handles, columns=1)
    ax.grid(alpha=0.3)
