"""The style every figure is drawn with: sizes, fonts, fixed ticks, the legend below the
axes, and the renderer that says where each text ended up."""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:  # matplotlib's own annotations (3.8+); nothing is imported at run time
    from matplotlib.typing import RcKeyType


COLUMN_WIDTH_IN = 3.5
"""One column of a two-column paper, in inches."""
FIGURE_HEIGHT_IN = 2.6
"""Height of every figure, in inches."""
TICKS = 6
"""At most this many intervals between major ticks on each axis (fixed: see fixed_ticks)."""
TICK_STEPS = (1, 2, 5, 10)
"""Tick spacings allowed (times a power of ten): round labels such as 0.002, not 0.0015."""
LEGEND_ROW_IN = 0.16
"""Height added to a figure per legend row, in inches (7-point text and its spacing)."""
LEGEND_CHARS = 52
"""Legend labels are wrapped at this many characters, so a legend fits a column's width."""
STYLE: dict[RcKeyType, object] = {
    "font.size": 8,
    "axes.labelsize": 8,
    "legend.fontsize": 7,
    "lines.linewidth": 1.2,
    "svg.hashsalt": "vorobound",  # fixed SVG ids: the same figure gives the same file
}


def axes_of(ax, legend_rows: int = 0):
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

    return matplotlib.rc_context(STYLE)


def rendered(fig):
    """Draw ``fig`` as it is written (style and layout applied) and return the renderer, whose
    extents (``get_window_extent``) say where each label, legend and line ended up. Query
    them inside :func:`style` too: tick labels are made again from the settings in force."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    with style():
        canvas = FigureCanvasAgg(fig)
        canvas.draw()
    return canvas.get_renderer()


def fixed_ticks(ax) -> None:
    """Tick positions that do not depend on the axes' size. Automatic ones are chosen again
    after the layout has shrunk the axes, and a new last label can then stick out of the
    figure (the clipped last tick of Figure 3)."""
    from matplotlib.ticker import LogLocator, MaxNLocator

    for axis in (ax.xaxis, ax.yaxis):
        if axis.get_scale() == "log":
            axis.set_major_locator(LogLocator(numticks=TICKS))
        else:
            axis.set_major_locator(MaxNLocator(nbins=TICKS, steps=TICK_STEPS))


def _wrapped(label: str, width: int = LEGEND_CHARS) -> str:
    """A legend label on lines of at most ``width`` characters (mathtext kept whole)."""
    import textwrap

    if "$" in label or len(label) <= width:
        return label
    return "\n".join(textwrap.wrap(label, width, break_long_words=False))


def legend_below(ax, handles, columns: int = 1) -> None:
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
