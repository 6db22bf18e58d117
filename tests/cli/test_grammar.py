"""One grammar for the command line and the Python API (issue 24): --version and -h, words as
metavars, outputs named by suffix, exit codes, tables that keep every digit, results that
print short and hold plain floats."""

import json
import re

import pytest

import vorobound
from vorobound.cli import app

COMMANDS = sorted(c.name for c in app.registered_commands)


def test_version_and_short_help(run_cli):
    code, out, _ = run_cli("--version")
    assert code == 0 and out.strip() == f"vorobound {vorobound.__version__}"
    code, out, _ = run_cli("-h")
    assert code == 0 and "Usage" in out
    for command in COMMANDS:
        code, out, _ = run_cli(command, "-h")
        assert code == 0 and "Usage" in out, command


@pytest.mark.parametrize("command", COMMANDS)
def test_options_show_words_not_types(run_cli, command):
    """Every option's placeholder reads as a word (EPS, FILE, R,r) or is absent for a flag."""
    code, out, _ = run_cli(command, "--help")
    assert code == 0
    lines = [line for line in out.splitlines() if "--help" not in line]
    found = [line for line in lines if re.search(r"<(float|int|path|text|bool)>", line)]
    assert not found, found


def test_a_file_output_needs_a_known_suffix(run_cli, tmp_path):
    for args in (
        ["sweep", "-o", str(tmp_path / "rows.txt")],
        ["sample", "--sphere", "1", "--eps", "0.3", "-o", str(tmp_path / "s.xyz")],
        ["lfs", "--mesh", str(tmp_path / "m.stl"), "-o", str(tmp_path / "l.txt")],
    ):
        code, out, err = run_cli(*args)
        assert code == 2 and out == "" and len(err.strip().splitlines()) == 1, (args, err)
        assert not list(tmp_path.glob("*.txt")) and not list(tmp_path.glob("*.xyz"))


def test_sweep_writes_json_when_the_file_says_json(run_cli, tmp_path):
    target = tmp_path / "rows.json"
    code, _, _ = run_cli("sweep", "--rho-f", "1.2,1.5", "-o", str(target))
    assert code == 0
    data = json.loads(target.read_text())
    assert data["command"] == "sweep" and data["n_rows"] == len(data["rows"]) == 8


def test_exit_code_one_when_a_check_or_certificate_fails(run_cli, tmp_path):
    code, out, _ = run_cli("certify", "--fraction", "1.01")
    assert code == 1 and out.strip().splitlines()[-1].startswith("not certified")
    # ε = 0.2 on the torus (1.5, 1) is far above the ratio target's ε* (0.0095): R > ρ_f·R̂
    # occurs (380 of 2,981 guide triangles; at 0.1, 1,119 of 13,956, four times the work).
    code, out, _ = run_cli("check", "--torus", "1.5,1", "--eps", "0.2")
    assert code == 1
    last = out.strip().splitlines()[-1]
    assert re.match(
        r"[\d,]+ violations on smooth patches: [\d,]+ guide triangles with R > rho_f\*R\^", last
    )
    code, out, _ = run_cli("check", "--torus", "1.5,1", "--eps", "0.2", "--json")
    data = json.loads(out)
    assert code == 1 and data["ok"] is False and data["failures"]["ratio"] > 0


def test_exit_code_zero_when_everything_holds(run_cli):
    code, out, _ = run_cli("check", "--torus", "3,1", "--eps", "0.2", "--json")
    data = json.loads(out)
    assert code == 0 and data["ok"] is True and not any(data["failures"].values())


def test_tables_keep_every_digit_at_80_columns(capsys, monkeypatch):
    """A table wider than the terminal never cuts a number: numbers stay whole on one line
    (rows become "column: value" lines when even the numbers do not fit)."""
    from rich.console import Console

    from vorobound.cli import render

    numbers = ["12,156,678 – 86,489,512", "0.0094976911", "153.53× fewer"]
    rows = [[f"mode {i}", *numbers, "some longer words that may fold"] for i in range(3)]
    for width in (40, 80, 200):
        monkeypatch.setattr("sys.stdout.isatty", lambda: True, raising=False)
        monkeypatch.setattr(Console, "width", property(lambda self, w=width: w))
        render.print_table("title", ["mode", "samples", "ε*", "vs", "note"], rows)
        printed = capsys.readouterr().out
        for number in numbers:
            assert number in printed, (width, number)
        assert "…" not in printed


def test_results_print_short_and_hold_plain_floats():
    result = vorobound.solve(mode="tight")
    assert type(result.eps_star) is float and len(repr(result)) < 300
    assert result.eps_star == pytest.approx(0.0094976911, rel=1e-8)
    bound = vorobound.bound(eps=0.005, target="additive")
    assert type(bound.value) is float and type(bound.fraction_of_target) is float
    tri = vorobound.triangle(edges=(5, 4, 3), weights=(0, 0.2, 0.5))
    assert type(tri.radius_gap) is float and len(repr(tri)) < 300
    for value in tri.to_dict().values():
        assert not hasattr(value, "dtype")


def test_triangle_json_names_the_gap_radius_gap_and_keeps_delta_for_one_release(run_cli):
    code, out, _ = run_cli("triangle", "--edges", "5,4,3", "-w", "0,0.2,0.5", "--json")
    data = json.loads(out)
    assert code == 0 and data["radius_gap"] == data["delta"] > 0
    assert data["deprecated_keys"]["delta"] == "radius_gap"


def test_api_errors_are_voroboundErrors():
    with pytest.raises(vorobound.VoroboundError, match="sigma"):
        vorobound.solve(sigma=-1)
    with pytest.raises(vorobound.VoroboundError, match="give one surface"):
        vorobound.advise(sphere=1, torus=(3, 1))
    with pytest.raises(vorobound.VoroboundError, match="mode"):
        vorobound.sweep(mode="bogus")


def test_per_row_results_become_dataframes(tmp_path):
    pd = pytest.importorskip("pandas")
    rows = vorobound.sweep(rho_f=[1.2, 1.3], mode="rigorous", target="additive").to_frame()
    assert isinstance(rows, pd.DataFrame) and len(rows) == 2
    assert list(rows["rho_f"]) == [1.2, 1.3] and rows["eps_star"].is_monotonic_increasing
    result = vorobound.check(torus=(3, 1), eps=0.25)
    triangles = result.to_frame()
    assert len(triangles) == result.n_guide_triangles
    assert triangles["gap_ratio"].max() == pytest.approx(result.gap_ratio_max or 0.0, abs=1e-12)


@pytest.mark.parametrize(
    "args",
    [
        ["check", "--torus", "3,1", "--eps", "0.15", "--out", ""],
        ["check", "--torus", "3,1", "--eps", "0.15", "--out="],
        ["sample", "--sphere", "1", "--eps", "0.2", "-o", ""],
    ],
)
def test_an_empty_output_path_is_refused_not_read_as_the_current_folder(
    run_cli, tmp_path, monkeypatch, args
):
    """An unset shell variable ($OUT) gives "": typer would read it as ".", the current folder."""
    monkeypatch.chdir(tmp_path)
    code, out, err = run_cli(*args)
    assert code == 2 and "empty string" in err and len(err.strip().splitlines()) == 1
    assert list(tmp_path.iterdir()) == []
