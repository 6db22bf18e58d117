"""Figures. The only module that imports matplotlib (object-oriented API, no display needed)."""

from __future__ import annotations

from pathlib import Path

from .files import atomic_path, ensure_folder, write_set
from .reports.figure_data import ComparisonData, Figure3Data

COLUMN_WIDTH_IN = 3.5
"""One column of a two-column paper, in inches."""
FIGURE_HEIGHT_IN = 2.6
"""Height of every figure, in inches."""
DPI = 200
"""Resolution of raster formats."""
COMPARISON_YLIM_FACTOR = 2.5
"""The comparison figure shows bounds up to this multiple of the target."""
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


def _axes(ax):
    from matplotlib.figure import Figure

    if ax is not None:
        return ax.figure, ax
    fig = Figure(figsize=(COLUMN_WIDTH_IN, FIGURE_HEIGHT_IN), layout="constrained")
    return fig, fig.add_subplot()


def plot_figure3(data: Figure3Data, ax=None):
    """Figure 3: the bound on |R − R̂| against ε (L_i = 1), both θ cases, target and markers.

    Returns the matplotlib Figure.

    References
    ----------
    Eq. (46)–(55); Figure 3.
    """
    import matplotlib

    with matplotlib.rc_context(_STYLE):
        fig, ax = _axes(ax)
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
        ax.legend(loc="upper left")
        ax.grid(alpha=0.3)
    return fig


def plot_comparison(data: ComparisonData, ax=None):
    """bound(ε)/ε for every mode, the target (ρ_f − 1)·δ/ε·L_i, and each mode's ε*.

    Returns the matplotlib Figure.
    """
    import matplotlib

    with matplotlib.rc_context(_STYLE):
        fig, ax = _axes(ax)
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
        ax.legend(loc="upper left")
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
    on a log scale (a few extreme triangles stay visible). Returns the matplotlib Figure.

    References
    ----------
    Theorem 1, eq. (29); the bounds of eq. (33)–(53).
    """
    import numpy as np

    gap_ratio = np.asarray(gap_ratio, dtype=float)
    data_max = float(gap_ratio.max()) if len(gap_ratio) else 0.0
    low = min(0.0, float(gap_ratio.min()) if len(gap_ratio) else 0.0)

    def draw(ax, high):
        if len(gap_ratio):
            ax.hist(gap_ratio, bins=np.linspace(low, high * 1.05, 121), color="0.5", log=True)

    return _gap_figure(draw, low, data_max, marks, f"{title}: {len(gap_ratio):,}", ax)


def plot_gap_counts(edges, counts, gap_range, marks, title: str, ax=None):
    """The same histogram from counts on fixed bins (a tiled check's merged histogram).

    ``counts`` has one entry below ``edges[0]``, one per bin, and one at or above
    ``edges[-1]``; ``gap_range`` is (min, max) of the data. Bins are grouped to about 120 bars
    over the range shown; the values below the first edge join the first bar and those above
    the last edge form one bar up to the maximum.
    """
    import numpy as np

    edges, counts = np.asarray(edges, dtype=float), np.asarray(counts, dtype=np.int64)
    data_min, data_max = gap_range
    low = min(0.0, data_min)
    total = int(counts.sum())

    def draw(ax, high):
        if not total:
            return
        shown = min(len(edges) - 1, int(np.searchsorted(edges, high * 1.05)) + 1)
        group = max(1, -(-shown // 120))
        bins = counts[1 : shown + 1]
        bins = np.add.reduceat(bins, np.arange(0, shown, group))
        lefts = edges[0:shown:group]
        rights = np.append(lefts[1:], edges[min(shown, len(edges) - 1)])
        bins[0] += counts[0]
        lefts[0] = min(lefts[0], low)
        rest = int(counts[shown + 1 :].sum())
        if rest:
            lefts, rights = (
                np.append(lefts, rights[-1]),
                np.append(rights, max(data_max, rights[-1])),
            )
            bins = np.append(bins, rest)
        ax.bar(lefts, bins, width=rights - lefts, align="edge", color="0.5", log=True)

    return _gap_figure(draw, low, data_max, marks, f"{title}: {total:,}", ax)


def _gap_figure(draw, low: float, data_max: float, marks, title: str, ax=None):
    """The gap histogram's axes: ``draw(ax, high)`` puts the bars, then the bounds' lines."""
    import math

    import matplotlib

    shown = [(mode, value, claim) for mode, value, claim in marks if math.isfinite(value)]
    with matplotlib.rc_context(_STYLE):
        fig, ax = _axes(ax)
        high = max([data_max, 1e-12, *(value for _, value, _ in shown)])
        draw(ax, high)
        for index, (mode, value, claim) in enumerate(shown):
            label = f"{mode} ({claim}): {value:.3g}"
            style = ("-", "--", "-.", ":")[index % 4]  # equal bounds stay visible
            ax.axvline(value, color=f"C{index}", linewidth=1.2, linestyle=style, label=label)
        ax.set_xlim(low, high * 1.08)
        ax.set_xlabel(r"realized $(R - \hat R)\,/\,(\epsilon L_i)$")
        ax.set_ylabel("guide triangles")
        ax.set_title(f"{title} guide triangles")
        ax.legend(loc="upper right")
        ax.grid(alpha=0.3)
    return fig
