"""Figures: the plotted data (not pixels), and the files the commands write."""

import json

import numpy as np
import pytest

from vorobound.bounds.chain import chain_bounds
from vorobound.bounds.params import QualityParams
from vorobound.plotting import plot_comparison, plot_figure3, plot_ratio
from vorobound.reports.figure_data import figure3_data, target_figure_data

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


@pytest.fixture(scope="module")
def target_data():
    """Both targets' curves as `vorobound figure` draws them (every ε* marked)."""
    from vorobound.api.figures import target_stars

    return target_figure_data(PARAMS.quality, target_stars(PARAMS.quality))


def _plotted(ax, colour, style):
    """The (x, y) of the drawn line with this colour and line style (a mode and a target)."""
    from matplotlib.colors import to_hex

    found = [
        line.get_xydata()
        for line in ax.get_lines()
        if to_hex(line.get_color()) == to_hex(colour) and line.get_linestyle() == style
        and len(line.get_xdata()) > 2
    ]  # fmt: skip
    assert len(found) == 1, (colour, style, len(found))
    return found[0].T


def test_comparison_draws_both_targets_of_every_mode_densely(target_data):
    """Each curve is the mode's bound over its target's allowance (the chains' own arrays, the
    tight closed form on hundreds of ε, not a 7-point polyline), crossing 1 at its ε*, where a
    marker sits."""
    from vorobound.bounds.guarantee import bound_at
    from vorobound.plotting import MODE_STYLE, TARGET_LINES

    ax = plot_comparison(target_data).axes[0]
    assert {(c.mode, c.target) for c in target_data.curves} == {
        (m, t) for m in MODE_STYLE for t in ("additive", "ratio")
    }
    for curve in target_data.curves:
        x, y = _plotted(ax, MODE_STYLE[curve.mode], TARGET_LINES[curve.target])
        assert len(x) >= 500
        np.testing.assert_allclose(y, curve.fraction, rtol=1e-12)
        crossing = np.interp(0.0, np.log(y), np.log(x))  # log y increases through 0
        assert np.exp(crossing) == pytest.approx(curve.eps_star, rel=5e-3)
        marker = [
            line
            for line in ax.get_lines()
            if line.get_label() == f"_{curve.mode} {curve.target} ε*"
        ]
        assert marker[0].get_xydata()[0] == pytest.approx([curve.eps_star, 1.0])
    # the tight curve agrees with the project's bound, evaluated independently per ε
    tight = next(c for c in target_data.curves if c.mode == "tight" and c.target == "ratio")
    for index in (50, 300, 500):
        at = bound_at(PARAMS.quality.at(float(tight.eps[index])), "tight")
        assert tight.fraction[index] == pytest.approx(at.fraction, rel=1e-12)


def test_ratio_figure_marks_rho_f_the_papers_eps_and_every_star(target_data):
    from vorobound.plotting import MODE_STYLE
    from vorobound.rounding import format_down

    ax = plot_ratio(target_data).axes[0]
    labels = [line.get_label() for line in ax.get_lines()]
    for curve in target_data.of_target("ratio"):
        x, y = _plotted(ax, MODE_STYLE[curve.mode], "-")
        finite = np.isfinite(curve.value)
        np.testing.assert_allclose(y[finite], curve.value[finite], rtol=1e-12)
        assert (y[~finite] > ax.get_ylim()[1]).all()  # no bound: the line leaves the top
        assert any(f"ε* = {format_down(curve.eps_star)}" in label for label in labels)
        (star,) = [line for line in ax.get_lines() if line.get_label() == f"_{curve.mode} ε*"]
        assert star.get_xydata()[0] == pytest.approx([curve.eps_star, target_data.rho_f])
        assert ax.get_xlim()[0] < curve.eps_star < ax.get_xlim()[1]
    assert _line(ax, r"\rho_f = 1.38").get_ydata()[0] == pytest.approx(1.38)
    assert _line(ax, "paper's ε = 0.0047").get_xdata()[0] == pytest.approx(0.0047)


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
    assert {p.rsplit("/", 1)[-1] for p in paths} == {
        f"{stem}.{fmt}" for stem in ("figure3", "comparison", "ratio")
    }
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


def _clipped_tick_labels(fig, renderer=None) -> list[str]:
    """Drawn tick labels that reach outside the figure (``renderer``: of a draw of ``fig``
    already made, else it is drawn)."""
    from vorobound.plotting import rendered, style

    renderer = renderer or rendered(fig)
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


