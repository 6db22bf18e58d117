"""``vorobound reconstruct`` end to end: outputs, the sweep, seed and ball files, exit codes."""

import json

import meshio
import numpy as np
import pytest

pytest.importorskip("gudhi")

KEYS = {
    "closed_manifold",
    "euler_characteristic",
    "n_facets",
    "hausdorff_over_eps_lfs",
    "normal_deviation_max_deg",
}
"""The keys other programs rely on (issue 22)."""


@pytest.mark.slow
def test_torus_writes_the_set_and_seed_file_measures_the_same(run_cli, tmp_path):
    out = tmp_path / "out"
    code, stdout, stderr = run_cli(
        "reconstruct", "--torus", "3,1", "--eps", "0.15", "--out", str(out), "--json"
    )
    assert code == 0, stderr
    made = json.loads(stdout)
    assert KEYS <= made.keys()
    assert made["closed_manifold"] is True and made["euler_characteristic"] == 0
    assert made["topology_correct"] and made["genus"] == 1
    names = sorted(p.name for p in out.iterdir())
    assert names == [
        "mhat.ply",
        "mhat.vtu",
        "quality.png",
        "seeds.csv",
        "seeds.vtu",
        "summary.json",
    ]
    mesh = meshio.read(out / "mhat.vtu")
    assert sum(len(block.data) for block in mesh.cells) == made["n_facets"]
    distance = np.concatenate(mesh.cell_data["hausdorff_over_eps_lfs"])
    assert distance.max() == pytest.approx(made["mhat_to_surface_over_eps_lfs"], rel=1e-12)
    # The seed file, in VoroCrust's format, read back gives the same M̂ and measurements.
    code, stdout, stderr = run_cli(
        "reconstruct",
        "--seeds",
        str(out / "seeds.csv"),
        "--torus",
        "3,1",
        "--eps",
        "0.15",
        "--json",
    )
    assert code == 0, stderr
    read = json.loads(stdout)
    assert read["labels"] == "file" and read["n_samples"] is None
    for key in KEYS | {"components", "edge_ratio_min", "surface_to_mhat_over_eps_lfs"}:
        assert read[key] == made[key], key
    # Without a surface: topology only.
    code, stdout, stderr = run_cli("reconstruct", "--seeds", str(out / "seeds.csv"), "--json")
    assert code == 0, stderr
    alone = json.loads(stdout)
    assert "hausdorff_over_eps_lfs" not in alone and alone["expected_euler_characteristic"] is None
    assert alone["euler_characteristic"] == 0 and alone["topology_correct"] is None


def test_balls_are_labelled_by_the_sheets(run_cli, tmp_path):
    path = tmp_path / "sample.npz"
    assert run_cli("sample", "--sphere", "1", "--eps", "0.15", "-o", str(path))[0] == 0
    code, stdout, stderr = run_cli("reconstruct", "--balls", str(path), "--json")
    assert code == 0, stderr
    s = json.loads(stdout)
    assert s["labels"] == "sheets" and s["euler_characteristic"] == 2 and s["closed_manifold"]
    code, stdout, stderr = run_cli(
        "reconstruct",
        "--balls",
        str(path),
        "--sphere",
        "1",
        "--eps",
        "0.15",
        "--compare-sheets",
        "--json",
    )
    assert code == 0, stderr
    s = json.loads(stdout)
    assert s["labels"] == "surface" and s["sheet_label_disagreements"] == 0
    assert s["hausdorff_over_eps_lfs"] < 1


