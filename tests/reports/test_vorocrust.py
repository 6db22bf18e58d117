"""Reading VoroCrust runs, inferring what their balls realize, and the deck vorobound writes.

The fixtures under tests/data/vorocrust/ are runs of Sandia's vc_mesh (docs/vorocrust.md: the
commit and build) on meshes made by vorobound's own code: a torus R = 1, r = 0.4 about z
(demo_meshes.torus_mesh(1, 0.4, 48, 16)) and the cube of side 2 (cad_meshes.cube()).
"""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path

import numpy as np
import pytest

from vorobound.cli import main
from vorobound.errors import ReadError
from vorobound.sampling.io.vorocrust import read_deck, read_run

DATA = Path(__file__).parents[1] / "data" / "vorocrust"
TORUS = DATA / "torus"
CUBE = DATA / "cube"


def run_cli(capsys, *args):
    code = main(list(args))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def _radius_lipschitz(balls):
    """max |r_p − r_q|/|p − q| over overlapping pairs and over all pairs (brute force)."""
    gap = np.linalg.norm(balls.centers[:, None] - balls.centers[None], axis=2)
    np.fill_diagonal(gap, np.inf)
    r = balls.radii
    ratio = np.abs(r[:, None] - r[None]) / gap
    return ratio[gap < r[:, None] + r[None]].max(), ratio.max()


def test_deck_is_read_as_vc_mesh_reads_it(tmp_path):
    deck = read_deck(TORUS / "vc.in")
    assert deck.input_meshes == ("torus.obj",)
    assert deck.values["LIP_CONST"] == 0.25 and deck.values["VC_ANGLE"] == 60
    assert deck.values["R_MIN"] == 0 and math.isinf(deck.values["R_MAX"]) is False
    assert deck.ignored == ("NUM_LOOP_REF",)  # declared in vc_mesh, never read
    path = tmp_path / "vc.in"
    path.write_text("INPUT_MESH_FILE = a.obj\nLIP_CONST=0.5\n# note\nGENERATE_VCG_FILE = 0\n")
    deck = read_deck(path)
    assert deck.values["LIP_CONST"] == 0.1  # 'LIP_CONST=0.5' is one token: ignored, default
    assert deck.ignored == ("LIP_CONST=0.5", "#")
    assert deck.flags == ("GENERATE_VCG_FILE",)  # a flag is set by its presence
    path.write_text("INPUT_MESH_FILE = a.obj\nR_MAX 3\n")
    with pytest.raises(ReadError, match="line 2: R_MAX needs 'KEY = VALUE'"):
        read_deck(path)
    path.write_text("INPUT_MESH_FILE = a.obj\nR_MAX = big\n")
    with pytest.raises(ReadError, match="not a number"):
        read_deck(path)
    path.write_text("R_MAX = 1\n")
    with pytest.raises(ReadError, match="no INPUT_MESH_FILE"):
        read_deck(path)


def test_run_strata_are_read():
    run = read_run(CUBE)
    counts = run.counts()
    assert counts == {"corner": 8, "edge": 17, "surface": 243, "interior": 0}
    assert run.mesh == CUBE / "cube.obj" and run.seeds == CUBE / "seeds.csv"
    # corner balls sit on the cube's corners
    corners = run.strata["corner"].centers
    assert np.all(np.isin(corners, [0.0, 2.0]))
    torus = read_run(TORUS)
    assert torus.strata["corner"] is None and torus.counts()["surface"] == 285


def test_each_file_also_reads_alone():
    from vorobound.sampling.io.balls import read_balls
    from vorobound.sampling.reconstruct.seeds import read_seed_file

    balls = read_balls(TORUS / "surface_spheres.csv")
    assert len(balls) == 285
    seeds = read_seed_file(TORUS / "seeds.csv")  # its header names 4 of the 5 columns
    assert len(seeds) == 1165 and 0 < seeds.inside.sum() < len(seeds)


