"""``vorobound sample`` and ``vorobound check`` end to end, including bad input."""

import json

import meshio
import numpy as np
import pytest

from vorobound.sampling.io.balls import pyarrow_available

pytest.importorskip("gudhi")

SUMMARY_KEYS = {
    "n_samples",
    "n_guide_triangles",
    "n_half_covered",
    "coverage_max",
    "sparsity_min",
    "rho_max",
    "gap_ratio_max",
    "bound",
    "outside_constraint_set",
    "violations",
}


def test_check_torus_writes_every_output(run_cli, tmp_path):
    out = tmp_path / "out"
    code, stdout, stderr = run_cli(
        "check", "--torus", "3,1", "--eps", "0.15", "--out", str(out), "--json"
    )
    assert code == 0, stderr
    summary = json.loads(stdout)
    assert SUMMARY_KEYS <= summary.keys()
    assert summary["coverage_max"] < 1 and summary["sparsity_min"] >= 1
    assert summary["n_guide_triangles"] > 0 and summary["outside_constraint_set"] == 0
    assert set(summary["bound"]) == {"paper", "rigorous", "tight", "tight_lipschitz"}
    # Per-triangle rows: Parquet where pyarrow is installed, else NPZ (the oldest-dependency CI
    # run has no pyarrow).
    rows_name = "triangles.parquet" if pyarrow_available() else "triangles.npz"
    names = sorted(p.name for p in out.iterdir())
    assert names == ["gap_histogram.png", "sample.vtu", "summary.json", rows_name]
    assert json.loads((out / "summary.json").read_text())["n_samples"] == summary["n_samples"]
    mesh = meshio.read(out / "sample.vtu")  # the VTU round-trips through meshio
    assert len(mesh.points) == summary["n_samples"]
    triangles = mesh.cells_dict["triangle"]
    assert len(triangles) == summary["n_guide_triangles"]
    rho = mesh.cell_data_dict["rho"]["triangle"]
    assert rho.max() == pytest.approx(summary["rho_max"], rel=1e-12)
    assert {"radius", "lfs"} <= mesh.point_data.keys()
    if pyarrow_available():
        import pyarrow.parquet as pq

        rho_rows = pq.read_table(out / "triangles.parquet").column("rho").to_numpy()
    else:
        rho_rows = np.load(out / "triangles.npz")["rho"]
    assert len(rho_rows) == summary["n_guide_triangles"]
    assert float(rho_rows.max()) == pytest.approx(summary["rho_max"])


def test_sample_then_check_the_balls(run_cli, tmp_path):
    path = tmp_path / "sample.npz"
    code, stdout, stderr = run_cli(
        "sample", "--sphere", "2", "--eps", "0.12", "-o", str(path), "--json"
    )
    assert code == 0, stderr
    made = json.loads(stdout)
    assert made["coverage_max"] < 1 and made["sparsity_min"] >= 1
    code, stdout, stderr = run_cli("check", "--balls", str(path), "--eps", "0.12", "--json")
    assert code == 0, stderr
    checked = json.loads(stdout)
    assert checked["n_samples"] == made["n_samples"]
    assert checked["coverage_max"] is None and "coverage_note" in checked
    assert checked["sparsity_violations"] == 0 and checked["lipschitz_violations"] == 0
    # With the surface given too, coverage is measured on it; the hull engine applies.
    code, stdout, _ = run_cli(
        "check", "--balls", str(path), "--sphere", "2", "--eps", "0.12", "--json"
    )
    both = json.loads(stdout)
    assert both["coverage_max"] < 1 and both["engine"] == "hull"
    assert both["n_guide_triangles"] == checked["n_guide_triangles"]


def test_check_prints_tables(run_cli):
    code, stdout, stderr = run_cli("check", "--sphere", "1", "--eps", "0.2")
    assert code == 0, stderr
    assert "guide triangles" in stdout and "rigorous" in stdout


def test_planted_bad_sample_is_reported(run_cli, tmp_path):
    """A good sample with two balls moved too close and one radius made non-Lipschitz."""
    eps = 0.12
    sample = tmp_path / "good.npz"
    assert run_cli("sample", "--torus", "3,1", "--eps", str(eps), "-o", str(sample))[0] == 0
    data = np.load(sample)
    centers = np.column_stack([data["x"], data["y"], data["z"]])
    radii = data["radius"].copy()
    close = 0.3 * 0.75 * eps  # a sparsity ratio of about 0.3
    direction = centers[1] - centers[0]
    centers[1] = centers[0] + close * direction / np.linalg.norm(direction)
    radii[100] *= 1.5  # L jumps by 0.5 between neighbours much closer than 0.5 apart
    bad = tmp_path / "bad.csv"
    rows = np.column_stack([centers, radii])
    bad.write_text("x,y,z,r\n" + "\n".join(",".join(repr(float(v)) for v in r) for r in rows))
    code, stdout, stderr = run_cli("check", "--balls", str(bad), "--eps", str(eps), "--json")
    assert code == 1, stderr  # ran, and found violations
    s = json.loads(stdout)
    assert s["ok"] is False and s["failures"]["sparsity"] == s["sparsity_violations"] >= 1
    worst = s["sparsity_worst"][0]
    assert {worst["i"], worst["j"]} == {0, 1}
    assert worst["ratio"] == pytest.approx(0.3, rel=1e-6)
    assert s["lipschitz_violations"] >= 1
    assert any(100 in (w["i"], w["j"]) for w in s["lipschitz_worst"])
    assert s["lipschitz_realized"] > 1


