"""CGAL's triangulations read in bulk: the compiled reader of GUDHI's serialized simplex tree
against GUDHI's own iterator, and the face neighbours against qhull's."""

import numpy as np
import pytest

from vorobound.sampling import simplices

pytest.importorskip("gudhi")


def _rows(array):
    return {tuple(row) for row in np.sort(array, axis=1)}


@pytest.mark.parametrize("weighted", [False, True], ids=["delaunay", "regular"])
def test_compiled_reader_gives_the_iterators_simplices(weighted):
    pytest.importorskip("numba")
    import gudhi

    rng = np.random.default_rng(3)
    points = rng.random((3000, 3))
    weights = 1e-4 * rng.random(3000) if weighted else None
    tree = gudhi.DelaunayComplex(points=points, weights=weights).create_simplex_tree()
    fast_tri, fast_tet = simplices.tree_simplices(tree, compiled=True)
    slow_tri, slow_tet = simplices.tree_simplices(tree, compiled=False)
    counts = tree.num_simplices_by_dimension()
    assert len(fast_tri) == counts[2] and len(fast_tet) == counts[3]
    np.testing.assert_array_equal(fast_tri, slow_tri)
    np.testing.assert_array_equal(fast_tet, slow_tet)
    only, _ = simplices.tree_simplices(tree, compiled=True, tetrahedra=False)
    np.testing.assert_array_equal(only, slow_tri)
    _, none = simplices.tree_simplices(tree, compiled=False, tetrahedra=False)
    assert none.shape == (0, 4)


def test_a_layout_the_reader_does_not_know_falls_back_to_the_iterator(monkeypatch):
    """Bytes cut short (as another GUDHI version's layout would read): the counts disagree,
    and the iterator gives the simplices."""
    pytest.importorskip("numba")
    import gudhi

    tree = gudhi.DelaunayComplex(points=np.random.default_rng(0).random((200, 3)))
    tree = tree.create_simplex_tree()
    kernel = simplices._load_kernel()
    assert simplices._read_compiled(tree, True, True) is not None
    real = kernel.read_tree
    monkeypatch.setattr(kernel, "read_tree", lambda data, a, b: real(data[:-40], a, b))
    assert simplices._read_compiled(tree, True, True) is None
    tri, tet = simplices.tree_simplices(tree, compiled=True)
    assert len(tet) == tree.num_simplices_by_dimension()[3]


def test_face_neighbours_match_qhull():
    from scipy.spatial import Delaunay

    points = np.random.default_rng(1).standard_normal((500, 3))
    _, tets, vertices = simplices.delaunay_simplices(points, triangles=False)
    assert vertices == 500
    qhull = Delaunay(points)
    assert _rows(tets) == _rows(qhull.simplices)
    mine = simplices.face_neighbours(tets)
    # Each neighbour shares the face opposite the corner, and the hull faces agree in number.
    for t in range(len(tets)):
        for k in range(4):
            other = mine[t, k]
            if other >= 0:
                assert set(tets[t]) - {tets[t, k]} <= set(tets[other])
    assert (mine < 0).sum() == (qhull.neighbors < 0).sum()
    # Shuffled corners give the same neighbours, at the right corners.
    shuffled = np.random.default_rng(2).permuted(tets, axis=1)
    again = simplices.face_neighbours(shuffled)
    for t in range(0, len(tets), 7):
        for k in range(4):
            match = int(np.flatnonzero(shuffled[t] == tets[t, k])[0])
            assert again[t, match] == mine[t, k]


def test_a_face_of_three_tetrahedra_is_no_triangulation():
    tets = np.array([[0, 1, 2, 3], [0, 1, 2, 4], [0, 1, 2, 5]])
    assert simplices.face_neighbours(tets) is None


def test_the_counts_without_gudhis_own_count_are_the_same():
    """GUDHI 3.11 (the declared floor) has no num_simplices_by_dimension: one pass over the
    skeleton gives the same counts."""
    import gudhi

    points = np.random.default_rng(3).normal(size=(60, 3))
    tree = gudhi.DelaunayComplex(points=points).create_simplex_tree()

    class Old:  # the 3.11 interface: no count by dimension
        def get_skeleton(self, dimension):
            return tree.get_skeleton(dimension)

    assert simplices._counts_by_dimension(Old())[:4] == simplices._counts_by_dimension(tree)[:4]
    assert simplices._counts_by_dimension(Old())[2] > 0
