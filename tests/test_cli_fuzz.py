"""Random argument lists never make the CLI print a traceback (every command joins here)."""

import contextlib
import io
from unittest import mock

from hypothesis import given, settings
from hypothesis import strategies as st

from vorobound.cli import main

COMMANDS = ["triangle", "bounds", "solve", "sweep", "advise", "cheng"]
OPTIONS = [
    "-p",
    "--edges",
    "-w",
    "--weights",
    "--json",
    "--help",
    "--bogus",
    "--eps",
    "--sigma",
    "--rho-f",
    "--delta-ratio",
    "--lfs",
    "--mode",
    "paper",
    "rigorous",
]
VALUES = st.one_of(
    st.sampled_from(
        [
            "0,0",
            "1,0",
            "0,1",
            "1,1,1",
            "nan",
            "inf,0",
            "-1,2,3",
            "",
            ",",
            "1e400,0",
            "3,4,5",
            "1,1,3",
            "0,0,0",
            "a,b",
        ]
    ),
    st.text(max_size=8),
    st.floats(allow_nan=True).map(str),
)


@settings(max_examples=300, deadline=None)
@given(st.sampled_from(COMMANDS), st.lists(st.one_of(st.sampled_from(OPTIONS), VALUES), max_size=8))
def test_no_traceback_escapes(command, args):
    out_buf, err_buf = io.StringIO(), io.StringIO()
    # The tight optimizer takes seconds per call; argument handling is what is fuzzed here, so
    # it answers with the rigorous chain's ε* (its own tests cover the optimizer).
    quick = mock.patch("vorobound.bounds.tight.solve_tight", _quick_solve_tight)
    with quick, contextlib.redirect_stdout(out_buf), contextlib.redirect_stderr(err_buf):
        code = main([command, *args])
    out, err = out_buf.getvalue(), err_buf.getvalue()
    assert code in (0, 2)
    assert "Traceback" not in out + err
    if code == 2:
        assert len(err.strip().splitlines()) == 1


def _quick_solve_tight(params, lipschitz=None, progress=False, **_):
    from vorobound.bounds.eps_star import solve_eps_star

    return solve_eps_star(params, "rigorous")
