"""``vorobound figure`` and ``vorobound reproduce``: bad input and unwritable places."""

import pytest
from helpers import assert_one_line_error


@pytest.mark.parametrize(
    "args",
    [
        ["figure", "--figure-format", "gif", "--no-tight"],
        ["figure", "--rho-f", "0.9", "--no-tight"],
        ["reproduce", "--sigma", "0", "--no-tight"],
    ],
)
def test_bad_input_one_line_exit_2(run_cli, args):
    assert_one_line_error(*run_cli(*args))


def test_figure_into_an_unwritable_place_is_one_line(run_cli, tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    code, _, err = run_cli("figure", "--no-tight", "--out", str(blocker / "sub"))
    assert_one_line_error(code, None, err)
