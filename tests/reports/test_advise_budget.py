"""What each ε costs and guarantees (issue 32, part 1): the inverse question "which ρ_f at
this ε", the sample budget ``--max-samples``, and the smallest ε ``vorobound sample`` builds
when the recommended one is too fine."""

from __future__ import annotations

import json
import math

import meshio
import pytest
from helpers import assert_one_line_error

import vorobound
from vorobound.bounds.guarantee_at import guarantee_at
from vorobound.bounds.params import QualityParams
from vorobound.bounds.targets import h3_route
from vorobound.reports.advisor import packing_count, printable_eps_up
from vorobound.rounding import format_down
from vorobound.sampling.sampler.cost import smallest_samplable_eps
from vorobound.sampling.sampler.mesh_lattice import expected_candidates
from vorobound.sampling.sampler.slabs import MAX_EXPECTED_CANDIDATES as MAX_CANDIDATES
from vorobound.sampling.surfaces import cad_meshes

QUALITY = QualityParams()
RTOL = 1e-9


def test_the_guarantee_at_each_targets_eps_star_is_its_rho_f():
    """Inverse of solve: at each target's ε*, the proven ρ_f is the ρ_f asked for."""
    ratio_star = vorobound.solve(target="ratio").eps_star
    additive_star = vorobound.solve(target="additive").eps_star
    at_ratio = guarantee_at(ratio_star, QUALITY)
    assert at_ratio.rho_f_ratio <= QUALITY.rho_f
    assert at_ratio.rho_f_ratio == pytest.approx(QUALITY.rho_f, rel=1e-9)
    assert guarantee_at(ratio_star * (1 + 1e-6), QUALITY).rho_f_ratio > QUALITY.rho_f
    at_additive = guarantee_at(additive_star, QUALITY)
    assert at_additive.rho_f_additive == pytest.approx(QUALITY.rho_f, rel=1e-9)
    h3 = h3_route(QUALITY).eps_star
    assert guarantee_at(h3, QUALITY).rho_f_h3 == pytest.approx(QUALITY.rho_f, rel=1e-12)


@pytest.mark.parametrize("eps", [1e-4, 0.003, 0.0094, 0.02, 0.1])
def test_the_guarantee_agrees_with_the_bounds_command(eps):
    """Independent route: `bounds` (tight mode) gives the same sup R/R̂ and sup(R − R̂)."""
    at = guarantee_at(eps, QUALITY)
    ratio = vorobound.bound(eps=eps, target="ratio")
    additive = vorobound.bound(eps=eps, target="additive")
    assert at.rho_f_ratio == pytest.approx(ratio.value, rel=RTOL)
    delta = QUALITY.delta_ratio * eps
    assert at.additive_fraction == pytest.approx(additive.value / delta, rel=RTOL)
    assert at.rho_f_55 <= at.rho_f_h3


def test_the_ratio_has_no_rho_f_once_the_weights_can_reach_the_plateau():
    assert math.isinf(guarantee_at(0.2, QUALITY).rho_f_ratio)


@pytest.mark.parametrize("budget", [1e4, 3e5, 7.5e6])  # 1e4: ε ≈ 0.053, no ρ_f for (54)
def test_the_budget_recommends_the_smallest_eps_within_it(budget):
    result = vorobound.advise(sphere=1.0, max_samples=budget, mode="tight")
    rec = result.advice.recommendation
    assert rec.samples_high <= budget
    surface = result.surface
    # Minimal: the printed ε one step lower in the last printed digit would exceed the budget.
    lower = float(format_down(rec.eps * (1 - 2e-5)))
    assert packing_count(surface, lower, QUALITY.sigma) > budget
    assert float(format_down(rec.eps)) == pytest.approx(rec.eps, rel=1e-15)
    assert rec.rho_f_proven == guarantee_at(rec.eps, QUALITY).rho_f_ratio
    data = result.to_dict()["recommendation"]
    assert data["samples_high"] <= budget and data["claim"] == "proven"
    finite = math.isfinite(rec.rho_f_proven)
    assert data["rho_f_proven"] == (rec.rho_f_proven if finite else None)  # JSON: null for ∞


def test_a_larger_budget_buys_a_better_guarantee():
    rho = [
        vorobound.advise(sphere=1.0, max_samples=n).advice.recommendation.rho_f_proven
        for n in (1e5, 1e6, 1e7)
    ]
    assert rho[0] > rho[1] > rho[2] > 1


