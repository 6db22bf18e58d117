"""Mesh files are read by content where the suffix lies (issue 34: an OBJ named .stl was read
by meshio as STL, its ``f`` lines became vertices, and ``lfs`` returned an L for 6 vertices and
2 triangles, exit 0)."""

import json
import warnings

import meshio
import numpy as np
import pytest

from vorobound.errors import ReadError, VoroboundWarning
from vorobound.sampling.io.meshes import read_triangle_mesh
from vorobound.sampling.surfaces.demo_meshes import icosphere


@pytest.fixture
def sphere():
    return icosphere(1.0, 1)


def _write(mesh, path, file_format, **options):
    meshio.write(
        path,
        meshio.Mesh(mesh.points, [("triangle", mesh.triangles)]),
        file_format=file_format,
        **options,
    )


@pytest.mark.parametrize(
    ("file_format", "suffix", "options"),
    [
        ("obj", ".stl", {}),
        ("ply", ".obj", {}),
        ("stl", ".off", {"binary": True}),
        ("off", ".ply", {}),
        ("stl", ".obj", {"binary": False}),
    ],
)
def test_a_mesh_in_disguise_is_read_by_its_content_with_a_warning(
    sphere, tmp_path, file_format, suffix, options
):
    honest = tmp_path / f"s.{file_format}"
    _write(sphere, honest, file_format, **options)
    disguised = tmp_path / f"s{suffix}"
    disguised.write_bytes(honest.read_bytes())
    truth = read_triangle_mesh(honest)
    with pytest.warns(VoroboundWarning, match=f"holds {file_format.upper()}, not what its suffix"):
        read = read_triangle_mesh(disguised)
    assert len(read.triangles) == len(truth.triangles) == len(sphere.triangles)
    assert np.allclose(read.points, truth.points, rtol=0, atol=1e-6)


@pytest.mark.parametrize("binary", [True, False])
def test_an_honest_stl_is_read_without_a_word(sphere, tmp_path, binary):
    path = tmp_path / "s.stl"
    _write(sphere, path, "stl", binary=binary)
    with warnings.catch_warnings():
        warnings.simplefilter("error", VoroboundWarning)
        read = read_triangle_mesh(path)
    assert len(read.triangles) == len(sphere.triangles)


def test_a_file_named_stl_that_is_no_stl_is_refused_with_the_reason(tmp_path):
    path = tmp_path / "junk.stl"
    path.write_text("some text\n1 2 3\n")
    with pytest.raises(ReadError, match="not an STL file"):
        read_triangle_mesh(path)


def test_lfs_of_an_obj_named_stl_says_so_and_reads_the_obj(sphere, tmp_path, run_cli):
    obj = tmp_path / "s.obj"
    _write(sphere, obj, "obj")
    stl = tmp_path / "s.stl"
    stl.write_bytes(obj.read_bytes())
    code, out, err = run_cli("lfs", "--mesh", str(stl), "--json")
    assert code == 0, err
    assert "holds OBJ, not what its suffix .stl says" in err.splitlines()[0]
    payload = json.loads(out)
    assert payload["vertices"] == len(sphere.points)
    assert payload["triangles"] == len(sphere.triangles)
