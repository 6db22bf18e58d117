"""ε* solvers: success means a root (residual ≈ 0), and ε* moves the right way with ρ_f and λ."""

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vorobound.bounds.eps_star import (
    STATUS_EMPTY,
    STATUS_EXCEEDS_AT_START,
    STATUS_NO_CROSSING,
    STATUS_OK,
    solve_eps_star,
    solve_eps_star_batch,
)
from vorobound.bounds.params import QualityParams
from vorobound.bounds.tight import tight_supremum
from vorobound.errors import NoAdmissibleEps, NoCrossing

RESIDUAL_TOL = 1e-9
"""bound/target − 1 at a reported ε*. The root finders stop at a few float spacings of ε; near
the end of the printed chain's domain the bound rises like 1/sqrt(edge − ε), where one spacing
moves the ratio by ~1e-12. A discontinuity (the old failure) leaves a residual of order 1."""
BATCH_RTOL = 1e-12
"""The batched solver and brentq agree to this (both converge to the same crossing)."""
LAMBDA_RTOL = 1e-9
"""sup(R − R̂)/λ may not decrease as λ shrinks by more than the optimizer's tolerance."""


@settings(max_examples=40, deadline=None)
@given(
    st.floats(0.2, 1.73),
    st.floats(0.2, 4.0),
    st.floats(1.001, 50.0),
    st.sampled_from(["paper", "rigorous"]),
)
def test_success_means_a_root(sigma, ratio, rho_f, mode):
    quality = QualityParams(sigma=sigma, delta_ratio=ratio, rho_f=rho_f)
    try:
        result = solve_eps_star(quality, mode)
    except NoCrossing:
        return
    assert abs(result.residual) < RESIDUAL_TOL
    assert result.bracket[0] <= result.eps_star <= result.bracket[1]


def test_batch_solver_matches_brentq_row_by_row():
    rng = np.random.default_rng(5)
    sigma, ratio, rho_f = (
        rng.uniform(0.2, 1.9, 60),
        rng.uniform(0.5, 3, 60),
        rng.uniform(1.01, 5, 60),
    )
    codes = set()
    for mode, target in itertools.product(("paper", "rigorous"), ("additive", "ratio")):
        stars, status = solve_eps_star_batch(sigma, ratio, rho_f, mode, target=target)
        for s, r, q, star, code in zip(sigma, ratio, rho_f, stars, status, strict=True):
            quality = QualityParams(sigma=s, delta_ratio=r, rho_f=q, target=target)
            codes.add(int(code))
            if code == STATUS_OK:
                expected = solve_eps_star(quality, mode).eps_star
                assert star == pytest.approx(expected, rel=BATCH_RTOL)
                if s > np.sqrt(3):  # the constraint set is empty below 1 − √3/σ
                    assert star > 1 - np.sqrt(3) / s
            elif code == STATUS_EMPTY:
                with pytest.raises(NoAdmissibleEps):
                    solve_eps_star(quality, mode)
            elif code == STATUS_EXCEEDS_AT_START:
                with pytest.raises(NoAdmissibleEps, match="already") as caught:
                    solve_eps_star(quality, mode)
                assert not isinstance(caught.value, NoCrossing)
            else:
                assert code == STATUS_NO_CROSSING
                with pytest.raises(NoCrossing):
                    solve_eps_star(quality, mode)
    assert {STATUS_OK, STATUS_EXCEEDS_AT_START} <= codes


def test_eps_star_is_monotone_in_rho_f():
    """ε* never decreases as ρ_f grows, and every row has a root. The printed chain's ε*
    levels off below 0.19276, where its eq. (52) divides by sqrt(1 − k_cos²) → 0: there the
    bound rises to infinity, so a larger ρ_f moves the root by less than a float spacing."""
    rho_f = np.geomspace(1.001, 1e4, 400)
    for mode in ("paper", "rigorous"):
        stars, status = solve_eps_star_batch(0.75, 2.0, rho_f, mode)
        assert (status == STATUS_OK).all()
        steps = np.diff(stars)
        assert np.all(steps >= -4 * np.spacing(stars[1:]))
        if mode == "rigorous":
            assert np.all(steps > 0)
        else:
            assert stars.max() < 0.1927639


# Six searches per ε (about 2 CPU-s): the paper's ε by default, 0.02 with the slow marker.
@pytest.mark.parametrize("eps", [0.0047, pytest.param(0.02, marks=pytest.mark.slow)])
def test_tight_supremum_is_monotone_in_lambda_down_to_tiny_values(eps):
    """sup is nondecreasing in λ, and sup/λ tends to a constant as λ → 0 (no collapse)."""
    params = QualityParams(target="additive").at(eps)
    lambdas = [1e-9, 1e-7, 1e-5, 1e-3, 1e-1, 1.0]
    sups = [
        tight_supremum(params.but(lipschitz=lam), dense_samples=2000, de_maxiter=40).supremum
        for lam in lambdas
    ]
    assert all(a <= b * (1 + LAMBDA_RTOL) for a, b in zip(sups, sups[1:], strict=False))
    per_lambda = np.array(sups[:3]) / np.array(lambdas[:3])
    assert per_lambda.min() == pytest.approx(per_lambda.max(), rel=1e-3)
