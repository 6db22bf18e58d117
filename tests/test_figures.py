"""Figures: the plotted data (not pixels), and the files the commands write."""

import json

import numpy as np
import pytest

from vorobound.bounds.chain import chain_bounds
from vorobound.bounds.params import QualityParams
from vorobound.plotting import plot_comparison, plot_figure3
from vorobound.reports.figure_data import chain_curve, comparison_data, figure3_data

PARAMS = QualityParams().at(0.0047)


def _line(ax, fragment):
    matches = [line for line in ax.get_lines() if fragment in line.get_label()]
    assert matches, f"no line labelled with {fragment!r}"
    return matches[0]


def test_figure3_paper_curve_meets_target_at_solved_eps():
    data = figure3_data(PARAMS.quality)
    ax = plot_figure3(data).axes[0]
    eps, acute = _line(ax, r"\theta \leq").get_xydata().T
    _, target = _line(ax, "target").get_xydata().T
    crossing = np.interp(0.0, (acute - target), eps)  # acute − target increases through 0
    assert crossing == pytest.approx(data.eps_star, rel=1e-3)
    star_line = _line(ax, r"\epsilon^*").get_xdata()
    assert star_line[0] == pytest.approx(data.eps_star, rel=1e-12)
    assert _line(ax, "1/500").get_xdata()[0] == pytest.approx(1 / 500)
    # the plotted bound is the chain's, not a re-derivation
    np.testing.assert_allclose(
        acute, chain_bounds(PARAMS, "paper", eps=eps).bound_acute, rtol=1e-14
    )
    assert len(_line(ax, r"\theta >").get_xydata()) == len(eps)


def test_comparison_has_every_mode_and_the_target():
    curves = [chain_curve(PARAMS.quality, mode) for mode in ("paper", "rigorous")]
    ax = plot_comparison(comparison_data(curves, PARAMS.quality)).axes[0]
    for curve in curves:
        line = _line(ax, f"{curve.mode}:")
        x, y = line.get_xydata().T
        assert np.interp(curve.eps_star, x, y) == pytest.approx(0.76, rel=1e-3)
    assert _line(ax, "target").get_ydata()[0] == pytest.approx(0.76)


def test_plotting_on_a_given_axes_returns_its_figure():
    from matplotlib.figure import Figure

    fig = Figure()
    ax = fig.add_subplot()
    assert plot_figure3(figure3_data(PARAMS.quality), ax=ax) is fig


@pytest.mark.parametrize("fmt", ["png", "pdf", "svg"])
def test_figure_command_writes_each_format(run_cli, tmp_path, fmt):
    code, out, _ = run_cli(
        "figure", "--no-tight", "--out", str(tmp_path), "--figure-format", fmt, "--json"
    )
    assert code == 0
    paths = json.loads(out)["figures"]
    assert {p.rsplit("/", 1)[-1] for p in paths} == {f"figure3.{fmt}", f"comparison.{fmt}"}
    for path in paths:
        assert (tmp_path / path.rsplit("/", 1)[-1]).stat().st_size > 1000


def test_reproduce_table_without_tight(run_cli, tmp_path):
    code, out, _ = run_cli("reproduce", "--no-tight", "--out", str(tmp_path), "--json")
    assert code == 0
    data = json.loads(out)
    assert round(data["eps_star"]["paper"], 4) == 0.0047
    first = data["rows"][0]
    assert first["paper"] == "0.0047" and set(first["values"]) == {"paper", "rigorous"}


# --- layout: measured on the drawn figure (display coordinates), not on pixels ---------------


def _in_view(axis, loc: float) -> bool:
    """Whether matplotlib draws the tick at ``loc`` (it skips ticks outside the view)."""
    low, high, at = axis.get_transform().transform([*axis.get_view_interval(), loc])
    low, high = min(low, high), max(low, high)
    return low - 1e-10 * (high - low) <= at <= high + 1e-10 * (high - low)


def _clipped_tick_labels(fig) -> list[str]:
    """Drawn tick labels that reach outside the figure."""
    from vorobound.plotting import rendered, style

    renderer = rendered(fig)
    bad = []
    with style():  # tick labels are made again from the settings in force
        bounds = fig.bbox
        for ax in fig.axes:
            for axis in (ax.xaxis, ax.yaxis):
                for tick in axis.get_major_ticks():
                    label = tick.label1
                    if not (label.get_visible() and label.get_text()):
                        continue
                    if not _in_view(axis, tick.get_loc()):
                        continue
                    box = label.get_window_extent(renderer)
                    inside = bounds.x0 <= box.x0 and box.x1 <= bounds.x1
                    if not (inside and bounds.y0 <= box.y0 and box.y1 <= bounds.y1):
                        bad.append(label.get_text())
    return bad


def _drawn_points(line, renderer, per_segment: int = 64) -> np.ndarray:
    """Display coordinates along a drawn line (segments sampled), as it is drawn: straight
    segments between the transformed vertices."""
    vertices = line.get_transform().transform(line.get_path().vertices)
    vertices = vertices[np.isfinite(vertices).all(axis=1)]
    if len(vertices) == 1:
        return vertices
    steps = np.linspace(0.0, 1.0, per_segment)[:, None, None]
    return (vertices[:-1] + steps * (vertices[1:] - vertices[:-1])).reshape(-1, 2)


