"""Paths of the command line that other tests do not reach: the human tables of every command,
tight sweeps on worker processes, tight figures and reproduction, and ``main``'s exit codes."""

import json

import pytest

from vorobound.cli import EXIT_INTERRUPTED, main

TABLE_CASES = [
    (["triangle", "--edges", "3,4,5", "-w", "0,0.2,0.5"], "R − R̂ (Theorem 1)"),
    (
        ["bounds", "--eps", "0.0047", "--mode", "paper", "--target", "additive"],
        "exceeds the target (ρ_f − 1)·δ·L_i",
    ),
    (["bounds", "--eps", "0.0047"], "closed form, proven"),
    (["bounds", "--eps", "0.0047"], "meets the target ρ_f = 1.38"),
    (["solve", "--mode", "rigorous"], "ε* / (1/500)"),
    (["solve", "--mode", "tight", "--lipschitz", "1"], "closed form"),
    (["validate", "--eps", "0.0047", "--samples", "500", "--no-tight"], "holds"),
    (["sweep", "--rho-f", "1.3,1.4"], "vorobound sweep"),
    (["advise", "--sphere", "1", "--mode", "rigorous"], "What ε ≤ ε* gives"),
    (["cheng", "--alpha", "0"], "c_rad"),
]


@pytest.mark.parametrize("args, expected", TABLE_CASES, ids=lambda v: str(v)[:30])
def test_every_command_prints_a_table_for_people(run_cli, args, expected):
    code, out, err = run_cli(*args)
    assert code == 0, err
    assert expected in " ".join(out.split())  # footers are wrapped to the terminal


@pytest.mark.slow
def test_tight_sweep_on_two_processes_matches_the_closed_form(run_cli):
    """Optimizer rows computed by two worker processes come back in order and agree with the
    closed form (computed in this process)."""
    args = ["sweep", "--mode", "tight", "--sigma", "0.75", "--lipschitz", "none,1", "--json"]
    code, out, _ = run_cli(*args, "--method", "optimize", "--jobs", "2")
    assert code == 0
    rows = json.loads(out)["rows"]
    keys = [(r["target"], r["lipschitz"], r["claim"]) for r in rows]
    assert keys == [
        (target, lam, "numerical") for target in ("additive", "ratio") for lam in (None, 1.0)
    ]
    closed = {
        (r["target"], r["lipschitz"]): r["eps_star"] for r in _closed_form_rows(run_cli, args)
    }
    for row in rows:
        assert row["eps_star"] == pytest.approx(closed[row["target"], row["lipschitz"]], rel=1e-6)


def _closed_form_rows(run_cli, args):
    code, out, _ = run_cli(*args)
    assert code == 0
    rows = json.loads(out)["rows"]
    assert {r["claim"] for r in rows} == {"proven"}
    return rows


@pytest.mark.slow
def test_tight_figures_and_reproduction(run_cli, tmp_path):
    """Slow (the tight modes and six figures); by default `reproduce --out` with the tight
    modes runs in test_printed_numbers.py::test_command_tables_round_toward_safety[args0] and
    `figure --figure-format svg` in test_figures.py::test_figure_command_writes_each_format."""
    code, out, _ = run_cli("reproduce", "--out", str(tmp_path), "--json")
    assert code == 0
    data = json.loads(out)
    assert data["claims"] == {
        "paper": "invalid",
        "rigorous": "proven",
        "tight": "proven",
        "tight λ=1": "proven",
    }
    rows = {r["quantity"]: r["values"] for r in data["rows"]}
    additive = rows["ε covered by an interval certificate, additive target"]
    ratio = rows["ε covered by an interval certificate, ratio target"]
    for mode in ("tight", "tight λ=1"):
        assert 0.999 * data["eps_star"][mode] == pytest.approx(additive[mode], rel=1e-12)
        assert 0.999 * data["eps_star_ratio"][mode] == pytest.approx(ratio[mode], rel=1e-12)
        assert data["eps_star_ratio"][mode] < data["eps_star"][mode]
    h3 = rows["ε up to which H3 alone gives (55), any mode"]
    assert list(h3.values()) == [pytest.approx(1 - 1 / (2 * 1.38))] * len(h3)
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "comparison.png",
        "figure3.png",
        "ratio.png",
    ]
    code, out, _ = run_cli(
        "figure", "--out", str(tmp_path / "svg"), "--figure-format", "svg", "--json"
    )
    assert code == 0 and len(json.loads(out)["figures"]) == 3


def test_main_exit_codes(capsys, monkeypatch):
    assert main([]) == 0  # no arguments: the help
    assert "Usage" in capsys.readouterr().out
    assert main(["--help"]) == 0
    assert main(["nonsense"]) == 2
    assert "No such command" in capsys.readouterr().err

    import typer

    import vorobound.bounds.chain as chain
    import vorobound.cli as cli

    for raised, code, message in (
        (cli.Interrupted(), EXIT_INTERRUPTED, "interrupted"),
        (typer.Abort(), EXIT_INTERRUPTED, "interrupted"),
        (typer.Exit(3), 3, ""),
    ):

        def stop(*args, raised=raised, **kwargs):
            raise raised

        monkeypatch.setattr(chain, "chain_bounds", stop)
        assert main(["bounds", "--eps", "0.01", "--mode", "rigorous"]) == code
        assert capsys.readouterr().err.strip() == message