def test_check_vorocrust_infers_and_the_values_fed_back_pass(capsys):
    code, out, err = run_cli(
        capsys, "check", "--vorocrust", str(TORUS), "--torus", "1,0.4", "--json"
    )
    assert code == 0, err
    data = json.loads(out)
    realized, guarantee = data["realized"], data["guarantee"]
    m = realized["measured"]
    # VoroCrust's own parameters come back out of its balls: its coverage radius ratio 0.4 (a
    # new centre stays sqrt(1 - 0.4^2) radii from the old ones) and LIP_CONST 0.25, which it
    # enforces between overlapping balls only; farther neighbours exceed it.
    overlapping, every = _radius_lipschitz(read_run(TORUS).strata["surface"])
    assert overlapping == pytest.approx(0.25, rel=1e-9) and every > 0.26
    assert overlapping <= m["radius_lipschitz"] <= every
    assert m["spacing_over_radius_min"] >= math.sqrt(1 - 0.4**2) - 1e-6
    # rounded toward safety
    assert realized["eps"] >= m["coverage_over_lfs_max"]
    assert realized["eps"] * realized["delta_ratio"] >= m["radius_over_lfs_max"]
    assert realized["sigma"] <= realized["delta_ratio"] * m["spacing_over_radius_min"]
    assert guarantee["target"] == "ratio" and guarantee["failed_condition"] is None
    assert 1 < guarantee["rho_f"] < 10
    assert data["ratio_max"] <= guarantee["rho_f"]  # measured R/R^ within the proven bound
    assert data["strata"]["surface"] == 285 and data["strata"]["seeds"] == 1165
    code, out, err = run_cli(
        capsys,
        "check",
        "--balls",
        str(TORUS / "surface_spheres.csv"),
        "--torus",
        "1,0.4",
        "--eps",
        repr(realized["eps"]),
        "--sigma",
        repr(realized["sigma"]),
        "--delta-ratio",
        repr(realized["delta_ratio"]),
        "--lipschitz",
        repr(realized["lipschitz"]),
        "--json",
    )
    fed = json.loads(out)
    assert fed["failures"]["coverage"] == 0
    assert fed["failures"]["sparsity"] == 0
    assert fed["failures"]["lipschitz"] == 0


def test_check_balls_without_eps_on_a_cad_run(capsys):
    code, out, err = run_cli(capsys, "check", "--vorocrust", str(CUBE), "--lfs", "1", "--json")
    assert code == 0, err
    data = json.loads(out)
    features = data["feature_strata"]
    assert features["corner"]["count"] == 8 and features["edge"]["count"] == 17
    assert data["n_samples"] == 243  # the smooth verdict counts the surface balls only
    realized = data["realized"]
    code, out, err = run_cli(
        capsys,
        "check",
        "--balls",
        str(CUBE / "surface_spheres.csv"),
        "--mesh",
        str(CUBE / "cube.obj"),
        "--lfs",
        "1",
        "--json",
    )
    alone = json.loads(out)
    assert alone["strata"] == {"balls": 243}
    # alone, the probes near the edges count too: coverage can only need a larger eps
    assert alone["realized"]["eps_coverage"] >= realized["eps_coverage"]
    for key in ("coverage", "sparsity", "lipschitz"):
        assert alone["failures"][key] == 0


@pytest.mark.parametrize(
    "args, message",
    [
        (["--balls", str(TORUS / "surface_spheres.csv")], "need the surface"),
        (
            ["--balls", str(TORUS / "surface_spheres.csv"), "--torus", "1,0.4", "--sigma", "1"],
            "inferred from the balls",
        ),
        (["--vorocrust", str(DATA / "missing")], "no such folder"),
        (
            ["--vorocrust", str(TORUS), "--balls", str(TORUS / "surface_spheres.csv")],
            "not both",
        ),
    ],
)
def test_bad_input_is_one_line(capsys, args, message):
    code, out, err = run_cli(capsys, "check", *args)
    assert code == 2
    assert message in err and len(err.strip().splitlines()) == 1


def test_run_without_ball_files_is_refused(tmp_path, capsys):
    shutil.copy(TORUS / "vc.in", tmp_path / "vc.in")
    code, out, err = run_cli(capsys, "check", "--vorocrust", str(tmp_path))
    assert code == 2 and "no ball file" in err


def test_reconstruct_vorocrust_measures_the_runs_own_seeds(capsys):
    code, out, err = run_cli(
        capsys, "reconstruct", "--vorocrust", str(TORUS), "--torus", "1,0.4", "--json"
    )
    assert code == 0, err
    data = json.loads(out)
    assert data["topology_correct"] and data["euler_characteristic"] == 0
    assert data["n_seeds"] == 1165
    assert "local ball radius" in data["distance_unit"]
    # M̂ of a VoroCrust run lies within its balls: well under one ball radius from the torus
    assert 0 < data["hausdorff_over_eps_lfs"] < 1
    assert data["normal_deviation_max_deg"] < 45
    code, out, err = run_cli(capsys, "reconstruct", "--vorocrust", str(TORUS), "--eps", "0.1")
    assert code == 2 and len(err.strip().splitlines()) == 1


def test_reconstruct_vorocrust_python_keyword_matches_cli():
    import vorobound

    result = vorobound.reconstruct(vorocrust=CUBE, lfs=1.0)
    assert result.topology_correct and result.euler_characteristic == 2
    assert result.to_dict()["params"]["vorocrust"] == str(CUBE)