def _legends_over_data(fig, renderer=None) -> list[str]:
    """Artists with drawn data (lines, markers, bars) inside a legend's box, or legends that
    leave the figure."""
    from matplotlib.transforms import Bbox

    from vorobound.plotting import rendered, style

    renderer = renderer or rendered(fig)
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
def committed_figures(target_data):
    """Figure 3, the comparison and the ratio figure exactly as `vorobound figure` draws them."""
    return (
        plot_figure3(figure3_data(PARAMS.quality)),
        plot_comparison(target_data),
        plot_ratio(target_data),
    )


def _texts_outside(fig, renderer=None) -> list[str]:
    """Every drawn text (titles, labels, legend entries, tags) that reaches outside the
    figure, measured with the renderer's bounding boxes."""
    from vorobound.plotting import rendered, style

    renderer = renderer or rendered(fig)
    bad = []
    ticks = {  # checked by _clipped_tick_labels, which knows the ones not drawn
        id(label)
        for ax in fig.axes
        for axis in (ax.xaxis, ax.yaxis)
        for tick in axis.get_major_ticks() + axis.get_minor_ticks()
        for label in (tick.label1, tick.label2)
    }
    with style():
        bounds = fig.bbox
        for text in fig.findobj(
            lambda a: hasattr(a, "get_text") and hasattr(a, "get_window_extent")
        ):
            if id(text) in ticks or not (text.get_visible() and text.get_text().strip()):
                continue
            box = text.get_window_extent(renderer)
            inside = bounds.x0 - 0.5 <= box.x0 and box.x1 <= bounds.x1 + 0.5
            if not (inside and bounds.y0 - 0.5 <= box.y0 and box.y1 <= bounds.y1 + 0.5):
                bad.append(text.get_text())
        legends = list(fig.legends) + [ax.get_legend() for ax in fig.axes if ax.get_legend()]
        for legend in legends:
            box = legend.get_window_extent(renderer)
            if not (bounds.x0 <= box.x0 and box.x1 <= bounds.x1):
                bad.append("legend")
    return bad


CLEAR = {"clipped tick labels": [], "legends over data": [], "texts outside the figure": []}
"""What :func:`_layout_faults` finds in a figure laid out well."""


def _layout_faults(fig) -> dict[str, list[str]]:
    """The three layout checks above on one draw of ``fig`` (drawing is the costly part, and
    the checks only read the extents a draw leaves)."""
    from vorobound.plotting import rendered

    renderer = rendered(fig)
    return {
        "clipped tick labels": _clipped_tick_labels(fig, renderer),
        "legends over data": _legends_over_data(fig, renderer),
        "texts outside the figure": _texts_outside(fig, renderer),
    }


HISTOGRAM_MARKS = [("paper", 2.34, "invalid"), ("rigorous", 2.34, "proven"), ("tight", 0.935, "p")]


def _histograms():
    from vorobound.plotting import plot_gap_histogram

    spread = np.abs(np.random.default_rng(0).normal(0.0, 0.05, 5000))
    return {
        "point mass at 0": plot_gap_histogram(np.zeros(1000), HISTOGRAM_MARKS, "torus"),
        "spread": plot_gap_histogram(spread, HISTOGRAM_MARKS, "torus"),
        "beyond the marks": plot_gap_histogram(3 + spread, HISTOGRAM_MARKS, "torus"),
        "near point mass": plot_gap_histogram(1e-6 * spread - 2e-8, HISTOGRAM_MARKS, CAD_TITLE),
    }


CAD_TITLE = "cube.stl (L: estimated, 1-Lipschitz (docs/lfs.md))"
"""The long title a check of an estimated mesh gives its histogram."""


def test_committed_figures_keep_tick_labels_and_legends_clear(committed_figures):
    for fig in committed_figures:
        assert _layout_faults(fig) == CLEAR


@pytest.mark.parametrize("sigma, rho_f", [(0.5, 1.1), (1.0, 2.0), (0.75, 5.0)])
def test_tick_labels_are_never_clipped(sigma, rho_f):
    """Other parameters than the defaults (σ = 0.75, ρ_f = 1.38: the figures `vorobound figure`
    draws, test_committed_figures_keep_tick_labels_and_legends_clear)."""
    from vorobound.api.figures import target_stars

    quality = QualityParams(sigma=sigma, rho_f=rho_f)
    targets = target_figure_data(quality, target_stars(quality))
    for fig in (
        plot_figure3(figure3_data(quality)),
        plot_comparison(targets),
        plot_ratio(targets),
    ):
        assert _layout_faults(fig) == CLEAR


