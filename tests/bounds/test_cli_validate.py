"""``vorobound validate``: the Monte Carlo audit of the printed chain from the command line."""

import pytest
from helpers import assert_one_line_error, json_of


def test_validate_json_names_the_failing_printed_steps(run_cli):
    data = json_of(run_cli("validate", "--eps", "0.0047", "--samples", "3000", "--json"))
    failing = {k for k, v in data["inequalities"].items() if v["violations"]}
    assert failing == {"(49)", "(52)", "(53)"}
    assert set(data["modes"]) == {"paper", "rigorous", "tight"}
    assert all(ratio <= 1 for ratio in data["modes"].values())


@pytest.mark.parametrize(
    "args",
    [
        ["validate", "--eps", "0"],
        ["validate", "--eps", "0.004", "--samples", "0"],
        ["validate", "--eps", "0.004", "--lipschitz", "-1"],
        ["validate"],
    ],
)
def test_bad_input_one_line_exit_2(run_cli, args):
    assert_one_line_error(*run_cli(*args))