def test_printable_eps_up_is_at_or_above_and_prints_as_itself():
    for value in (0.0094976910, 0.1, 1 / 3, 2.5e-7):
        eps = printable_eps_up(value)
        assert eps >= value
        assert float(format_down(eps)) <= eps and format_down(eps) == format_down(eps * 1.0)
        assert eps <= value * (1 + 1e-4)


@pytest.fixture(scope="module")
def cylinder(tmp_path_factory):
    path = tmp_path_factory.mktemp("parts") / "cylinder.stl"
    part = cad_meshes.capped_cylinder(length=100.0, rings=2)
    meshio.write_points_cells(path, part.points, [("triangle", part.triangles)])
    return path


@pytest.fixture(scope="module")
def plate(tmp_path_factory):
    """The CAD plate: its advised ε needs about 3.4e10 plain-lattice candidates, beyond the
    slab sampler's 4e9."""
    path = tmp_path_factory.mktemp("parts") / "plate.stl"
    part = cad_meshes.plate()
    meshio.write_points_cells(path, part.points, [("triangle", part.triangles)])
    return path


def test_an_unsamplable_recommendation_names_the_smallest_eps_and_exits_1(plate, run_cli):
    code, out, _ = run_cli("advise", "--mesh", str(plate), "--json")
    assert code == 1
    rec = json.loads(out)["recommendation"]
    assert rec["samplable"] is False
    back = rec["smallest_samplable"]
    assert back["eps"] > rec["eps"] and back["sampler_cost"]["samplable"] is True
    integral = json.loads(out)["surface"]["inv_lfs_sq_integral"]
    # Smallest: just below it the lattice is too large, at it the lattice fits.
    assert expected_candidates(integral, back["eps"], 0.75, 1.0) <= MAX_CANDIDATES
    assert expected_candidates(integral, back["eps"] * (1 - 1e-4), 0.75, 1.0) > MAX_CANDIDATES
    assert back["rho_f_proven"] == pytest.approx(
        guarantee_at(back["eps"], QUALITY).rho_f_ratio, rel=1e-12
    )
    code, out, _ = run_cli("advise", "--mesh", str(plate))
    assert code == 1
    last = out.strip().splitlines()[-1]
    assert "smallest eps it builds is " + format_down(back["eps"]) in last


def test_the_cylinders_advised_eps_is_samplable_in_slabs(cylinder, run_cli):
    """The issue's cylinder: its advised ε (2.6e8 plain-lattice candidates) is within the slab
    sampler's reach, so `advise` exits 0 with an estimate of one slab's memory."""
    code, out, _ = run_cli("advise", "--mesh", str(cylinder), "--json")
    assert code == 0
    rec = json.loads(out)["recommendation"]
    assert rec["samplable"] is True and rec["smallest_samplable"] is None
    assert 1e8 < rec["lattice_candidates"] < MAX_CANDIDATES
    assert rec["sampler_cost"]["memory_bytes"] < 4e9


def test_sample_names_the_smallest_eps_it_builds(cylinder, run_cli):
    code, out, err = run_cli("sample", "--mesh", str(cylinder), "--eps", "0.002", "-o", "s.npz")
    assert code == 2 and out == ""
    errors = [line for line in err.strip().splitlines() if not line.startswith("warning:")]
    assert len(errors) == 1 and "the smallest eps it builds" in errors[0]
    assert "R <= " in errors[0] and "proven" in errors[0]


def test_a_budget_within_the_samplers_reach_exits_0(cylinder, run_cli):
    code, out, _ = run_cli("advise", "--mesh", str(cylinder), "--max-samples", "2300000", "--json")
    assert code == 0
    rec = json.loads(out)["recommendation"]
    assert rec["samples_high"] <= 2_300_000 and rec["samplable"] is True
    assert rec["rho_f_proven"] > 1.38  # fewer samples than the default advice: weaker


def test_smallest_samplable_eps_refuses_what_no_eps_samples():
    with pytest.raises(vorobound.VoroboundError, match="cannot sample"):
        smallest_samplable_eps(1e20, 0.75, 1.0)


@pytest.mark.parametrize(
    "args",
    [
        ["--sphere", "1", "--max-samples", "1e308"],
        ["--sphere", "1", "--max-samples", "0.5"],
        ["--sphere", "1", "--max-samples", "nan"],
        ["--sphere", "1", "--max-samples", "3"],
        ["--max-samples", "100"],
    ],
)
def test_bad_budgets_are_one_line(run_cli, args):
    code, out, err = run_cli("advise", *args)
    assert_one_line_error(code, out, err)