def _write(path, rows, header="x,y,z,r"):
    path.write_text(header + "\n" + "\n".join(",".join(repr(float(v)) for v in r) for r in rows))
    return path


GOOD = np.column_stack([np.random.default_rng(1).random((10, 3)), np.full(10, 0.3)])


@pytest.mark.parametrize(
    "args, message",
    [
        (["--balls", "{nan}"], "not finite"),
        (["--balls", "{negative}"], "positive"),
        (["--balls", "{duplicate}"], "coincide"),
        (["--balls", "{few}"], "at least 4"),
        (["--balls", "{text}"], "cannot read"),
        (["--balls", "{apart}"], "no guide triangle"),
        (["--torus", "3,1", "--eps", "1e-6"], "fit in memory"),
        (["--torus", "3"], "2 comma-separated"),
        (["--torus", "1,3"], "R > r"),
        (["--sphere", "nan"], "sphere"),
        (["--mesh", "{text}"], "cannot read mesh"),
        (["--mesh", "{text}", "--lfs", "1", "--sizing", "{text}"], "not both"),
        ([], "give a surface"),
        (["--sphere", "1", "--lipschitz", "1"], "goes with balls"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(run_cli, tmp_path, args, message):
    files = {
        "nan": _write(
            tmp_path / "nan.csv", np.where(np.arange(40).reshape(10, 4) == 9, np.nan, GOOD)
        ),
        "negative": _write(tmp_path / "neg.csv", GOOD * np.array([1, 1, 1, -1])),
        "duplicate": _write(tmp_path / "dup.csv", np.vstack([GOOD, GOOD[:1]])),
        "few": _write(tmp_path / "few.csv", GOOD[:3]),
        "apart": _write(tmp_path / "apart.csv", GOOD * np.array([1, 1, 1, 1e-3])),
        "text": tmp_path / "notes.txt",
    }
    files["text"].write_text("not a point set\n")
    out = tmp_path / "out"
    args = [a.format(**files) for a in args]
    if "--eps" not in args:
        args += ["--eps", "0.1"]
    code, stdout, stderr = run_cli("check", *args, "--out", str(out), "--json")
    assert code == 2
    assert stdout == ""
    lines = stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error:") and message in lines[0], stderr
    assert not out.exists()  # nothing half-written


@pytest.mark.slow
def test_check_a_mesh_with_estimated_lfs(run_cli, tmp_path):
    from vorobound.sampling.surfaces.demo_meshes import torus_mesh

    mesh = torus_mesh(3.0, 1.0, 120, 40)
    path = tmp_path / "torus.vtu"
    meshio.write(path, meshio.Mesh(mesh.points, [("triangle", mesh.triangles)]))
    code, stdout, stderr = run_cli("check", "--mesh", str(path), "--eps", "0.2", "--json")
    assert code == 0, stderr
    s = json.loads(stdout)
    assert "estimated" in s["source"]
    assert s["coverage_max"] < 1 and s["sparsity_min"] >= 1 and s["n_guide_triangles"] > 0


def test_sample_refuses_a_bad_output_name_before_work(run_cli, tmp_path):
    code, stdout, stderr = run_cli(
        "sample", "--sphere", "1", "--eps", "0.1", "-o", str(tmp_path / "s.txt")
    )
    assert code == 2 and ".npz, .vtu or .csv" in stderr
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize("table", ["npz", "csv"])
def test_the_per_triangle_table_formats_agree(run_cli, tmp_path, table):
    """Compact by default; CSV on request with 10 significant digits; the same rows."""
    out = tmp_path / table
    code, stdout, _ = run_cli(
        "check", "--torus", "3,1", "--eps", "0.25", "--out", str(out), "--table", table, "--json"
    )
    assert code in (0, 1)
    summary = json.loads(stdout)
    if table == "npz":
        rows = np.load(out / "triangles.npz")
        rho = rows["rho"]
    else:
        text = (out / "triangles.csv").read_text().splitlines()
        header = text[0].split(",")
        rho = np.loadtxt(text[1:], delimiter=",", ndmin=2)[:, header.index("rho")]
        assert max(len(v) for v in text[1].split(",")) <= 17  # no 17-digit noise
    assert len(rho) == summary["n_guide_triangles"]
    assert rho.max() == pytest.approx(summary["rho_max"], rel=1e-9)
    assert summary["params"]["table"] == table
