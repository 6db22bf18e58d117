"""The compiled steps of M̂ (face neighbours, circumcentres, the walks around the in/out edges)
against the numpy steps and against qhull, on random, cospherical and lattice seeds."""

import numpy as np
import pytest

from vorobound.errors import InputError
from vorobound.sampling import simplices
from vorobound.sampling.reconstruct import facets
from vorobound.sampling.reconstruct.facets import inout_facets

pytest.importorskip("gudhi")
pytest.importorskip("numba")

VERTEX_ATOL = 1e-12
"""Facet vertices of the two paths agree to this (seeds of unit size): the circumcentre
formula is the same, only its rounding may differ."""


def _kernel():
    kernel = facets._facets_kernel()
    assert kernel is not None
    return kernel


def _same(compiled, plain):
    """The two results describe the same M̂: equal combinatorics, vertices within rounding."""
    one, two = compiled.surface, plain.surface
    np.testing.assert_array_equal(one.corners, two.corners)
    np.testing.assert_array_equal(one.offsets, two.offsets)
    np.testing.assert_array_equal(one.seed_pairs, two.seed_pairs)
    np.testing.assert_array_equal(compiled.unbounded, plain.unbounded)
    np.testing.assert_allclose(one.vertices, two.vertices, rtol=0, atol=VERTEX_ATOL)
    for name in ("collapsed", "unresolved", "non_simple", "delaunay_edges", "tetrahedra"):
        assert getattr(compiled, name) == getattr(plain, name), name


def _lattice(count: int) -> np.ndarray:
    """A cubic lattice of count³ points (every cell's eight corners cospherical)."""
    axis = np.arange(count, dtype=float)
    return np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), axis=-1).reshape(-1, 3)


def _sphere_pairs(rng) -> np.ndarray:
    """Points on two concentric spheres along the same 60 directions (cospherical sets)."""
    direction = rng.standard_normal((60, 3))
    direction /= np.linalg.norm(direction, axis=1, keepdims=True)
    return np.vstack([0.9 * direction, 1.1 * direction])


SEED_SETS = {
    "random": lambda rng: (rng.standard_normal((400, 3)), None),
    "lattice": lambda rng: (_lattice(6), None),
    "spheres": lambda rng: (_sphere_pairs(rng), None),
}


@pytest.mark.parametrize("name", sorted(SEED_SETS))
def test_compiled_steps_give_the_numpy_facets(name):
    """Seeds inside the unit ball (or the lattice's middle) against those outside: the same
    facets, cycles, unbounded facets and counts from both paths, and the same pairs as qhull's."""
    rng = np.random.default_rng(11)
    points, _ = SEED_SETS[name](rng)
    centre = points.mean(axis=0)
    radius = np.median(np.linalg.norm(points - centre, axis=1))
    inside = np.linalg.norm(points - centre, axis=1) < radius
    compiled = inout_facets(points, inside, compiled=True)
    plain = inout_facets(points, inside, compiled=False)
    _same(compiled, plain)
    assert compiled.surface.n_facets > 0
    qhull = inout_facets(points, inside, triangulation="qhull", compiled=True)
    assert {tuple(p) for p in qhull.surface.seed_pairs} <= {
        tuple(p) for p in compiled.surface.seed_pairs
    } | {tuple(p) for p in compiled.unbounded}
    if name == "random":  # general position: one triangulation, the same facets
        assert {tuple(p) for p in qhull.surface.seed_pairs} == {
            tuple(p) for p in compiled.surface.seed_pairs
        }


def test_seeds_on_the_hull_give_the_same_unbounded_facets():
    """Labels split by a plane: the in/out edges on the convex hull have unbounded facets, found
    by both walks (the compiled one marks the rest of each open fan)."""
    rng = np.random.default_rng(5)
    points = rng.random((300, 3))
    inside = points[:, 0] < 0.5
    compiled = inout_facets(points, inside, compiled=True)
    plain = inout_facets(points, inside, compiled=False)
    assert len(compiled.unbounded) > 0
    _same(compiled, plain)


def test_compiled_face_neighbours_are_the_numpy_ones():
    """On a random and on a lattice (cospherical) triangulation; and a face of three
    tetrahedra is refused."""
    kernel = _kernel()
    for points in (np.random.default_rng(2).random((2000, 3)), _lattice(7)):
        _, tets, _ = simplices.delaunay_simplices(points, triangles=False, compiled=False)
        mine, ok = kernel.face_neighbours(tets, len(points))
        assert ok
        np.testing.assert_array_equal(mine, simplices.face_neighbours(tets))
    _, ok = kernel.face_neighbours(np.array([[0, 1, 2, 3], [0, 1, 2, 4], [0, 1, 2, 5]]), 6)
    assert not ok


def test_compiled_circumcentres_match_the_numpy_formula():
    kernel = _kernel()
    rng = np.random.default_rng(4)
    points = np.vstack([rng.random((500, 3)), _lattice(2)])
    _, tets, _ = simplices.delaunay_simplices(points, triangles=False, compiled=False)
    # Flat ones too: the four corners of a face of the unit cube (cocircular, coplanar).
    tets = np.vstack([tets, 500 + np.array([[0, 1, 2, 3], [0, 1, 4, 5], [0, 2, 4, 6]])])
    centres, error, flat = kernel.circumcentres(
        points, tets, facets.ROUNDING_FACTOR, facets.FLAT_RTOL
    )
    want_centres, want_error, want_flat = facets._circumcentres(points[tets])
    np.testing.assert_array_equal(flat, want_flat)
    assert flat[-3:].all() and not flat[:-3].any()
    good = ~flat
    np.testing.assert_allclose(centres[good], want_centres[good], rtol=0, atol=1e-12)
    np.testing.assert_allclose(error[good], want_error[good], rtol=1e-12)


def test_an_inconsistent_triangulation_is_refused():
    """A neighbour table that does not close the walk around an edge is an input error."""
    kernel = _kernel()
    points = np.random.default_rng(8).random((50, 3))
    inside = points[:, 2] < 0.5
    _, tets, _ = simplices.delaunay_simplices(points, triangles=False, compiled=False)
    neighbors, _ = kernel.face_neighbours(tets, len(points))
    broken = neighbors.copy()
    inner = np.flatnonzero((broken >= 0).all(axis=1))[0]
    broken[inner] = inner  # every face leads back to itself
    with pytest.raises(InputError, match="inconsistent"):
        facets._compiled_cycles(kernel, points, tets, broken, inside)


def test_compiled_true_without_numba_is_refused(monkeypatch):
    monkeypatch.setenv("VOROBOUND_PURE_NUMPY", "1")
    points = np.random.default_rng(0).random((20, 3))
    with pytest.raises(InputError, match="numba"):
        inout_facets(points, points[:, 0] < 0.5, compiled=True)
    plain = inout_facets(points, points[:, 0] < 0.5)  # None: numpy where numba is off
    assert plain.delaunay_edges > 0


def test_dense_unique_is_numpys_unique():
    values = np.random.default_rng(6).integers(0, 50, 300)
    unique, inverse = facets.dense_unique(values, 60)
    want, want_inverse = np.unique(values, return_inverse=True)
    np.testing.assert_array_equal(unique, want)
    np.testing.assert_array_equal(inverse, want_inverse)
    empty, none = facets.dense_unique(np.empty(0, dtype=np.int64), 5)
    assert len(empty) == len(none) == 0