def _turned_balls(tmp_path) -> Path:
    """The torus fixture's surface balls with the torus's axis along y: (x, y, z) -> (y, z, x)
    as columns, i.e. the world's y is the fixture's z."""
    from vorobound.sampling.io.balls import read_balls

    balls = read_balls(TORUS / "surface_spheres.csv")
    turned = balls.centers[:, [1, 2, 0]]
    path = tmp_path / "turned.csv"
    np.savetxt(path, np.column_stack([turned, balls.radii]), delimiter=",", fmt="%.17g")
    return path


def test_torus_axis_gives_the_same_inference(tmp_path, capsys):
    code, out, err = run_cli(
        capsys, "check", "--balls", str(TORUS / "surface_spheres.csv"), "--torus", "1,0.4", "--json"
    )
    assert code == 0, err
    about_z = json.loads(out)
    code, out, err = run_cli(
        capsys, "check", "--balls", str(_turned_balls(tmp_path)), "--torus", "1,0.4,y", "--json"
    )
    assert code == 0, err
    about_y = json.loads(out)
    assert "off the given surface" not in err
    for key in ("eps", "sigma", "delta_ratio", "lipschitz"):
        assert about_y["realized"][key] == pytest.approx(about_z["realized"][key], rel=1e-3)
    assert about_y["guarantee"]["rho_f"] == pytest.approx(about_z["guarantee"]["rho_f"], rel=1e-3)


def test_balls_off_the_given_surface_are_warned_about(tmp_path, capsys):
    turned = str(_turned_balls(tmp_path))
    code, out, err = run_cli(capsys, "check", "--balls", turned, "--torus", "1,0.4", "--eps", "0.5")
    assert "ball centres lie off the given surface" in err and "axis" in err
    code, out, err = run_cli(
        capsys, "reconstruct", "--balls", turned, "--torus", "1,0.4", "--eps", "0.5", "--json"
    )
    assert "ball centres lie off the given surface" in err
    code, out, err = run_cli(capsys, "check", "--torus", "1,0.4,y", "--eps", "0.3")
    assert code == 2 and "samples are made about z" in err
    assert len(err.strip().splitlines()) == 1
    code, out, err = run_cli(capsys, "check", "--balls", turned, "--torus", "1,0.4,w")
    assert code == 2 and len(err.strip().splitlines()) == 1


def test_advise_writes_a_deck_vc_mesh_reads(tmp_path, capsys):
    folder = tmp_path / "run"
    code, out, err = run_cli(
        capsys,
        "advise",
        "--mesh",
        str(CUBE / "cube.obj"),
        "--lfs",
        "1",
        "--lipschitz",
        "1",
        "--vorocrust",
        str(folder),
        "--json",
    )
    assert code == 0, err
    data = json.loads(out)
    chosen, eps = data["vorocrust"], data["recommendation"]["eps"]
    beta = math.sqrt(1 - 0.4**2)
    deck = read_deck(folder / "vc.in")
    assert deck.input_meshes == ("cube.obj",) and deck.sizing_file == "sizing.csv"
    assert deck.ignored == ("#",)  # the comment lines, which vc_mesh skips as unknown keys
    assert deck.values["LIP_CONST"] == pytest.approx(eps / beta, rel=1e-12)
    assert deck.values["VC_ANGLE"] == 30
    table = np.loadtxt(folder / "sizing.csv", delimiter=",", skiprows=1)
    assert table.shape[1] == 4 and len(table) == chosen["sizing_rows"]
    # L = 1 everywhere: every row's radius is at most eps*L/beta, R_MAX the largest
    assert table[:, 3].max() <= eps / beta * (1 + 1e-12)
    assert deck.values["R_MAX"] == pytest.approx(table[:, 3].max(), rel=1e-12)
    from vorobound.sampling.io.meshes import read_triangle_mesh

    assert len(read_triangle_mesh(folder / "cube.obj").triangles) == 12
    code, out, err = run_cli(capsys, "advise", "--sphere", "1", "--vorocrust", str(folder))
    assert code == 2 and "give mesh too" in err and len(err.strip().splitlines()) == 1


LIVE = pytest.mark.skipif(shutil.which("vc_mesh") is None, reason="vc_mesh is not on PATH")


