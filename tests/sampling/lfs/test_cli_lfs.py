"""``vorobound lfs`` from the command line: outputs that round-trip, warnings, bad input."""

import json

import meshio
import numpy as np
import pytest

from vorobound.sampling.io.meshes import read_sizing, read_triangle_mesh
from vorobound.sampling.lfs.estimate import AUTO_SAMPLES
from vorobound.sampling.surfaces import analytic as surfaces
from vorobound.sampling.surfaces.demo_meshes import cube_mesh, torus_mesh


def write_mesh(path, mesh):
    meshio.write(path, meshio.Mesh(mesh.points, [("triangle", mesh.triangles)]))
    return str(path)


@pytest.fixture(scope="module")
def torus_stl(tmp_path_factory):
    return write_mesh(tmp_path_factory.mktemp("lfs") / "torus.stl", torus_mesh(3.0, 1.0, 96, 32))


def test_json_and_both_outputs(run_cli, torus_stl, tmp_path):
    csv_path, vtu_path = tmp_path / "l.csv", tmp_path / "l.vtu"
    code, out, err = run_cli("lfs", torus_stl, "-o", str(csv_path), "-o", str(vtu_path), "--json")
    assert code == 0, err
    data = json.loads(out)
    assert data["vertices"] == 96 * 32 and data["sharp_edges"] == 0 and data["warnings"] == []
    assert data["samples"] == 4 * 96 * 32 and data["added_samples"] == 3 * 96 * 32
    assert data["lfs_min"] == pytest.approx(1.0, rel=0.01)
    mesh = read_triangle_mesh(torus_stl)  # single precision, as STL stores it
    sizing = read_sizing(csv_path, len(mesh.points))
    exact = surfaces.TorusShape(3.0, 1.0).lfs_at(mesh.points)
    assert np.median(np.abs(sizing / exact - 1)) < 1e-3
    vtu = meshio.read(vtu_path)
    assert np.allclose(vtu.point_data["lfs"], sizing)
    assert vtu.point_data["sharp"].sum() == 0


def test_samples_zero_uses_the_vertices_only(run_cli, torus_stl):
    code, out, err = run_cli("lfs", torus_stl, "--samples", "0", "--json")
    assert code == 0, err
    data = json.loads(out)
    assert data["samples"] == 96 * 32 and data["added_samples"] == 0
    assert "edge midpoints" not in data["method"]


def test_help_states_the_library_default(run_cli):
    code, out, _ = run_cli("lfs", "--help")
    assert code == 0
    assert f"at most {AUTO_SAMPLES} points" in " ".join(out.replace("│", " ").split())


def test_table_for_people(run_cli, torus_stl):
    # From the vertices only: the table is what is tested (the default sample, 3 CPU-s more,
    # is test_json_and_both_outputs').
    code, out, _ = run_cli("lfs", torus_stl, "--lipschitz", "0.5", "--samples", "0")
    assert code == 0
    assert "Local feature size" in out and "Voronoi poles" in out


def test_cube_warns_about_sharp_edges(run_cli, tmp_path):
    path = write_mesh(tmp_path / "cube.obj", cube_mesh(1.0, 3))
    code, out, err = run_cli("lfs", path, "--json")
    assert code == 0
    data = json.loads(out)
    assert data["sharp_edges"] == 36 and data["patches"] == 6 and data["feature_corners"] == 8
    assert data["lfs_max"] == pytest.approx(1.0, rel=1e-6)  # half the side: no 50x overshoot
    assert "warning:" in err and "piecewise-smooth" in err


@pytest.mark.parametrize(
    "args",
    [
        ("missing.stl",),
        ("{mesh}", "-o", "{dir}/l.txt"),
        ("{mesh}", "--lipschitz", "0"),
        ("{mesh}", "--lipschitz", "nan"),
        ("{mesh}", "--sharp-angle", "200"),
        ("{mesh}", "--samples", "-1"),
        ("{mesh}", "--samples", "many"),
    ],
)
def test_bad_arguments_exit_2_with_one_line(run_cli, torus_stl, tmp_path, args):
    filled = [a.format(mesh=torus_stl, dir=tmp_path) for a in args]
    code, out, err = run_cli("lfs", *filled)
    assert code == 2 and out == ""
    assert err.startswith("error:") and err.count("\n") == 1


def test_nan_and_flat_meshes_exit_2(run_cli, tmp_path):
    nan_path = tmp_path / "nan.obj"
    nan_path.write_text("v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n")
    flat = cube_mesh(1.0, 2)
    top = flat.points[flat.triangles].mean(axis=1)[:, 2] > 0.999
    flat_path = tmp_path / "flat.obj"
    meshio.write(flat_path, meshio.Mesh(flat.points, [("triangle", flat.triangles[top])]))
    for path in (nan_path, flat_path):
        code, out, err = run_cli("lfs", str(path))
        assert code == 2 and out == "" and err.splitlines()[-1].startswith("error:")