def test_sweep_table_and_exit_code(run_cli, tmp_path):
    out = tmp_path / "sweep"
    code, stdout, stderr = run_cli(
        "reconstruct", "--sphere", "1", "--eps", "0.3,0.5", "--out", str(out), "--json"
    )
    assert code == 1, stderr  # no guide triangle at ε = 0.5: M̂ is wrong there
    s = json.loads(stdout)
    rows = {row["eps"]: row for row in s["rows"]}
    assert rows[0.3]["topology_correct"] and rows[0.3]["euler_characteristic"] == 2
    assert not rows[0.5]["topology_correct"] and "no guide triangle" in rows[0.5]["note"]
    marks = {(m["label"], m["target"]) for m in s["eps_star"]}
    assert {("paper", "additive"), ("rigorous", "ratio"), ("tight", "ratio")} <= marks
    assert sorted(p.name for p in out.iterdir()) == ["summary.json", "sweep.csv", "sweep.png"]
    code, stdout, _ = run_cli("reconstruct", "--sphere", "1", "--eps", "0.3:0.4:2")
    assert code == 0 and "Every bound's ε*" in stdout


def test_a_wrong_reconstruction_exits_with_1(run_cli, tmp_path):
    rng = np.random.default_rng(0)
    points = rng.standard_normal((200, 3))
    label = rng.integers(0, 2, 200)  # random labels: facets reach the hull
    path = tmp_path / "seeds.csv"
    np.savetxt(path, np.column_stack([points, np.ones(200), label]), delimiter=",")
    code, stdout, stderr = run_cli("reconstruct", "--seeds", str(path), "--json")
    assert code == 1, stderr
    s = json.loads(stdout)
    assert not s["closed_manifold"] and s["unbounded_facets"] > 0


@pytest.mark.parametrize(
    "args, message",
    [
        (["--torus", "3,1"], "give eps"),
        (["--eps", "0.1"], "give a surface"),
        (["--balls", "a.npz", "--seeds", "b.csv"], "not both"),
        (["--seeds", "SEEDS", "--torus", "3,1"], "give eps to measure"),
        (["--seeds", "SEEDS", "--eps", "0.1:0.2:2", "--torus", "3,1"], "sweep"),
        (["--seeds", "missing.csv"], "no such file"),
        (["--sphere", "1", "--eps", "0.1", "--figure-format", "gif"], "--figure-format"),
        (["--sphere", "1", "--eps", "nan"], "eps"),
        (["--sphere", "1", "--eps", "0.3", "--repeats", "0"], "repeats"),
        (["--sphere", "1", "--eps", "0.3", "--repeats", str(2**64)], "repeats"),
        (["--sphere", "1", "--eps", "0.3", "--repeats", "2", "--seed", str(2**63 - 1)], "seed"),
        (["--seeds", "SEEDS", "--repeats", "2"], "repeats"),
    ],
    ids=[
        "no-eps",
        "no-surface",
        "balls-and-seeds",
        "seeds-surface-no-eps",
        "seeds-sweep",
        "missing",
        "format",
        "nan-eps",
        "repeats-0",
        "repeats-2**64",
        "repeats-past-the-last-seed",
        "repeats-of-a-seed-file",
    ],
)
def test_bad_input_is_one_line_and_exit_2(run_cli, tmp_path, args, message):
    seeds = tmp_path / "seeds.csv"
    seeds.write_text("0,0,0,1,0\n1,0,0,1,1\n0,1,0,1,0\n0,0,1,1,1\n1,1,1,1,0\n")
    args = [str(seeds) if a == "SEEDS" else a for a in args]
    code, stdout, stderr = run_cli("reconstruct", *args)
    assert code == 2
    assert stderr.startswith("error:") and len(stderr.strip().splitlines()) == 1
    assert message in stderr


def test_a_mesh_is_measured_through_closest_points(run_cli, tmp_path):
    from vorobound.sampling.surfaces.demo_meshes import icosphere

    mesh = icosphere()
    path = tmp_path / "ico.obj"
    meshio.write(path, meshio.Mesh(mesh.points, [("triangle", mesh.triangles)]))
    code, stdout, stderr = run_cli(
        "reconstruct", "--mesh", str(path), "--lfs", "1", "--eps", "0.15", "--json"
    )
    assert code == 0, stderr
    s = json.loads(stdout)
    assert s["expected_euler_characteristic"] == 2 and s["topology_correct"]
    assert 0 < s["hausdorff_over_eps_lfs"] < 1 and s["flipped_facets"] == 0


