"""The mesh object (vorobound.mesh): derived data computed once and cached, the L estimate
cached on it, the nearest point of an allowed label."""

import numpy as np
import pytest
from scipy.spatial import cKDTree

from vorobound.mesh import TriangleMesh
from vorobound.mesh.nearest import nearest_allowed
from vorobound.sampling.io.meshes import read_triangle_mesh
from vorobound.sampling.lfs import estimate as estimate_module
from vorobound.sampling.surfaces import cad_meshes, demo_meshes


@pytest.fixture
def bracket():
    return cad_meshes.l_bracket()


def test_the_derived_data_is_what_its_definition_says(bracket):
    points, faces = bracket.points, bracket.triangles
    pairs = {
        tuple(sorted(p)) for f in faces.tolist() for p in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0]))
    }
    assert [tuple(e) for e in bracket.edges.tolist()] == sorted(pairs)
    lengths = {e: np.linalg.norm(points[e[0]] - points[e[1]]) for e in pairs}
    longest_at = np.zeros(len(points))
    for (a, b), length in lengths.items():
        longest_at[a] = max(longest_at[a], length)
        longest_at[b] = max(longest_at[b], length)
    assert np.allclose(bracket.vertex_longest_edge, longest_at, rtol=1e-15, atol=0)
    per_face = [
        max(lengths[tuple(sorted(p))] for p in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0])))
        for f in faces.tolist()
    ]
    assert np.allclose(bracket.longest_edges, per_face, rtol=1e-15, atol=0)
    used = np.unique(faces)
    assert all(v in faces[bracket.vertex_face[v]] for v in used)
    labels = np.arange(len(faces)) % 3
    table = bracket.vertex_label_table(labels)
    for v in used[:50]:
        mine = sorted(set(labels[np.flatnonzero((faces == v).any(axis=1))].tolist()))
        assert table[v][table[v] >= 0].tolist() == mine
    assert (bracket.vertex_labels(labels)[used] == labels[bracket.vertex_face[used]]).all()
    assert bracket.kdtree.query(points[:5])[0].max() == 0


def test_derived_data_is_computed_once(bracket):
    assert bracket.edges is bracket.edges and bracket.kdtree is bracket.kdtree
    calls = []
    assert bracket.cached("key", lambda: calls.append(1) or 7) == 7
    assert bracket.cached("key", lambda: calls.append(1) or 8) == 7
    assert calls == [1]


@pytest.mark.filterwarnings("ignore::vorobound.errors.VoroboundWarning")
def test_the_l_estimate_is_cached_on_the_mesh_object(monkeypatch):
    calls = []
    compute = estimate_module._estimate

    def counting(*args):
        calls.append(args[1:5])
        return compute(*args)

    monkeypatch.setattr(estimate_module, "_estimate", counting)
    mesh = demo_meshes.cube_mesh(1.0, 2)
    first = estimate_module.estimate_lfs(mesh)
    assert estimate_module.estimate_lfs(mesh) is first  # sample, advise, check: one estimate
    assert read_triangle_mesh(mesh) is mesh  # a mesh object passes through the reader
    other = estimate_module.estimate_lfs(mesh, lipschitz=0.5)
    assert other is not first and other.lipschitz == 0.5
    again = estimate_module.estimate_lfs(demo_meshes.cube_mesh(1.0, 2))  # a new object
    assert np.array_equal(again.lfs, first.lfs)
    assert len(calls) == 3


def test_nearest_allowed_is_the_nearest_point_of_an_allowed_label():
    rng = np.random.default_rng(5)
    points = rng.random((400, 3))
    labels = rng.integers(0, 6, len(points))
    queries = rng.random((300, 3))
    query_labels = rng.integers(0, 6, len(queries))
    allowed = rng.random((6, 6)) < 0.3
    allowed[0] = False  # label 0 allows nothing: no point found

    def ok(rows, index):
        return allowed[query_labels[rows][:, None], labels[index]]

    for neighbours in ((2, 8), (1, 4, 16, len(points))):
        distance, index = nearest_allowed(cKDTree(points), queries, ok, neighbours)
        full = np.linalg.norm(queries[:, None] - points[None], axis=2)
        full[~allowed[query_labels][:, labels]] = np.inf
        best = full.min(axis=1)
        found = index >= 0
        assert found.sum() > 100 and not found[query_labels == 0].any()
        assert np.array_equal(distance[found], best[found])
        assert np.array_equal(full[found, index[found]], best[found])
        if neighbours[-1] == len(points):  # every allowed point was reachable
            assert np.array_equal(found, np.isfinite(best))
        for pairs in (1, 7, 50):  # queries in chunks of pairs // k: the same answers
            chunked = nearest_allowed(cKDTree(points), queries, ok, neighbours, pairs)
            assert np.array_equal(chunked[0], distance)
            assert np.array_equal(chunked[1], index)
        assert (distance[~found] == np.inf).all()


def test_a_mesh_is_frozen():
    mesh = TriangleMesh(np.eye(3), np.array([[0, 1, 2]]), "one")
    with pytest.raises(AttributeError):
        mesh.points = np.zeros((3, 3))


def test_a_cached_estimate_warns_as_a_computed_one_at_the_callers_line():
    from vorobound.errors import VoroboundWarning, forget_warnings

    mesh = demo_meshes.cube_mesh(1.0, 2)
    for _ in range(2):  # computed, then taken from the mesh object
        forget_warnings()
        with pytest.warns(VoroboundWarning, match="sharp edges") as caught:
            estimate_module.estimate_lfs(mesh)
        assert {w.filename for w in caught} == {__file__}


def test_the_api_estimates_l_once_for_sample_advise_and_check_on_one_mesh(monkeypatch, tmp_path):
    """In Python, sample, then advise, then check on one mesh object estimate L once (each
    estimated it again from the file before)."""
    import warnings

    import vorobound

    calls = []
    compute = estimate_module._estimate
    monkeypatch.setattr(
        estimate_module, "_estimate", lambda *a, **k: calls.append(1) or compute(*a, **k)
    )
    mesh = cad_meshes.cube()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the cube's sharp edges
        vorobound.sample(eps=0.2, mesh=mesh, output=tmp_path / "s.csv")
        advice = vorobound.advise(mesh=mesh)
        checked = vorobound.check(eps=0.2, mesh=mesh, balls=tmp_path / "s.csv")
    assert len(calls) == 1
    # A mesh object is named in the JSON as a file would be, and the JSON stays JSON.
    import json

    assert "mesh cube" in json.dumps(advice.to_dict())
    assert json.loads(json.dumps(checked.to_dict()))["n_guide_triangles"] > 0


def test_the_api_refuses_what_is_neither_a_path_nor_a_mesh():
    import vorobound
    from vorobound.errors import InputError

    with pytest.raises(InputError, match="mesh"):
        vorobound.sample(eps=0.2, mesh=np.zeros((3, 3)), output="x.csv")