def _legends_over_data(fig) -> list[str]:
    """Artists with drawn data (lines, markers, bars) inside a legend's box, or legends that
    leave the figure."""
    from matplotlib.transforms import Bbox

    from vorobound.plotting import rendered, style

    renderer = rendered(fig)
    found = []
    with style():
        legends = list(fig.legends) + [ax.get_legend() for ax in fig.axes if ax.get_legend()]
        assert legends, "no legend drawn"
        for legend in legends:
            box = legend.get_window_extent(renderer)
            if not fig.bbox.contains(box.x0, box.y0) or not fig.bbox.contains(box.x1, box.y1):
                found.append("legend outside the figure")
            for ax in fig.axes:
                frame = ax.get_window_extent(renderer)
                for line in ax.get_lines():
                    pad = line.get_markersize() * fig.dpi / 72 / 2 + line.get_linewidth()
                    points = _drawn_points(line, renderer)
                    visible = points[
                        (points[:, 0] >= frame.x0) & (points[:, 0] <= frame.x1)
                        & (points[:, 1] >= frame.y0) & (points[:, 1] <= frame.y1)
                    ]  # fmt: skip
                    hit = (
                        (visible[:, 0] > box.x0 - pad) & (visible[:, 0] < box.x1 + pad)
                        & (visible[:, 1] > box.y0 - pad) & (visible[:, 1] < box.y1 + pad)
                    )  # fmt: skip
                    if hit.any():
                        found.append(line.get_label())
                for patch in ax.patches:
                    drawn = Bbox.intersection(patch.get_window_extent(renderer), frame)
                    if drawn is not None and Bbox.intersection(drawn, box) is not None:
                        found.append(f"bar {patch.get_label()}")
    return found


@pytest.fixture(scope="module")
def committed_figures():
    """Figure 3 and the comparison exactly as `vorobound figure` draws them (tight curves
    included)."""
    from vorobound.api.figures import tight_stars
    from vorobound.reports.figure_data import figure_set_data

    figure3, comparison = figure_set_data(PARAMS.quality, tight_stars(PARAMS.quality))
    return plot_figure3(figure3), plot_comparison(comparison)


HISTOGRAM_MARKS = [("paper", 2.34, "invalid"), ("rigorous", 2.34, "proven"), ("tight", 0.935, "p")]


def _histograms():
    from vorobound.plotting import plot_gap_histogram

    spread = np.abs(np.random.default_rng(0).normal(0.0, 0.05, 5000))
    return {
        "point mass at 0": plot_gap_histogram(np.zeros(1000), HISTOGRAM_MARKS, "torus"),
        "spread": plot_gap_histogram(spread, HISTOGRAM_MARKS, "torus"),
        "beyond the marks": plot_gap_histogram(3 + spread, HISTOGRAM_MARKS, "torus"),
    }


def test_committed_figures_keep_tick_labels_and_legends_clear(committed_figures):
    for fig in committed_figures:
        assert _clipped_tick_labels(fig) == []
        assert _legends_over_data(fig) == []


@pytest.mark.parametrize("sigma, rho_f", [(0.75, 1.38), (0.5, 1.1), (1.0, 2.0), (0.75, 5.0)])
def test_tick_labels_are_never_clipped(sigma, rho_f):
    quality = QualityParams(sigma=sigma, rho_f=rho_f)
    curves = [chain_curve(quality, mode) for mode in ("paper", "rigorous")]
    for fig in (
        plot_figure3(figure3_data(quality)),
        plot_comparison(comparison_data(curves, quality)),
    ):
        assert _clipped_tick_labels(fig) == []
        assert _legends_over_data(fig) == []


@pytest.fixture(scope="module")
def histograms():
    return _histograms()


@pytest.mark.parametrize("name", ["point mass at 0", "spread", "beyond the marks"])
def test_histogram_layout(histograms, name):
    fig = histograms[name]
    assert _clipped_tick_labels(fig) == []
    assert _legends_over_data(fig) == []


def test_a_point_mass_is_a_visible_labelled_bar(histograms):
    """Constant L gives R − R̂ = 0 for every triangle: one bar at 0, clear of the frame, as tall
    as the axes allow, and the figure says so."""
    from vorobound.plotting import rendered, style

    fig = histograms["point mass at 0"]
    renderer = rendered(fig)
    with style():
        ax = fig.axes[0]
        frame = ax.get_window_extent(renderer)
        (bar,) = ax.patches
        drawn = bar.get_window_extent(renderer)
        texts = [text.get_text() for legend in fig.legends for text in legend.get_texts()]
    assert texts[0] == "all 1,000 triangles have R − R̂ = 0"
    assert bar.get_height() == 1000 and bar.get_x() < 0 < bar.get_x() + bar.get_width()
    assert drawn.x0 - frame.x0 > 5 and drawn.width >= 2  # not hidden against the axis
    assert drawn.height > 0.8 * frame.height


def test_histogram_data_names_the_point_mass():
    from vorobound.reports.figure_data import gap_histogram_data

    constant = gap_histogram_data(np.full(7, 0.25), HISTOGRAM_MARKS)
    assert constant.bins is None and constant.point_mass == 0.25
    assert constant.note == "all 7 triangles have (R − R̂)/(εL_i) = 0.25"
    narrow = gap_histogram_data(0.25 + np.array([0.0, 1e-9, 2e-9, np.nan]), HISTOGRAM_MARKS)
    assert narrow.bins is None and narrow.count == 4 and len(narrow.values) == 3
    assert narrow.note.startswith("all 3 triangles with a value have (R − R̂)/(εL_i) in [0.25")
    spread = gap_histogram_data(np.linspace(0, 1, 50), HISTOGRAM_MARKS)
    assert spread.point_mass is None and spread.note is None
    assert spread.xlim[0] < 0 and spread.xlim[1] > 2.34  # data and marks clear of the frame
    assert np.histogram(spread.values, spread.bins)[0].sum() == 50