def test_the_sweep_figure_plots_the_rows_and_every_eps_star():
    from vorobound.plotting import plot_reconstruct_sweep

    eps = [0.1, 0.2, 0.5]
    panels = {"Hausdorff": [0.03, 0.07, None], "angle": [27.0, 29.0, None]}
    marks = [("tight", "ratio", 0.0095), ("tight", "additive", 0.0248), ("H3 alone", "(55)", 0.64)]
    figure = plot_reconstruct_sweep(eps, panels, [True, True, False], marks, "test")
    top = figure.axes[0]
    lines = {tuple(line.get_xdata()): line for line in top.get_lines()}
    assert list(lines[(0.1, 0.2)].get_ydata()) == [0.03, 0.07]  # right topology: dots
    assert lines[(0.5,)].get_marker() == "x"  # wrong topology: a cross on the axis
    verticals = sorted(
        line.get_xdata()[0]
        for line in top.get_lines()
        if line.get_xdata()[0] == line.get_xdata()[-1] and len(line.get_xdata()) == 2
    )
    assert verticals == sorted(m[2] for m in marks)


def test_without_a_reference_surface_the_topology_is_not_judged(run_cli, tmp_path):
    """Seeds alone: M̂ is a closed manifold, but nothing says which χ is right, so
    topology_correct is null (not true) and the table says so; the exit code follows
    closed_manifold."""
    out = tmp_path / "out"
    code, _, stderr = run_cli("reconstruct", "--sphere", "1", "--eps", "0.3", "--out", str(out))
    assert code == 0, stderr
    seeds = str(out / "seeds.csv")
    code, stdout, stderr = run_cli("reconstruct", "--seeds", seeds, "--json")
    assert code == 0, stderr
    alone = json.loads(stdout)
    assert alone["closed_manifold"] and alone["expected_euler_characteristic"] is None
    assert alone["topology_correct"] is None and alone["ok"]
    code, stdout, _ = run_cli("reconstruct", "--seeds", seeds)
    assert code == 0
    row = next(line for line in stdout.splitlines() if "topology" in line)
    assert "no reference surface" in row and "right" not in row
    with_surface = run_cli(
        "reconstruct", "--seeds", seeds, "--sphere", "1", "--eps", "0.3", "--json"
    )
    assert json.loads(with_surface[1])["topology_correct"] is True


def test_repeats_count_the_draws_with_the_right_topology(run_cli):
    """--repeats K at one ε: draw k is the single run with seed SEED + k, and share_correct
    is the fraction of the draws whose M̂ has the surface's topology."""
    code, stdout, stderr = run_cli(
        "reconstruct", "--torus", "3,1", "--eps", "0.48", "--repeats", "3", "--seed", "5", "--json"
    )
    assert code in (0, 1), stderr
    s = json.loads(stdout)
    (row,) = s["rows"]
    draws = row["per_draw"]
    assert [d["seed"] for d in draws] == [5, 6, 7] and s["seed_range"] == [5, 7]
    right = [d["topology_correct"] for d in draws]
    assert s["share_correct"] == row["share_correct"] == sum(right) / 3
    assert code == (0 if all(right) else 1)
    hausdorff = sorted(d["hausdorff"] for d in draws)
    assert row["hausdorff"]["median"] == hausdorff[1] and row["hausdorff"]["max"] == hausdorff[2]
    assert len(set(hausdorff)) == 3  # three different samples
    code, stdout, _ = run_cli(
        "reconstruct", "--torus", "3,1", "--eps", "0.48", "--seed", "6", "--json"
    )
    alone = json.loads(stdout)
    assert alone["hausdorff_over_eps_lfs"] == draws[1]["hausdorff"]
    assert alone["topology_correct"] == draws[1]["topology_correct"]


