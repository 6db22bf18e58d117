"""Random argument lists never make the CLI print a traceback (every command joins here).

Numeric options draw extreme values too: subnormals, the float64 limits, ±2⁶⁴, NaN, infinity.
Every outcome is a result (exit 0) or one line on stderr with exit 2, never a bug (exit 70).
"""

import contextlib
import io
from unittest import mock

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vorobound.cli import main

COMMANDS = ["triangle", "bounds", "solve", "sweep", "advise"]
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
    "--lipschitz",
    "--mode",
    "--format",
    "--jobs",
    "--max-rows",
    "--sphere",
    "--torus",
    "--area",
    "paper",
    "rigorous",
    "tight",
    "csv",
]
EXTREMES = [
    "1e-320",
    "4.9e-324",
    "1e308",
    "-1e308",
    "1.7976931348623157e308",
    str(2**64),
    str(-(2**64)),
    "0",
    "-0",
    "nan",
    "inf",
    "-inf",
    "1e-300",
    "99999999999999999999",
]
VALUES = st.one_of(
    st.sampled_from(
        [
            "0,0",
            "1,0",
            "0,1",
            "1,1,1",
            "inf,0",
            "-1,2,3",
            "",
            ",",
            "1e400,0",
            "3,4,5",
            "1,1,3",
            "0,0,0",
            "a,b",
            "3,1",
            "1e200,1e199",
            "0.3:1.5:3",
            "0:1:0",
            "none,1",
        ]
    ),
    st.sampled_from(EXTREMES),
    st.sampled_from(EXTREMES).map(lambda v: f"{v},{v},{v}"),
    st.text(max_size=8),
    st.floats(allow_nan=True).map(str),
    st.integers(min_value=-(2**70), max_value=2**70).map(str),
)


DEFAULT_EXAMPLES = 40
"""Argument lists tried by the default run (a few seconds on a loaded 2-core machine)."""
SLOW_EXAMPLES = 400
"""Argument lists tried under the slow marker (CI runs it with -m slow)."""
ARGUMENT_LISTS = (
    st.sampled_from(COMMANDS),
    st.lists(st.one_of(st.sampled_from(OPTIONS), VALUES), max_size=8),
)


@settings(max_examples=DEFAULT_EXAMPLES, deadline=None)
@given(*ARGUMENT_LISTS)
def test_no_traceback_escapes(command, args):
    _no_traceback(command, args)


@pytest.mark.slow
@settings(max_examples=SLOW_EXAMPLES, deadline=None)
@given(*ARGUMENT_LISTS)
def test_no_traceback_escapes_in_many_argument_lists(command, args):
    _no_traceback(command, args)


def _no_traceback(command: str, args: list[str]) -> None:
    out_buf, err_buf = io.StringIO(), io.StringIO()
    # The tight optimizer (the fallback where the closed form is not proven exact) takes seconds
    # per call; argument handling is what is fuzzed here, so it answers with the closed form
    # (its own tests cover the optimizer).
    quick_star = mock.patch("vorobound.bounds.tight.method.solve_tight", _quick_eps_star)
    quick_bound = mock.patch("vorobound.bounds.tight.method.tight_supremum", _quick_bound)
    with quick_star, quick_bound, contextlib.redirect_stdout(out_buf):
        with contextlib.redirect_stderr(err_buf):
            code = main([command, *args])
    out, err = out_buf.getvalue(), err_buf.getvalue()
    assert code in (0, 2), err
    assert "Traceback" not in out + err
    if code == 2:
        assert len(err.strip().splitlines()) == 1


def _quick_eps_star(quality, progress=None, **_):
    """The closed form's root standing in for the optimizer's ε* (where the closed form is only
    an upper bound, this is what the optimizer path would be handed back)."""
    from vorobound.bounds.eps_star import EpsStar
    from vorobound.bounds.tight.closed_form import tight_eps_star_closed_form
    from vorobound.bounds.tight.ratio_form import ratio_eps_star_closed_form

    solve = (
        ratio_eps_star_closed_form
        if quality.target.value == "ratio"
        else (tight_eps_star_closed_form)
    )
    found = solve(quality.sigma, quality.delta_ratio, quality.rho_f, quality.lipschitz)
    return EpsStar(
        eps_star=found.eps_star,
        mode="tight",
        quality=quality,
        residual=0.0,
        iterations=0,
        bracket=(found.eps_star, found.eps_star),
        method="optimizer (stub)",
        claim="numerical",
    )


def _quick_bound(params, *_, **__):
    """The closed form's value standing in for the optimizer's supremum."""
    from vorobound.bounds.tight.closed_form import tight_supremum_closed_form
    from vorobound.bounds.tight.ratio_form import ratio_supremum_closed_form
    from vorobound.bounds.tight.scan import TightResult

    closed = tight_supremum_closed_form(
        params.eps, params.sigma, params.delta_ratio, params.lfs, params.lipschitz
    )
    value = closed.value
    if params.target.value == "ratio":
        value = ratio_supremum_closed_form(
            params.eps, params.sigma, params.delta_ratio, params.lipschitz
        ).share
    return TightResult(value, 0.0, closed.maximizer, closed.maximizer, None, None, params)


def test_the_optimizer_stubs_answer_where_the_closed_form_is_only_an_upper_bound(run_cli):
    """The case that once made the stubs recurse: the closed form is an upper bound only, so
    the tight mode falls back to the (stubbed) optimizer, and the command still answers."""
    quick_star = mock.patch("vorobound.bounds.tight.method.solve_tight", _quick_eps_star)
    quick_bound = mock.patch("vorobound.bounds.tight.method.tight_supremum", _quick_bound)
    args = ["--sigma", "0.1", "--delta-ratio", "0.001", "--rho-f", "10", "--json"]
    with quick_star, quick_bound:
        code, out, err = run_cli("solve", *args)
        assert code in (0, 2), err
        bounds = [
            "--eps",
            "0.05",
            "--sigma",
            "1.79",
            "--delta-ratio",
            "0.5",
            "--target",
            "additive",
        ]
        code, out, err = run_cli("bounds", *bounds, "--json")
    assert code == 0, err
    assert '"optimizer"' in out
