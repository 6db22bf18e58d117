"""``vorobound bounds`` and ``vorobound solve``."""

import json

import pytest
from helpers import assert_one_line_error


def test_bounds_json_lists_every_equation(run_cli):
    code, out, _ = run_cli(
        "bounds", "--eps", "0.0047", "--mode", "paper", "--target", "additive", "--json"
    )
    assert code == 0
    data = json.loads(out)
    assert {"bound", "limit", "target", "quantities", "mode", "premise"} <= data.keys()
    assert data["target"] == "additive" and data["claim"] == "invalid"
    equations = {q["equation"] for q in data["quantities"].values()}
    for label in (
        "(33)",
        "(34)",
        "(35)",
        "(36)",
        "(44)",
        "(45)",
        "(46)",
        "(48)",
        "(49)",
        "(51)",
        "(52)",
    ):
        assert label in equations
    assert data["limit"] == pytest.approx(0.76 * 0.0047)


def test_solve_json_paper_and_rigorous(run_cli):
    values = {}
    for mode in ("paper", "rigorous"):
        code, out, _ = run_cli("solve", "--mode", mode, "--target", "additive", "--json")
        assert code == 0
        values[mode] = json.loads(out)["eps_star"]
    assert round(values["paper"], 4) == 0.0047
    assert values["rigorous"] > values["paper"]


def test_solve_table(run_cli):
    code, out, _ = run_cli("solve")
    assert code == 0 and "ε* / (1/500)" in out


@pytest.mark.parametrize(
    "args",
    [
        ["bounds", "--eps", "2"],
        ["bounds", "--eps", "nan"],
        ["bounds", "--eps", "x"],
        ["bounds"],
        ["bounds", "--eps", "0.01", "--mode", "nope"],
        ["bounds", "--eps", "0.01", "--mode", "rigorous", "--lipschitz", "1"],
        ["bounds", "--eps", "0.01", "--target", "nope"],
        ["solve", "--target", "both"],
        ["solve", "--rho-f", "1"],
        ["solve", "--sigma", "-0.5"],
        ["solve", "--rho-f", "1.000000000001"],
    ],
)
def test_bad_parameters_one_line_exit_2(run_cli, args):
    code, out, err = run_cli(*args)
    assert_one_line_error(code, out, err)
