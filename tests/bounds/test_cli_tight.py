"""The tight mode of ``vorobound bounds`` and ``vorobound solve`` from the command line."""

import pytest
from helpers import assert_one_line_error, json_of


def test_tight_mode_json_of_bounds_and_solve(run_cli):
    data = json_of(
        run_cli("bounds", "--eps", "0.0047", "--mode", "tight", "--target", "additive", "--json")
    )
    assert data["bound"] == pytest.approx(0.178410 * data["limit"], rel=1e-5)
    assert data["fraction_of_target"] == pytest.approx(0.178410, rel=1e-5)
    assert {"b", "c", "theta", "lfs_j", "lfs_k"} <= data["maximizer"].keys()
    data = json_of(run_cli("solve", "--mode", "tight", "--target", "additive", "--json"))
    assert data["eps_star"] == pytest.approx(0.0247812, rel=1e-5) and "maximizer" in data


def test_bad_input_one_line_exit_2(run_cli):
    assert_one_line_error(*run_cli("solve", "--mode", "tight", "--lipschitz", "-1"))
