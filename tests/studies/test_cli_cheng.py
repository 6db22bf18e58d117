"""``vorobound cheng`` from the command line."""

import pytest
from helpers import assert_one_line_error, json_of


def test_cheng_json(run_cli):
    data = json_of(run_cli("cheng", "--alpha", "0.3", "--json"))
    assert {"c_rad", "c_conjectured", "numeric_sup", "maximizer"} <= data.keys()
    assert data["numeric_sup"] == pytest.approx(data["c_conjectured"], rel=1e-9)


@pytest.mark.parametrize(
    "args",
    [
        ["cheng", "--alpha", "0.5"],
        ["cheng", "--alpha", "nan"],
        ["cheng", "--alpha", "0.1", "--dim", "4"],
    ],
)
def test_bad_input_one_line_exit_2(run_cli, args):
    assert_one_line_error(*run_cli(*args))
