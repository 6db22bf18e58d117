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
