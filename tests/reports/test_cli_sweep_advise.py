"""``vorobound sweep`` and ``vorobound advise`` from the command line."""

import csv
import io
import json

import pytest
from helpers import assert_one_line_error

from vorobound.bounds.eps_star import solve_eps_star
from vorobound.bounds.params import QualityParams


def test_sweep_rho_f_range_is_inclusive_and_matches_the_solver(run_cli):
    code, out, _ = run_cli("sweep", "--rho-f", "1.2:1.5:4", "--mode", "paper", "--format", "json")
    assert code == 0
    rows = json.loads(out)["rows"]
    assert [r["rho_f"] for r in rows] == pytest.approx([1.2, 1.3, 1.4, 1.5] * 2)
    assert [r["target"] for r in rows] == ["additive"] * 4 + ["ratio"] * 4
    for row in rows:
        quality = QualityParams(rho_f=row["rho_f"], target=row["target"])
        expected = solve_eps_star(quality, "paper").eps_star
        assert row["eps_star"] == pytest.approx(expected, rel=1e-10)


def test_sweep_csv_and_json_round_trip(run_cli, tmp_path):
    args = ["sweep", "--sigma", "0.5,0.75", "--rho-f", "1.3,1.38"]
    _, as_json, _ = run_cli(*args, "--format", "json")
    target = tmp_path / "out.csv"
    code, _, _ = run_cli(*args, "--format", "csv", "-o", str(target))
    assert code == 0
    from_csv = list(csv.DictReader(io.StringIO(target.read_text())))
    from_json = json.loads(as_json)["rows"]
    assert len(from_csv) == len(from_json) == 16  # 2 modes × 2 targets × 2 σ × 2 ρ_f
    for c, j in zip(from_csv, from_json, strict=True):
        assert c["mode"] == j["mode"] and c["target"] == j["target"]
        assert float(c["eps_star"]) == j["eps_star"]
        assert float(c["sigma"]) == j["sigma"] and c["lipschitz"] == ""


def test_sweep_over_eps_gives_bound_curves(run_cli):
    code, out, _ = run_cli(
        "sweep", "--eps", "0.001:0.01:5", "--mode", "rigorous,tight", "--format", "json"
    )
    assert code == 0
    rows = json.loads(out)["rows"]
    assert len(rows) == 20 and {"eps", "bound", "limit", "target"} <= rows[0].keys()
    for mode in ("rigorous", "tight"):
        for target in ("additive", "ratio"):
            curve = [r for r in rows if r["mode"] == mode and r["target"] == target]
            finite = [r["bound"] for r in curve if r["bound"] is not None]
            assert all(a < b for a, b in zip(finite, finite[1:], strict=False))
            expected = [1.38 if target == "ratio" else 0.76 * r["eps"] for r in curve]
            assert [r["limit"] for r in curve] == pytest.approx(expected)
    tight_ratio = [r for r in rows if r["mode"] == "tight" and r["target"] == "ratio"]
    assert all(r["bound"] is not None and r["claim"] == "proven" for r in tight_ratio)


def test_advise_sphere_json(run_cli):
    code, out, _ = run_cli("advise", "--sphere", "2", "--mode", "paper,rigorous", "--json")
    assert code == 0
    data = json.loads(out)
    assert len(data["modes"]) == 4  # 2 modes × 2 targets
    keys = {
        "mode",
        "eps_star",
        "ball_radius",
        "min_spacing",
        "samples_low",
        "samples_high",
        "reduction_vs_1_500",
    }
    for entry in data["modes"]:
        assert keys <= entry.keys()
        assert entry["samples_low"] == pytest.approx(4 * 2**2 / (entry["eps_star"] * 2) ** 2)
        assert entry["ball_radius"] == pytest.approx(2 * entry["eps_star"] * 2)
        if entry["claim"] == "invalid":  # no "fewer samples" beside an invalid claim
            assert entry["reduction_vs_1_500"] is None
        else:
            assert entry["reduction_vs_1_500"] == pytest.approx((entry["eps_star"] * 500) ** 2)
    assert "Not covered" in data["guarantee"]


