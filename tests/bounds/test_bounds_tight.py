"""The tight bound: the exact supremum of R − R̂ over feasible guide triangles, and its ε*."""

import subprocess
import sys

import numpy as np
import pytest

from vorobound import VoroboundError
from vorobound.bounds.chain import chain_bounds
from vorobound.bounds.configurations import GuideTriangles, feasible_mask, sample_feasible
from vorobound.bounds.eps_star import solve_eps_star
from vorobound.bounds.params import QualityParams, SamplingParams
from vorobound.bounds.tight import solve_tight, tight_supremum

PAPER = QualityParams(target="additive").at(0.0047)
BUDGET = {"dense_samples": 3000, "de_maxiter": 60}
"""Small search budgets: the optimum is found from every start anyway (see the evidence)."""
SAMPLE_RTOL = 1e-9
"""No sampled triangle may beat the supremum by more than this (feasibility slack ~1e-12)."""
VERTEX_RTOL = 1e-9
EPS_STAR_RTOL = 1e-6
RIGOROUS_EPS_STAR = 0.0058164  # vorobound solve --mode rigorous, paper parameters


def _vertex(params: SamplingParams, lipschitz: float | None) -> GuideTriangles:
    """The maximizer in closed form: b = c = σεL_i, R = ε/(1−ε)L_i, L_j = L_k maximal."""
    eps, sigma, lfs = params.eps, params.sigma, params.lfs
    excess = 2 * eps / (1 - eps)  # L_max/L_i − 1, eq. (33)
    if lipschitz is not None:
        excess = min(excess, lipschitz * sigma * eps)
    theta = 2 * np.arccos(sigma * (1 - eps) / 2)
    return GuideTriangles.of(sigma * eps * lfs, sigma * eps * lfs, theta, excess, excess)


def _as_triangle(config) -> GuideTriangles:
    return config.triangles()


@pytest.fixture(scope="module")
def paper_tight():
    return {lam: tight_supremum(PAPER.but(lipschitz=lam), **BUDGET) for lam in (None, 1.0)}


@pytest.fixture(scope="module")
def eps_stars():
    return {lam: solve_tight(PAPER.quality.but(lipschitz=lam), **BUDGET) for lam in (None, 1.0)}


@pytest.mark.parametrize("lam", [None, 1.0])
def test_supremum_dominates_a_dense_feasible_sample(paper_tight, lam):
    result = paper_tight[lam]
    tri = sample_feasible(PAPER.but(lipschitz=lam), 5000, np.random.default_rng(7))
    delta = tri.radius_gap(PAPER)
    assert len(tri) == 5000
    assert delta.max() <= result.supremum * (1 + SAMPLE_RTOL)
    assert delta.min() >= result.infimum * (1 + SAMPLE_RTOL)
    for config in (result.maximizer, result.minimizer):
        assert feasible_mask(_as_triangle(config), PAPER.but(lipschitz=lam)).all()
    maximizer = _as_triangle(result.maximizer)
    assert maximizer.radius_gap(PAPER)[0] == pytest.approx(result.supremum, rel=1e-14)
    for config in (result.maximizer, result.minimizer):
        assert config.lfs_j <= config.lfs_k


@pytest.mark.parametrize("lam", [None, 1.0])
def test_supremum_is_the_closed_form_vertex(paper_tight, lam):
    vertex = _vertex(PAPER, lam)
    assert feasible_mask(vertex, PAPER.but(lipschitz=lam)).all()
    expected = vertex.radius_gap(PAPER)[0]
    result = paper_tight[lam]
    assert expected * (1 - 1e-15) <= result.supremum <= expected * (1 + VERTEX_RTOL)
    assert result.maximizer.b == pytest.approx(PAPER.sigma * PAPER.eps, rel=1e-12)
    assert "R = ε/(1−ε)·L_i (H3)" in result.evidence.active_constraints


def test_evidence_shows_agreement_and_is_json_ready(paper_tight):
    import json
    from dataclasses import asdict

    evidence = paper_tight[None].evidence
    assert evidence.agreeing_starts >= evidence.starts - 1
    assert evidence.spread_of_local_optima < SAMPLE_RTOL
    assert evidence.dense_sample_extreme <= paper_tight[None].supremum
    assert paper_tight[None].infimum_evidence.dense_sample_extreme >= paper_tight[None].infimum
    json.dumps(asdict(evidence))
    assert paper_tight[None].supremum / PAPER.gap_allowance == pytest.approx(0.17841021, rel=1e-7)


