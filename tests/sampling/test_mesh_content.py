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


TETRAHEDRON = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]])
TET_FACES = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


def _pinched_pair():
    """Two tetrahedra touching at the origin (vertex 0 of both)."""
    points = np.vstack([TETRAHEDRON, -TETRAHEDRON[1:]])
    faces = np.vstack([TET_FACES, np.where(TET_FACES == 0, 0, TET_FACES + 3)])
    return points, faces


def test_two_tetrahedra_touching_at_a_vertex_are_refused_by_lfs(tmp_path, run_cli):
    """lfs exited 0 without a word, and L at the pinch (true value 0) was the largest."""
    points, faces = _pinched_pair()
    path = tmp_path / "pinch.obj"
    meshio.write(path, meshio.Mesh(points, [("triangle", faces)]))
    code, out, err = run_cli("lfs", "--mesh", str(path), "--json")
    assert code == 2 and out == ""
    assert "touch at a point" in err and "(0, 0, 0)" in err
    assert len(err.strip().splitlines()) == 1


def test_pinched_vertices_are_found_and_only_they():
    from vorobound.sampling.io.meshes import TriangleMesh
    from vorobound.sampling.lfs.mesh_quality import prepare_mesh
    from vorobound.sampling.surfaces.demo_meshes import cube_mesh

    points, faces = _pinched_pair()
    prepared = prepare_mesh(TriangleMesh(points, faces, "pinch"))
    (pinch,) = prepared.report.pinched_vertices
    assert np.allclose(prepared.centre + prepared.scale * prepared.points[pinch], 0, atol=1e-12)
    for clean in (icosphere(1.0, 2), cube_mesh(1.0, 3), TriangleMesh(TETRAHEDRON, TET_FACES, "t")):
        assert len(prepare_mesh(clean).report.pinched_vertices) == 0
    # An open fan (a boundary vertex) is one fan, not a pinch.
    fan = TriangleMesh(TETRAHEDRON, TET_FACES[:3], "fan")
    assert len(prepare_mesh(fan).report.pinched_vertices) == 0