@pytest.mark.parametrize(
    "args",
    [
        ["sweep", "--rho-f", "1:2"],
        ["sweep", "--rho-f", "1.2:1.5:0"],
        ["sweep", "--rho-f", "a,b"],
        ["sweep", "--rho-f", "0.5"],
        ["sweep", "--eps", "0:2:3"],
        ["sweep", "--mode", "fast"],
        ["sweep", "--jobs", "0"],
        ["sweep", "-o", "/nonexistent/dir/out.csv"],
        ["advise", "--area", "10"],
        ["advise", "--sphere", "-1"],
        ["advise", "--torus", "1,2"],
        ["advise", "--torus", "1"],
        ["advise", "--mesh", "/no/such/mesh.stl", "--lfs", "1"],
        ["advise", "--sphere", "1", "--torus", "3,1"],
        ["advise", "--mode", "tight,nope"],
    ],
)
def test_bad_input_one_line_exit_2(run_cli, args):
    code, out, err = run_cli(*args)
    assert_one_line_error(code, out, err)


def test_unreadable_mesh_file_is_one_line(run_cli, tmp_path):
    junk = tmp_path / "junk.stl"
    junk.write_bytes(b"\x00\x01 not a mesh")
    code, _, err = run_cli("advise", "--mesh", str(junk), "--lfs", "1", "--mode", "paper")
    assert code == 2 and len(err.strip().splitlines()) == 1


@pytest.mark.slow
def test_a_mode_without_eps_star_does_not_abort_the_advice(run_cli):
    """σ = 1.8: the rigorous chain has no admissible ε; the tight rows and the
    recommendation (from the tight closed form's proven lower bound) still come out."""
    code, out, err = run_cli("advise", "--sphere", "1", "--sigma", "1.8", "--json")
    assert code == 0, err
    data = json.loads(out)
    rigorous = [m for m in data["modes"] if m["mode"] == "rigorous"]
    assert len(rigorous) == 2
    for row in rigorous:
        assert row["eps_star"] is None and row["claim"] == "none"
        assert "no admissible eps" in row["note"]
    tight = [m for m in data["modes"] if m["mode"] == "tight"]
    assert all(m["eps_star"] > 0 and m["note"] is None for m in tight)
    rec = data["recommendation"]
    assert rec is not None and rec["mode"] == "tight" and rec["claim"] == "proven"
    assert rec["eps"] <= min(m["eps_star"] for m in tight)
    code, out, _ = run_cli("advise", "--sphere", "1", "--sigma", "1.8")
    assert code == 0 and "no ε* for rigorous, target additive" in out


def _advise_estimated_and_exact(run_cli, path, mesh, exact_option):
    """advise on a mesh file with nothing else given, and on the analytic surface: (estimated
    JSON, exact JSON), after the checks that L was estimated from the mesh and said so."""
    import meshio

    meshio.write(path, meshio.Mesh(mesh.points, [("triangle", mesh.triangles)]))
    code, out, _ = run_cli("advise", "--mesh", str(path), "--mode", "rigorous", "--json")
    estimated = json.loads(out)
    # Exit code 1 exactly when `vorobound sample` cannot build the recommended ε.
    assert code == (0 if estimated["recommendation"]["samplable"] else 1)
    assert estimated["surface"]["lfs_source"].startswith("estimated from the mesh")
    code, out, _ = run_cli("advise", *exact_option, "--mode", "rigorous", "--json")
    exact = json.loads(out)
    assert exact["surface"]["lfs_source"] == "exact"
    return estimated, exact


def test_advise_on_a_mesh_estimates_its_feature_size_and_says_so(run_cli, tmp_path):
    """A sphere mesh with nothing else given: L is estimated from the mesh, and the sample
    counts match the analytic sphere within the estimator's error (1 CPU-s; the torus, where
    L switches between the tube radius and the distance to the axis, is the slow test below)."""
    from vorobound.sampling.surfaces.demo_meshes import icosphere

    mesh = icosphere(1.0, 2)
    estimated, exact = _advise_estimated_and_exact(
        run_cli, tmp_path / "sphere.stl", mesh, ("--sphere", "1")
    )
    ratio = estimated["modes"][0]["samples_low"] / exact["modes"][0]["samples_low"]
    assert ratio == pytest.approx(1, rel=0.03)  # facets and the estimate, 162 vertices


@pytest.mark.slow
def test_advise_on_a_torus_mesh_matches_the_analytic_torus(run_cli, tmp_path):
    """The same on a 3 072-vertex torus (1.5, 1): 15 CPU-s, most of it the L estimate."""
    from vorobound.sampling.surfaces.demo_meshes import torus_mesh

    mesh = torus_mesh(1.5, 1.0, 96, 32)
    estimated, exact = _advise_estimated_and_exact(
        run_cli, tmp_path / "torus.stl", mesh, ("--torus", "1.5,1")
    )
    ratio = estimated["modes"][0]["samples_low"] / exact["modes"][0]["samples_low"]
    assert ratio == pytest.approx(1, rel=0.03)  # facets and the estimate, 3 072 vertices