@pytest.mark.slow
@LIVE
def test_live_run_realizes_what_the_fixture_does(tmp_path, capsys):
    """vc_mesh run live on the torus fixture's deck and mesh (about 10 CPU seconds) realizes
    the fixture's parameters (identical with a FIXED_RNG_SEED build)."""
    import subprocess

    for name in ("vc.in", "torus.obj"):
        shutil.copy(TORUS / name, tmp_path / name)
    subprocess.run(["vc_mesh", "-vc", "vc.in"], cwd=tmp_path, check=True, capture_output=True)
    found = []
    for folder in (TORUS, tmp_path):
        code, out, err = run_cli(
            capsys, "check", "--vorocrust", str(folder), "--torus", "1,0.4", "--json"
        )
        assert code == 0, err
        found.append(json.loads(out)["realized"])
    for key in ("eps", "sigma", "delta_ratio", "lipschitz"):
        assert found[1][key] == pytest.approx(found[0][key], rel=0.2)


@pytest.mark.slow
@LIVE
def test_round_trip_through_vc_mesh(tmp_path, capsys):
    """advise --vorocrust, then vc_mesh live, then check --vorocrust (skipped without it; the
    run makes about 21,000 balls, 400 CPU seconds: docs/vorocrust.md)."""
    import subprocess

    folder = tmp_path / "run"
    code, out, err = run_cli(
        capsys,
        "advise",
        "--mesh",
        str(CUBE / "cube.obj"),
        "--lfs",
        "1",
        "--rho-f",
        "3",
        "--lipschitz",
        "1",
        "--vorocrust",
        str(folder),
    )
    assert code == 0, err
    subprocess.run(["vc_mesh", "-vc", "vc.in"], cwd=folder, check=True, capture_output=True)
    code, out, err = run_cli(capsys, "check", "--vorocrust", str(folder), "--lfs", "1", "--json")
    data = json.loads(out)
    assert data["strata"]["corner"] == 8
    assert data["realized"]["eps_coverage"] <= 0.0611 * 1.05  # about the advised eps
    assert data["guarantee"]["rho_f"] <= 3


def test_json_matches_the_schema(capsys):
    import jsonschema

    schema = json.loads(
        (Path(__file__).parents[2] / "docs/schema/vorobound-output.schema.json").read_text()
    )
    code, out, err = run_cli(
        capsys, "check", "--vorocrust", str(TORUS), "--torus", "1,0.4", "--json"
    )
    jsonschema.validate(json.loads(out), schema)
    broken = json.loads(out)
    broken["realized"].pop("eps")
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate(broken, schema)


def test_inference_on_vorobounds_own_sample_is_at_least_as_good(tmp_path):
    """Balls sampled by vorobound at eps = 0.1 (sigma 3/4, delta = 2 eps, L exact on the unit
    sphere): the realized eps is at most 0.1 and the proven rho_f at most the bound at the
    sampling parameters (realized sigma/(delta/eps) = S is at least 0.75/2)."""
    import vorobound
    from vorobound.bounds.tight.ratio_form import ratio_supremum_closed_form
    from vorobound.reports.vorocrust import realize
    from vorobound.sampling.io.balls import read_balls
    from vorobound.sampling.surfaces.analytic import SphereShape

    path = tmp_path / "sample.csv"
    vorobound.sample(eps=0.1, sphere=1.0, output=path)
    found = realize(read_balls(path), SphereShape(1.0), "auto", 1.38)
    assert found.failed_condition is None
    assert found.eps <= 0.1
    assert found.measured.spacing >= 0.75 / 2 * (1 - 1e-9)
    assert found.delta_ratio * found.eps >= 0.2 * (1 - 1e-9)  # delta = max r/L = 2 eps
    at_sampling = ratio_supremum_closed_form(0.1, 0.75, 2.0, 1.0).value
    assert found.rho_f_ratio <= at_sampling * (1 + 1e-4)
    # equal radii on the sphere: lambda = 0, so mu* = 0 and R = R^ (orthocentre = circumcentre)
    assert found.lipschitz == 0 and found.rho_f_ratio == 1


def test_check_vorocrust_at_given_eps_and_with_out(tmp_path, capsys):
    code, out, err = run_cli(
        capsys,
        "check",
        "--vorocrust",
        str(TORUS),
        "--torus",
        "1,0.4",
        "--eps",
        "0.1",
        "--json",
    )
    data = json.loads(out)
    assert code == 1  # at eps = 0.1 the coarse run is no eps-sample
    assert data["failures"]["coverage"] == 1 and "realized" not in data
    assert data["strata"]["surface"] == 285
    folder = tmp_path / "out"
    code, out, err = run_cli(
        capsys, "check", "--vorocrust", str(TORUS), "--torus", "1,0.4", "--out", str(folder)
    )
    assert code == 0, err
    summary = json.loads((folder / "summary.json").read_text())
    assert summary["realized"]["eps"] is not None and summary["guarantee"]["rho_f"] > 1
