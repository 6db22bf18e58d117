"""Guide triangles of real samples against the constraint set and the bounds."""

import numpy as np
import pytest

from vorobound.bounds.params import QualityParams, SamplingParams
from vorobound.bounds.tight import tight_supremum
from vorobound.geometry import weighted_triangles
from vorobound.reports.check import check_balls, check_surface
from vorobound.sampling.balls import make_balls
from vorobound.sampling.guides.measure import BOUND_RTOL, mode_bounds
from vorobound.sampling.surfaces.analytic import SphereShape, TorusShape

pytest.importorskip("gudhi")

QUALITY = QualityParams()
RHO_RTOL = 1e-12
"""R/(δL_i) from the report and from a direct circumradius formula agree to this."""


@pytest.fixture(scope="module")
def variable_torus():
    """A sampler sample of a torus whose L varies (min(r, ρ) switches on the inner side)."""
    return check_surface(TorusShape(1.5, 1.0), 0.08, QUALITY, seed=4)


def test_every_guide_triangle_of_a_sampler_sample_is_inside_the_constraint_set(variable_torus):
    g = variable_torus.guides
    assert len(g) > 1000
    assert g.inside.all(), {k: int(v.sum()) for k, v in g.violated.items() if v.any()}
    # The Lipschitz conditions were part of it (λ = 1 for an exact local feature size).
    assert {"lipschitz_ij", "lipschitz_ik", "lipschitz_jk"} <= set(g.violated)


def test_realized_gap_is_below_the_tight_supremum(variable_torus):
    report = variable_torus
    g = report.guides
    assert (g.gap_ratio > 0).any()  # L varies, so the weights do and R − R̂ is not 0
    unit = SamplingParams(report.params.eps, QUALITY.but(target="additive"))
    for lipschitz in (None, 1.0):
        supremum = tight_supremum(unit.but(lipschitz=lipschitz)).supremum
        assert (g.radius_gap <= supremum * g.lfs[:, 0] * (1 + BOUND_RTOL)).all()
    assert not any(rows.any() for rows in g.exceeds.values())


def test_realized_ratio_is_below_the_tight_ratio_supremum(variable_torus):
    """Every guide triangle's R/R̂ (eq. (54)) stays below the tight sup of R/R̂ at its ε,
    with and without λ, and H3's R(1−ε)/(εL_i) stays at most 1 on a sampler sample."""
    from vorobound.bounds.tight.ratio_form import ratio_supremum_closed_form

    report = variable_torus
    g, eps = report.guides, report.params.eps
    assert (g.quality_ratio > 1).any()
    for lipschitz in (None, 1.0):
        sup = ratio_supremum_closed_form(eps, QUALITY.sigma, QUALITY.delta_ratio, lipschitz)
        assert g.quality_ratio.max() <= sup.value * (1 + BOUND_RTOL)
    summary = report.summary()
    assert summary["ratio_max"] == pytest.approx(g.quality_ratio.max())
    assert summary["ratio_bound_violations"] == {"rigorous": 0, "tight": 0, "tight_lipschitz": 0}
    assert 0.5 < summary["h3_ratio_max"] <= 1 and summary["h3_violations"] == 0
    # R/R̂ from the geometry core's own shifted orthoradius.
    p = report.balls.centers[g.triples]
    w = report.balls.radii[g.triples] ** 2
    core = weighted_triangles(p, w)
    assert np.allclose(g.quality_ratio, core.circumradius / core.shifted_orthoradius, rtol=1e-9)
    h3 = core.circumradius * (1 - eps) / (eps * g.lfs[:, 0])
    assert np.allclose(g.h3_ratio, h3, rtol=1e-12)


def test_measurements_follow_their_definitions(variable_torus):
    report, g = variable_torus, variable_torus.guides
    lfs_all = report.lfs
    assert np.array_equal(g.lfs, lfs_all[g.triples])
    assert (g.lfs[:, 0] <= g.lfs[:, 1:].min(axis=1)).all()  # A is the vertex of smallest L
    p = report.balls.centers[g.triples]
    a = np.linalg.norm(p[:, 1] - p[:, 2], axis=1)
    b = np.linalg.norm(p[:, 2] - p[:, 0], axis=1)
    c = np.linalg.norm(p[:, 0] - p[:, 1], axis=1)
    area = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
    circumradius = a * b * c / (4 * area)
    delta = report.params.delta
    assert np.allclose(g.rho, circumradius / (delta * g.lfs[:, 0]), rtol=RHO_RTOL)
    unit = report.params.eps * g.lfs[:, 0]
    assert np.allclose(g.edges, np.column_stack([a, b, c]) / unit[:, None], rtol=RHO_RTOL)
    assert (g.orthoradius_sq < 0).all()  # a guide triangle has seeds


def test_constant_lfs_gives_zero_gap():
    report = check_surface(SphereShape(1.0), 0.12, QUALITY, seed=1)
    assert len(report.guides) > 0
    assert np.abs(report.guides.gap_ratio).max() < 1e-12
    assert report.engine == "hull"


def test_a_triangle_outside_the_constraint_set_is_reported():
    # Three balls far apart relative to their radii around a spot: edges far beyond 2ε/(1−ε)·L.
    eps = 0.05
    params = SamplingParams(eps, QUALITY)
    centers = np.array([[0, 0, 0], [1, 0, 0], [0.5, 0.8, 0], [0.5, 0.3, -3], [0.4, 0.2, 3.0]])
    radii = np.array([0.62, 0.62, 0.62, 0.1, 0.1])
    report = check_balls(make_balls(centers, radii), params.but(lipschitz=1.0))
    s = report.summary()
    assert s["n_guide_triangles"] >= 1
    assert s["outside_constraint_set"] >= 1
    assert s["constraint_violations"]["c_max"] >= 1


def test_mode_bounds_per_unit_lfs():
    params = SamplingParams(0.01, QualityParams(lfs=7.0, lipschitz=1.0))
    bounds = {b.mode: b for b in mode_bounds(params, "additive")}
    assert set(bounds) == {"paper", "rigorous", "tight", "tight_lipschitz"}
    assert bounds["tight_lipschitz"].value <= bounds["tight"].value
    assert bounds["rigorous"].claim == "proven" and bounds["paper"].claim == "invalid"
    reference = tight_supremum(QualityParams(target="additive").at(0.01)).supremum
    assert bounds["tight"].value == pytest.approx(reference, rel=1e-9)


def test_gap_histogram_plots_the_data_and_every_finite_bound():
    from vorobound.plotting import plot_gap_histogram

    gaps = np.array([0.0, 0.01, 0.02, 0.02, 0.1])
    marks = [("paper", float("nan"), "invalid"), ("rigorous", 2.3, "proven"), ("tight", 0.9, "p")]
    fig = plot_gap_histogram(gaps, marks, "test")
    ax = fig.axes[0]
    assert sum(patch.get_height() for patch in ax.patches) == len(gaps)
    lines = [line.get_xdata()[0] for line in ax.get_lines()]
    assert lines == [2.3, 0.9]  # the NaN bound (paper chain undefined) is left out
