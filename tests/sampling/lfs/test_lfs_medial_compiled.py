"""The compiled pole pass of :func:`vertex_poles` (:mod:`.compiled_medial`, issue 35) gives the
numpy path's poles to the last bit: on a sampled torus, with patch labels, with the reliability
test of single-precision inputs, and on degenerate samples (a lattice, whose Delaunay
tetrahedra are slivers and flat ones without a circumcentre; a sphere, all of whose points are
cospherical)."""

import numpy as np
import pytest

from vorobound.geometry.kernels import pure_numpy
from vorobound.sampling.surfaces.demo_meshes import torus_mesh

pytest.importorskip("numba")
pytestmark = pytest.mark.skipif(pure_numpy(), reason="VOROBOUND_PURE_NUMPY: no compiled pass")


def _both(monkeypatch, points, normals, **options):
    """vertex_poles with the compiled pass and with the numpy path (the compiled nearest-site
    search in both, and the same tetrahedra: geogram's row order may change from run to run,
    and the farthest of equally far circumcentres is the one of highest row)."""
    from vorobound.sampling.lfs import medial

    triangulate = medial.delaunay_tetrahedra
    once = []

    def same_tetrahedra(moved):
        once.append(once[0] if once else triangulate(moved))
        return once[-1]

    with monkeypatch.context() as patch:
        patch.setattr(medial, "delaunay_tetrahedra", same_tetrahedra)
        compiled = medial.vertex_poles(points, normals, **options)
        patch.setattr(medial, "compiled_medial", lambda: None)
        plain = medial.vertex_poles(points, normals, **options)
    return compiled, plain


def _assert_same(compiled, plain):
    assert compiled.tetrahedra == plain.tetrahedra
    assert compiled.dropped == plain.dropped
    assert np.array_equal(compiled.points, plain.points)
    for name in ("owner_labels", "labelled_points", "labelled_reach"):
        mine, theirs = getattr(compiled, name), getattr(plain, name)
        assert (mine is None) == (theirs is None), name
        if mine is not None:
            assert np.array_equal(mine, theirs), name


def _torus(around=64, tube=20):
    mesh = torus_mesh(3.0, 1.0, around, tube, jitter=0.2, seed=1)
    points = mesh.points / 8.0
    ring = np.c_[mesh.points[:, :2], np.zeros(len(points))]
    ring *= 3.0 / np.linalg.norm(ring, axis=1)[:, None]
    return points, mesh.points - ring


def test_compiled_poles_of_a_torus_are_the_numpy_ones(monkeypatch):
    points, normals = _torus()
    compiled, plain = _both(monkeypatch, points, normals, seed=3)
    _assert_same(compiled, plain)
    assert len(compiled.points) > len(points) // 2  # poles were found: the test bites
    # Normals of the other sign: the sides swap.
    _assert_same(*_both(monkeypatch, points, -normals, seed=3))


def test_compiled_poles_with_labels_and_single_precision_are_the_numpy_ones(monkeypatch):
    """Four patches (quarters of the torus), each adjacent to the next; coordinates rounded to
    single precision with the matching noise, so the reliability test drops centres."""
    from vorobound.sampling.lfs.poles import rounding_error

    points, normals = _torus()
    points = points.astype(np.float32).astype(float)
    labels = ((np.arctan2(points[:, 1], points[:, 0]) + np.pi) // (np.pi / 2)).astype(np.int64)
    labels = np.minimum(labels, 3)
    adjacent = np.zeros((4, 4), dtype=bool)
    for k in range(4):
        adjacent[k, (k + 1) % 4] = adjacent[(k + 1) % 4, k] = True
    options = dict(noise=rounding_error(points), seed=1, labels=labels, adjacent=adjacent)
    compiled, plain = _both(monkeypatch, points, normals, **options)
    _assert_same(compiled, plain)
    assert compiled.labelled_points is not None and len(compiled.labelled_points)
    # Without adjacent patches, every candidate counts.
    options["adjacent"] = np.zeros((4, 4), dtype=bool)
    _assert_same(*_both(monkeypatch, points, normals, **options))


@pytest.mark.parametrize("seed", [0, 1])
def test_compiled_poles_of_degenerate_samples_are_the_numpy_ones(monkeypatch, seed):
    """A 7³ lattice (slivers, flat tetrahedra: many dropped) and a sphere's points."""
    from vorobound.sampling.lfs import medial

    grid = np.stack(np.meshgrid(*[np.linspace(-0.5, 0.5, 7)] * 3, indexing="ij"), -1)
    lattice = grid.reshape(-1, 3)
    normals = lattice + np.array([1e-3, 2e-3, 3e-3])
    compiled, plain = _both(monkeypatch, lattice, normals, seed=seed)
    _assert_same(compiled, plain)
    # Flat tetrahedra (no circumcentre) are among the lattice's.
    jitter = medial.JITTER * medial.nearest_spacing(lattice)
    moved = lattice + jitter[:, None] * np.random.default_rng(seed).standard_normal(lattice.shape)
    tets, _ = medial.delaunay_tetrahedra(moved)
    assert np.isnan(medial._circumcentres(lattice[tets])[0]).any()
    assert compiled.dropped > 0

    rng = np.random.default_rng(seed)
    sphere = rng.normal(size=(400, 3))
    sphere /= 2 * np.linalg.norm(sphere, axis=1)[:, None]
    labels = (sphere[:, 2] > 0).astype(np.int64)
    adjacent = np.array([[False, True], [True, False]])
    options = dict(seed=seed, labels=labels, adjacent=adjacent)
    _assert_same(*_both(monkeypatch, sphere, sphere, **options))


def test_compiled_consistency_drops_are_the_numpy_ones(monkeypatch):
    """An icosphere with relative noise 10⁻⁸ stored in single precision, its rounding not
    declared: some poles hold a sample, and the consistency test drops further circumcentres of
    their groups (counted here), in both paths alike."""
    from vorobound.sampling.lfs import medial
    from vorobound.sampling.surfaces.demo_meshes import icosphere

    points = icosphere(0.5, 4).points
    points = points * (1 + 1e-8 * np.random.default_rng(0).normal(size=(len(points), 1)))
    points = points.astype(np.float32).astype(float)
    dropped = []
    drop = medial._IncidentCandidates.drop

    def counted(self, points, centres, bound, group, witness, usable):
        before = int(usable.sum())
        drop(self, points, centres, bound, group, witness, usable)
        dropped.append(before - int(usable.sum()))

    monkeypatch.setattr(medial._IncidentCandidates, "drop", counted)
    _assert_same(*_both(monkeypatch, points, points, seed=0))
    assert sum(dropped) > 0