def test_repeats_over_a_sweep_report_the_band_and_write_the_set(run_cli, tmp_path):
    out = tmp_path / "draws"
    code, stdout, stderr = run_cli(
        "reconstruct", "--sphere", "1", "--eps", "0.3,0.4,0.5", "--repeats", "2", "--out", str(out)
    )
    assert code == 1, stderr  # no guide triangle at ε = 0.5 in either draw
    assert "transition band (measured): every draw right up to ε = 0.4" in stdout
    assert "no draw right at ε = 0.5" in stdout
    s = json.loads((out / "summary.json").read_text())
    assert (s["largest_all_correct_eps"], s["smallest_none_correct_eps"]) == (0.4, 0.5)
    assert [r["share_correct"] for r in s["rows"]] == [1.0, 1.0, 0.0]
    assert "share_correct" not in s  # a sweep has it per ε only
    assert sorted(p.name for p in out.iterdir()) == ["draws.csv", "summary.json", "sweep.png"]
    lines = (out / "draws.csv").read_text().splitlines()
    assert lines[0].startswith("seed,eps,") and len(lines) == 1 + 2 * 3


def test_repeats_in_python_mirror_the_option():
    import vorobound

    result = vorobound.reconstruct(sphere=1, eps=0.45, repeats=2, seed=3)
    assert result.share_correct == 1.0 and result.ok and result.repeats == 2
    assert result.to_dict()["params"]["repeats"] == 2
    assert [row.seeds for row in result.draws.rows] == [(3, 4)]
    one = vorobound.reconstruct(sphere=1, eps=0.45, repeats=1, seed=3)  # one draw, counted
    assert one.share_correct == 1.0 and one.draws.rows[0].seeds == (3,)
    assert not hasattr(vorobound.reconstruct(sphere=1, eps=0.45, seed=3), "share_correct")


def test_the_draws_figure_shades_the_band():
    from vorobound.plotting import plot_reconstruct_draws

    spreads = {"Hausdorff": ([0.1, 0.5, None], [0.2, 0.9, None])}
    figure = plot_reconstruct_draws(
        [0.3, 0.4, 0.5], [1.0, 0.5, 0.0], spreads, (0.3, 0.5), [("tight", "ratio", 0.01)], "t"
    )
    top = figure.axes[0]
    assert list(top.get_lines()[0].get_ydata()) == [1.0, 0.5, 0.0]
    (band,) = top.patches
    if hasattr(band, "get_width"):  # a Rectangle (matplotlib ≥ 3.9)
        low, high = band.get_x(), band.get_x() + band.get_width()
    else:  # a Polygon
        corners = np.asarray(band.get_xy())
        low, high = corners[:, 0].min(), corners[:, 0].max()
    assert (low, high) == pytest.approx((0.3, 0.5), rel=1e-12)


@pytest.mark.parametrize("bad", ["0", "-3", str(2**64)])
def test_a_bad_slab_count_is_one_line_and_exit_2(run_cli, bad):
    code, stdout, stderr = run_cli("reconstruct", "--sphere", "1", "--eps", "0.3", "--slabs", bad)
    assert code == 2
    assert stderr.startswith("error:") and len(stderr.strip().splitlines()) == 1
    assert "slabs" in stderr


def test_slabs_in_python_and_json_mirror_the_option(run_cli):
    """--slabs 3 builds the same M̂ as --slabs 1 (the whole set), and says how many slabs it
    used; below WHOLE_SEEDS the default is the whole set. The slabs need the compiled steps:
    without numba (CI's floor run) the whole set is triangulated and the JSON says 1."""
    import vorobound
    from vorobound.sampling.simplices import kernel_available

    used = 3 if kernel_available() else 1

    code, stdout, stderr = run_cli(
        "reconstruct", "--sphere", "1", "--eps", "0.2", "--slabs", "3", "--json"
    )
    assert code == 0, stderr
    split = json.loads(stdout)
    whole = vorobound.reconstruct(sphere=1, eps=0.2, slabs=1).payload()
    default = vorobound.reconstruct(sphere=1, eps=0.2).payload()
    assert split["slabs"] == used and whole["slabs"] == 1 and default["slabs"] == 1
    assert split["params"]["slabs"] == 3 and default["params"]["slabs"] is None
    for key in KEYS | {"n_vertices", "collapsed_facets", "components"}:
        assert split[key] == whole[key] == default[key], key