@pytest.fixture(scope="module")
def histograms():
    return _histograms()


@pytest.mark.parametrize(
    "name", ["point mass at 0", "spread", "beyond the marks", "near point mass"]
)
def test_histogram_layout(histograms, name):
    fig = histograms[name]
    assert _layout_faults(fig) == CLEAR


def test_a_near_point_mass_is_drawn_on_its_own_scale(histograms):
    """A CAD part's gaps within 10⁻⁶ of 0 beside bounds near 1: the bars span the data (not one
    bar at 0), the bounds are listed as off the scale (rounded up), and the title says why."""
    from vorobound.rounding import format_up

    ax = histograms["near point mass"].axes[0]
    lefts = [bar.get_x() for bar in ax.patches]
    heights = [bar.get_height() for bar in ax.patches]
    assert sum(heights) == 5000 and sum(h > 0 for h in heights) > 20
    low, high = ax.get_xlim()
    assert low <= min(lefts) and high - low < 1e-5
    assert "point mass beside the bounds" in ax.get_title()
    texts = [t.get_text() for legend in ax.figure.legends for t in legend.get_texts()]
    assert f"tight (p): {format_up(0.935, 3)}, off the scale →" in texts
    assert not any(line.get_xdata()[0] > high for line in ax.get_lines())


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
    assert ax.get_title().replace("\n", " ").endswith("point mass: all 1,000 have R − R̂ = 0")
    assert bar.get_height() == 1000 and bar.get_x() < 0 < bar.get_x() + bar.get_width()
    assert drawn.x0 - frame.x0 > 5 and drawn.width >= 2  # not hidden against the axis
    assert drawn.height > 0.8 * frame.height


def test_histogram_data_names_the_point_mass():
    from vorobound.reports.figure_data import gap_histogram_data

    constant = gap_histogram_data(np.full(7, 0.25), HISTOGRAM_MARKS)
    assert constant.bins is None and constant.point_mass == 0.25
    assert constant.note == "point mass: all 7 have (R − R̂)/(εL_i) = 0.25"
    one = gap_histogram_data(np.array([0.0, np.nan]), HISTOGRAM_MARKS)
    assert one.note == "point mass: the one with a value has R − R̂ = 0"
    narrow = gap_histogram_data(0.25 + np.array([0.0, 1e-9, 2e-9, np.nan]), HISTOGRAM_MARKS)
    assert narrow.zoomed and narrow.count == 4 and len(narrow.values) == 3
    assert narrow.bins[0] == 0.25 and narrow.bins[-1] == 0.25 + 2e-9
    assert narrow.note.endswith("every value in [0.25, 0.250000002]")  # apart, outward
    assert [m[0] for m in narrow.off_scale] == ["paper", "rigorous", "tight"]
    spread = gap_histogram_data(np.linspace(0, 1, 50), HISTOGRAM_MARKS)
    assert spread.point_mass is None and spread.note is None
    assert spread.xlim[0] < 0 and spread.xlim[1] > 2.34  # data and marks clear of the frame
    assert np.histogram(spread.values, spread.bins)[0].sum() == 50


def test_reconstruct_sweep_puts_each_cross_at_its_own_value():
    """A wrong M̂ with a value is crossed at that value; one without a value on the axis; each
    ε* line is numbered, near-coincident ones (0.024781 and 0.02557) on different rows."""
    from vorobound.plotting import plot_reconstruct_sweep, rendered, style

    eps = np.array([0.01, 0.02, 0.04, 0.08])
    values = [0.1, 0.3, None, 0.2]
    correct = [True, False, False, True]
    marks = [("tight", "additive", 0.0247811999), ("tight, λ = 1", "ratio", 0.0255700324)]
    fig = plot_reconstruct_sweep(eps, {"Hausdorff / (εL)": values}, correct, marks, "M̂ of t")
    ax = fig.axes[0]
    crosses = [line for line in ax.get_lines() if line.get_marker() == "x"]
    valued, blank = crosses
    assert valued.get_xydata().tolist() == [[0.02, 0.3]]
    assert blank.get_xdata().tolist() == [0.04] and blank.get_ydata().tolist() == [0.0]
    assert blank.get_transform() == ax.get_xaxis_transform()
    tags = {t.get_text(): t for t in ax.texts}
    assert set(tags) == {"1", "2"} and tags["1"].get_position()[1] != tags["2"].get_position()[1]
    labels = [t.get_text() for legend in fig.legends for t in legend.get_texts()]
    assert labels == ["1  tight, additive: ε* = 0.024781", "2  tight, λ = 1, ratio: ε* = 0.02557"]
    renderer = rendered(fig)
    with style():
        one, two = (tags[k].get_window_extent(renderer) for k in ("1", "2"))
    assert one.y1 <= two.y0 or two.y1 <= one.y0  # readable apart
    assert _texts_outside(fig, renderer) == []
    assert _legends_over_data(fig, renderer) == []