def test_infimum_below_supremum_and_lipschitz_only_lowers_it(paper_tight):
    plain, lipschitz = paper_tight[None], paper_tight[1.0]
    for result in (plain, lipschitz):
        assert result.infimum < 0 < result.supremum
    assert lipschitz.supremum <= plain.supremum
    assert lipschitz.infimum >= plain.infimum


# Two searches per ε (about 0.9 CPU-s): both ends and the paper's ε by default, the two between
# with the slow marker.
@pytest.mark.parametrize(
    "eps",
    [1e-4, pytest.param(0.002, marks=pytest.mark.slow), 0.0047]
    + [pytest.param(0.02, marks=pytest.mark.slow), 0.05],
)
def test_tight_never_exceeds_the_rigorous_chain(eps):
    params = QualityParams(target="additive").at(eps)
    rigorous = float(chain_bounds(params, "rigorous").bound)
    plain = tight_supremum(params, **BUDGET).supremum
    lipschitz = tight_supremum(params.but(lipschitz=1.0), **BUDGET).supremum
    assert lipschitz <= plain * (1 + SAMPLE_RTOL) <= rigorous


def test_large_eps_reaches_the_trivial_bound_with_zero_orthoradius():
    params = QualityParams(target="additive").at(0.1)
    result = tight_supremum(params, **BUDGET)
    r_max = params.eps / (1 - params.eps) * params.lfs
    assert result.supremum == pytest.approx(r_max, rel=1e-12)
    assert "R̂ = 0 (w_B = c², w_C = b²)" in result.evidence.active_constraints
    assert feasible_mask(_as_triangle(result.maximizer), params).all()


def test_deterministic_for_a_seed_and_scale_free():
    lam_one = PAPER.but(lipschitz=1.0)
    first = tight_supremum(lam_one, seed=3, **BUDGET)
    assert tight_supremum(lam_one, seed=3, **BUDGET) == first
    scaled = tight_supremum(lam_one.but(lfs=30.0), seed=3, **BUDGET)
    assert scaled.supremum == pytest.approx(30 * first.supremum, rel=1e-12)


def test_solve_tight_meets_the_target_at_eps_star(eps_stars):
    for lam, result in eps_stars.items():
        assert result.mode == "tight"
        assert result.bracket[0] < result.eps_star < result.bracket[1]
        assert abs(result.residual) < EPS_STAR_RTOL
        assert result.lipschitz == lam
        check = tight_supremum(result.params, seed=1, **BUDGET)
        assert check.supremum == pytest.approx(result.params.gap_allowance, rel=EPS_STAR_RTOL)
        assert feasible_mask(_as_triangle(result.maximizer), result.params).all()


def test_tight_eps_star_beats_the_rigorous_one(eps_stars):
    rigorous = solve_eps_star(PAPER.quality, "rigorous").eps_star
    assert rigorous == pytest.approx(RIGOROUS_EPS_STAR, rel=1e-4)
    assert eps_stars[None].eps_star > 4 * rigorous
    assert eps_stars[1.0].eps_star >= eps_stars[None].eps_star
    assert eps_stars[None].eps_star == pytest.approx(0.0247812, rel=1e-5)
    assert eps_stars[1.0].eps_star == pytest.approx(0.0650307, rel=1e-5)


def test_solve_tight_is_quiet_without_progress(capsys):
    grid = np.geomspace(0.005, 0.05, 6)
    result = solve_tight(PAPER.quality, grid=grid, **BUDGET)
    captured = capsys.readouterr()
    assert captured.out == captured.err == ""
    assert result.eps_star == pytest.approx(0.0247812, rel=1e-5)


@pytest.mark.parametrize("lam", [-1.0, float("nan"), float("inf")])
def test_bad_lipschitz_is_a_clear_error(lam):
    with pytest.raises(VoroboundError, match="lipschitz"):
        PAPER.but(lipschitz=lam)
    with pytest.raises(VoroboundError, match="lipschitz"):
        QualityParams(lipschitz=lam)


def test_impossible_inputs_raise_voroboundError():
    with pytest.raises(VoroboundError, match="no crossing"):
        solve_tight(PAPER.quality.but(lipschitz=0.0), grid=np.geomspace(1e-3, 0.5, 5), **BUDGET)
    with pytest.raises(VoroboundError, match="no feasible guide triangle"):
        tight_supremum(QualityParams(sigma=2.5).at(0.1))


def test_importing_the_module_does_not_import_scipy():
    probe = "import sys, vorobound.bounds.tight; print('scipy' in sys.modules)"
    done = subprocess.run(
        [sys.executable, "-c", probe], capture_output=True, text=True, check=False
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "False"
