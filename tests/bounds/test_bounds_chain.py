"""The chain (33)–(53): the paper's number, the corrected chain, the Monte Carlo audit."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vorobound import VoroboundError
from vorobound.bounds.audit import audit_chain, exact_quantities, printed_step_counterexamples
from vorobound.bounds.chain import chain_bounds
from vorobound.bounds.configurations import feasible_mask, sample_feasible
from vorobound.bounds.eps_star import solve_eps_star
from vorobound.bounds.params import QualityParams
from vorobound.errors import InputError

PAPER = QualityParams(target="additive").at(0.0047)
INVALID_PRINTED_STEPS = {"(49)", "(52)", "(53)"}


def test_paper_mode_reproduces_the_published_eps():
    result = solve_eps_star(PAPER.quality, "paper")
    assert round(result.eps_star, 4) == 0.0047  # the paper's figure
    assert result.eps_star > 1 / 500
    chain = chain_bounds(PAPER, "paper", eps=result.eps_star)
    np.testing.assert_allclose(chain.bound, chain.gap_allowance, rtol=1e-12)
    assert abs(result.residual) < 1e-12
    assert result.bracket[0] < result.eps_star < result.bracket[1]


def test_target_is_076_eps_for_the_paper_parameters():
    chain = chain_bounds(PAPER, "paper", eps=np.array([0.001, 0.002]))
    np.testing.assert_allclose(chain.gap_allowance, 0.76 * np.array([0.001, 0.002]), rtol=1e-14)


def test_eps_star_does_not_depend_on_the_feature_size():
    base = solve_eps_star(PAPER.quality, "rigorous").eps_star
    for lfs in (0.01, 30.0):
        other = solve_eps_star(PAPER.quality.but(lfs=lfs), "rigorous").eps_star
        assert other == pytest.approx(base, rel=1e-10)


@settings(max_examples=25, deadline=None)
@given(st.floats(1.05, 3.0), st.floats(0.01, 0.5), st.sampled_from(["paper", "rigorous"]))
def test_eps_star_grows_with_rho_f(rho_f, step, mode):
    low = solve_eps_star(PAPER.quality.but(rho_f=rho_f), mode).eps_star
    high = solve_eps_star(PAPER.quality.but(rho_f=rho_f + step), mode).eps_star
    assert high > low


def test_no_admissible_eps_is_a_clear_error():
    with pytest.raises(VoroboundError, match="no admissible eps"):
        solve_eps_star(PAPER.quality.but(rho_f=1 + 1e-12), "paper")


@pytest.mark.parametrize(
    "kwargs",
    [
        {"eps": 0},
        {"eps": 1},
        {"eps": float("nan")},
        {"eps": 1e-320},
        {"eps": 0.1, "sigma": -1},
        {"eps": 0.1, "sigma": 1e308},
        {"eps": 0.1, "delta_ratio": 0},
        {"eps": 0.1, "delta_ratio": 1e308},
        {"eps": 0.1, "delta_ratio": 1e-300},
        {"eps": 0.1, "lfs": 0},
        {"eps": 0.1, "lfs": 1e-320},
        {"eps": 0.1, "rho_f": 1},
        {"eps": 0.1, "rho_f": 1e308},
        {"eps": "0.1"},
        {"eps": True},
        {"eps": 0.1, "sigma": 1 + 1j},
    ],
)
def test_invalid_parameters_raise_input_errors(kwargs):
    eps = kwargs.pop("eps")
    with pytest.raises(InputError):
        QualityParams(**kwargs).at(eps)


def test_chain_accepts_arrays_of_eps():
    eps = np.geomspace(1e-4, 0.05, 7)
    chain = chain_bounds(PAPER, "rigorous", eps=eps)
    assert chain.bound.shape == (7,)
    single = chain_bounds(QualityParams().at(float(eps[3])), "rigorous")
    assert chain.bound[3] == pytest.approx(float(single.bound), rel=1e-15)


@pytest.mark.parametrize("eps", [0.002, 0.0047, 0.0058, 0.02])
@pytest.mark.parametrize("sigma", [0.5, 0.75, 1.0])
def test_rigorous_chain_is_never_violated(eps, sigma):
    params = QualityParams(sigma=sigma).at(eps)
    tri = sample_feasible(params, 4000, np.random.default_rng(int(eps * 1e4) + int(sigma * 10)))
    assert len(tri) == 4000
    assert feasible_mask(tri, params).all()
    for audit in audit_chain(tri, params, "rigorous"):
        assert audit.violations == 0, audit


def test_paper_chain_fails_exactly_at_the_steps_the_errata_name():
    tri = sample_feasible(PAPER, 8000, np.random.default_rng(0))
    failing = {a.label for a in audit_chain(tri, PAPER, "paper") if a.violations}
    assert failing == INVALID_PRINTED_STEPS


@pytest.mark.parametrize("eps", [0.001, 0.0047, 0.01])
def test_counterexamples_are_feasible_and_violate_their_step(eps):
    params = QualityParams().at(eps)
    found = printed_step_counterexamples(params)
    assert {c.label for c in found} == {"(49)", "(52)"}
    printed = chain_bounds(params, "paper")
    for example in found:
        assert feasible_mask(example.triangle, params).all()
        q = exact_quantities(example.triangle, params)
        if example.label == "(49)":
            assert q.cos[0] < printed.k_cos
        else:
            assert q.sin[0] < printed.sin_min_obtuse and not q.acute[0]


def test_rigorous_bounds_use_the_corrected_cosine():
    chain = chain_bounds(PAPER, "rigorous")
    assert float(chain.k_cos) == pytest.approx(2 * float(chain.k_sin) ** 2 - 1, rel=1e-15)
    example = printed_step_counterexamples(PAPER)[0]
    # The counterexample sits (just inside) the corrected bound: it is sharp.
    assert np.cos(example.triangle.theta[0]) >= float(chain.k_cos)
    assert np.cos(example.triangle.theta[0]) == pytest.approx(float(chain.k_cos), abs=1e-8)