def test_reconstruct_sweep_layout_with_every_mark():
    """Nine ε* lines, three panels and a long surface name (the torus sweep's figure): the
    layout holds (no collapsed axes), the legend leaves the data and the texts stay inside."""
    import warnings

    from vorobound.bounds.params import QualityParams
    from vorobound.plotting import plot_reconstruct_sweep, rendered
    from vorobound.reports.reconstruct_sweep import bound_marks

    marks = [(m.label, m.target, m.eps_star) for m in bound_marks(QualityParams())]
    eps = np.array([0.06, 0.12, 0.18, 0.24])
    panels = {
        "Hausdorff / (εL)": [0.05, 0.09, 0.14, 0.25],
        "max normal dev. (°)": [35.2, 33.3, 35.2, 43.1],
        "min angle (°)": [5e-4, 7e-3, 3e-3, 0.06],
    }
    fig = plot_reconstruct_sweep(eps, panels, [True] * 4, marks, "M̂ of torus R=3, r=1")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # "constrained_layout not applied" is a warning
        renderer = rendered(fig)
    assert _texts_outside(fig, renderer) == []
    assert _legends_over_data(fig, renderer) == []


# --- the tiled check's histogram: counts on fixed bins ----------------------------------------


def _tiled_histograms(tmp_path_factory, monkeypatch_module):
    """The gap histogram of a tiled check of balls on a sphere (constant L) with constant radii
    (R − R̂ = 0 exactly) and with radii spread by 10⁻⁷ (gaps within 10⁻⁶ of 0), as the check
    draws it; with the (min, max) it was given."""
    pytest.importorskip("gudhi")
    import vorobound
    import vorobound.plotting
    from vorobound.sampling.balls import make_balls
    from vorobound.sampling.io.balls import write_balls
    from vorobound.sampling.sampler.maximal import sample_surface
    from vorobound.sampling.surfaces.analytic import SphereShape

    drawn = {}
    plot = vorobound.plotting.plot_gap_counts

    def kept(*args, **kwargs):
        drawn["figure"], drawn["range"] = plot(*args, **kwargs), args[2]
        return drawn["figure"]

    monkeypatch_module.setattr(vorobound.plotting, "plot_gap_counts", kept)
    eps = 0.3
    sample = sample_surface(SphereShape(1.0), eps, 0.75, seed=0)
    found = {}
    for name, spread in (("constant", 0.0), ("tiny spread", 1e-7)):
        folder = tmp_path_factory.mktemp(name.replace(" ", "_"))
        scale = 1 + spread * np.random.default_rng(0).random(len(sample.points))
        write_balls(folder / "b.npz", make_balls(sample.points, 2 * eps * sample.lfs * scale), {})
        result = vorobound.check(balls=folder / "b.npz", eps=eps, workers=1, out=folder / "out")
        assert (folder / "out" / "gap_histogram.png").stat().st_size > 1000
        found[name] = (drawn["figure"], drawn["range"], result.n_guide_triangles)
    return found


@pytest.fixture(scope="module")
def tiled_histograms(tmp_path_factory):
    with pytest.MonkeyPatch.context() as patch:
        yield _tiled_histograms(tmp_path_factory, patch)


def _legend_texts(fig) -> list[str]:
    return [t.get_text() for legend in fig.legends for t in legend.get_texts()]


def test_a_tiled_check_of_constant_radii_shows_one_bar_at_zero(tiled_histograms):
    fig, (low, high), count = tiled_histograms["constant"]
    assert low == high == 0.0 and count > 100
    ax = fig.axes[0]
    (bar,) = ax.patches
    assert bar.get_height() == count and bar.get_x() < 0 < bar.get_x() + bar.get_width()
    assert ax.get_yscale() == "linear" and ax.get_ylim()[1] > count
    title = ax.get_title().replace("\n", " ")
    assert title.endswith(f"point mass: all {count:,} have R − R̂ = 0")
    assert not any("off the scale" in text for text in _legend_texts(fig))  # bounds drawn


