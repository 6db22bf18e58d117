"""``validate``, ``cheng``, ``figure``/``reproduce`` and the tight mode of ``bounds``/``solve``."""

import json

import pytest


def test_validate_json_names_the_failing_printed_steps(run_cli):
    code, out, _ = run_cli("validate", "--eps", "0.0047", "--samples", "3000", "--json")
    assert code == 0
    data = json.loads(out)
    failing = {k for k, v in data["inequalities"].items() if v["violations"]}
    assert failing == {"(49)", "(52)", "(53)"}
    assert set(data["modes"]) == {"paper", "rigorous", "tight"}
    assert all(ratio <= 1 for ratio in data["modes"].values())


def test_cheng_json(run_cli):
    code, out, _ = run_cli("cheng", "--alpha", "0.3", "--json")
    assert code == 0
    data = json.loads(out)
    assert {"c_rad", "c_conjectured", "numeric_sup", "maximizer"} <= data.keys()
    assert data["numeric_sup"] == pytest.approx(data["c_conjectured"], rel=1e-9)


def test_tight_mode_json_of_bounds_and_solve(run_cli):
    code, out, _ = run_cli(
        "bounds", "--eps", "0.0047", "--mode", "tight", "--target", "additive", "--json"
    )
    assert code == 0
    data = json.loads(out)
    assert data["bound"] == pytest.approx(0.178410 * data["limit"], rel=1e-5)
    assert data["fraction_of_target"] == pytest.approx(0.178410, rel=1e-5)
    assert {"b", "c", "theta", "lfs_j", "lfs_k"} <= data["maximizer"].keys()
    code, out, _ = run_cli("solve", "--mode", "tight", "--target", "additive", "--json")
    assert code == 0
    data = json.loads(out)
    assert data["eps_star"] == pytest.approx(0.0247812, rel=1e-5) and "maximizer" in data


@pytest.mark.parametrize(
    "args",
    [
        ["validate", "--eps", "0"],
        ["validate", "--eps", "0.004", "--samples", "0"],
        ["validate", "--eps", "0.004", "--lipschitz", "-1"],
        ["validate"],
        ["cheng", "--alpha", "0.5"],
        ["cheng", "--alpha", "nan"],
        ["cheng", "--alpha", "0.1", "--dim", "4"],
        ["figure", "--figure-format", "gif", "--no-tight"],
        ["figure", "--rho-f", "0.9", "--no-tight"],
        ["reproduce", "--sigma", "0", "--no-tight"],
        ["solve", "--mode", "tight", "--lipschitz", "-1"],
    ],
)
def test_bad_input_one_line_exit_2(run_cli, args):
    code, out, err = run_cli(*args)
    assert code == 2 and out == ""
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err


def test_figure_into_an_unwritable_place_is_one_line(run_cli, tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    code, _, err = run_cli("figure", "--no-tight", "--out", str(blocker / "sub"))
    assert code == 2 and len(err.strip().splitlines()) == 1
