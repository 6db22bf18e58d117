"""Figures. The only package that imports matplotlib (object-oriented API, no display needed;
matplotlib is imported inside the functions that draw).

- ``style``: sizes, fonts, fixed ticks, the legend below the axes, the renderer
- ``writers``: figures written atomically, one at a time or as a set
- ``paper``: Figure 3, the comparison of both targets by mode, the ratio target
- ``gaps``: the gap histogram of a check, whole or tiled
- ``reconstruct``: M̂'s facet quality and its measurements against ε

Every public name is re-exported here: import them from ``vorobound.plotting``.
"""

from __future__ import annotations

from .gaps import POINT_MASS_WIDTH, TITLE_CHARS, plot_gap_counts, plot_gap_histogram
from .paper import (
    FRACTION_YLIM,
    LEGEND_COLUMNS,
    MODE_STYLE,
    RATIO_SPAN,
    RATIO_YLIM_FACTOR,
    STAR_MARKERS,
    TARGET_LINES,
    TARGET_WORDS,
    plot_comparison,
    plot_figure3,
    plot_ratio,
)
from .reconstruct import (
    TAG_GAP,
    TAG_ROW,
    plot_reconstruct_draws,
    plot_reconstruct_quality,
    plot_reconstruct_sweep,
)
from .style import (
    COLUMN_WIDTH_IN,
    FIGURE_HEIGHT_IN,
    LEGEND_CHARS,
    LEGEND_ROW_IN,
    TICK_STEPS,
    TICKS,
    rendered,
    style,
)
from .writers import DPI, figure_writer, save, save_set

__all__ = [
    "COLUMN_WIDTH_IN",
    "DPI",
    "FIGURE_HEIGHT_IN",
    "FRACTION_YLIM",
    "LEGEND_CHARS",
    "LEGEND_COLUMNS",
    "LEGEND_ROW_IN",
    "MODE_STYLE",
    "POINT_MASS_WIDTH",
    "RATIO_SPAN",
    "RATIO_YLIM_FACTOR",
    "STAR_MARKERS",
    "TAG_GAP",
    "TAG_ROW",
    "TARGET_LINES",
    "TARGET_WORDS",
    "TICKS",
    "TICK_STEPS",
    "TITLE_CHARS",
    "figure_writer",
    "plot_comparison",
    "plot_figure3",
    "plot_gap_counts",
    "plot_gap_histogram",
    "plot_ratio",
    "plot_reconstruct_draws",
    "plot_reconstruct_quality",
    "plot_reconstruct_sweep",
    "rendered",
    "save",
    "save_set",
    "style",
]