def test_a_tiled_check_of_a_tiny_spread_draws_its_range_on_its_own_scale(tiled_histograms):
    """Gaps within 10⁻⁶ of 0 beside bounds above 1: one bar over exactly [min, max] (the counts
    do not say more), the bounds listed as off the scale (rounded up), the title says why."""
    from vorobound.reports.figure_data import TILED_NOTE
    from vorobound.rounding import format_down, format_up

    fig, (low, high), count = tiled_histograms["tiny spread"]
    assert low < high and high - low < 1e-5
    ax = fig.axes[0]
    (bar,) = ax.patches
    assert bar.get_height() == count
    assert bar.get_x() == low and bar.get_x() + bar.get_width() == pytest.approx(high, abs=1e-20)
    xlim = ax.get_xlim()
    assert xlim[0] < low and high < xlim[1] and xlim[1] - xlim[0] < 2 * (high - low)
    title = ax.get_title().replace("\n", " ")
    assert "point mass beside the bounds, drawn on its own scale" in title
    assert TILED_NOTE in title and format_down(low, 3) in title and format_up(high, 3) in title
    off = [text for text in _legend_texts(fig) if text.endswith("off the scale →")]
    assert len(off) == 3 and not ax.get_lines()  # every finite bound beyond the data


@pytest.mark.parametrize("name", ["constant", "tiny spread"])
def test_tiled_histogram_layout(tiled_histograms, name):
    fig = tiled_histograms[name][0]
    assert _layout_faults(fig) == CLEAR


def _counted(values, edges):
    """A tally's counts of ``values`` on ``edges``: below, per bin, at or above."""
    inside = np.histogram(values, edges)[0]
    inside[-1] -= int((values == edges[-1]).sum())  # the last bin is half-open in a tally
    below, above = int((values < edges[0]).sum()), int((values >= edges[-1]).sum())
    return np.concatenate([[below], inside, [above]])


def test_tiled_counts_of_a_spread_are_grouped_bars_on_the_bounds_scale():
    from vorobound.plotting import plot_gap_counts
    from vorobound.reports.figure_data import gap_counts_data

    edges = np.linspace(0.0, 1.05 * 2.34, 1201)
    values = np.concatenate(
        [np.abs(np.random.default_rng(0).normal(0.0, 0.05, 5000)), [-0.01, 3.0]]
    )
    counts = _counted(values, edges)
    span = (float(values.min()), float(values.max()))
    data = gap_counts_data(edges, counts, span, HISTOGRAM_MARKS)
    assert data.note is None and data.point_mass is None and data.log
    assert data.total == len(values) == data.heights.sum() and data.off_scale == ()
    assert [m[0] for m in data.marks] == ["paper", "rigorous", "tight"]
    assert data.lefts[0] == -0.01 and data.rights[-1] == 3.0 and data.heights[-1] == 1
    assert 100 <= len(data.heights) <= 122
    middle = slice(1, -1)  # each bar counts the values inside it
    for left, right, height in zip(
        data.lefts[middle], data.rights[middle], data.heights[middle], strict=True
    ):
        assert height == ((values >= left) & (values < right)).sum()
    assert data.xlim[0] < -0.01 and data.xlim[1] > 3.0
    fig = plot_gap_counts(edges, counts, span, HISTOGRAM_MARKS, "torus")
    ax = fig.axes[0]
    assert ax.get_yscale() == "log" and len(ax.patches) == len(data.heights)
    assert [bar.get_height() for bar in ax.patches] == data.heights.tolist()
    assert "\n" not in ax.get_title() and len(ax.get_lines()) == 3
    assert _layout_faults(fig) == CLEAR


def test_tiled_counts_in_one_bar_are_a_point_mass():
    """Values within one bar (below the first edge and in the first bin): the range they
    span, not the bar's; nothing counted: no bar, no note."""
    from vorobound.reports.figure_data import gap_counts_data

    edges = np.linspace(0.0, 2.5, 1201)
    values = np.array([-1e-9, 0.0, 1e-3])  # wider than 10⁻⁶, within one bar of 2.5/120
    data = gap_counts_data(edges, _counted(values, edges), (-1e-9, 1e-3), HISTOGRAM_MARKS)
    assert data.lefts.tolist() == [-1e-9] and data.rights.tolist() == [1e-3]
    assert data.heights.tolist() == [3] and not data.log
    assert data.note.startswith("a point mass beside the bounds") and len(data.off_scale) == 3
    none = gap_counts_data(edges, np.zeros(1202, dtype=int), (None, 0.0), HISTOGRAM_MARKS)
    assert none.total == 0 and len(none.heights) == 0 and none.note is None
