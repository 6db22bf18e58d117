"""The smooth path of ``vorobound lfs`` made cheaper without changing its answers (issue 35):
the nearest allowed pole by a compiled box-tree walk, the pole check's exact sample distance
only where a face is near, CGAL's tetrahedra read in bulk."""

import numpy as np
import pytest
from scipy.spatial import Delaunay, cKDTree

from vorobound.sampling.surfaces.demo_meshes import torus_mesh


def _circle_poles(rng, count=4000, spread=1e-3):
    """Poles crowded around a circle (a torus's core: thousands at nearly one distance from a
    point of the tube), a few far ones, and a label (patch) of each."""
    angle = rng.uniform(0, 2 * np.pi, count)
    poles = np.c_[3 * np.cos(angle), 3 * np.sin(angle), np.zeros(count)]
    poles += spread * rng.normal(size=poles.shape)
    poles = np.vstack([poles, rng.normal(size=(50, 3)) * 4])
    return poles, rng.integers(0, 3, len(poles))


def test_compiled_nearest_allowed_pole_is_the_k_d_tree_answer():
    """Crowded poles, three patches, one of them allowing only another: the compiled walk's
    distance equals the k-d tree path's to the last bit, and the brute-force minimum."""
    pytest.importorskip("numba")
    from vorobound.sampling.lfs import poles as module
    from vorobound.sampling.lfs.compiled_poles import PoleTree

    rng = np.random.default_rng(2)
    points, labels = _circle_poles(rng)
    angle = rng.uniform(0, 2 * np.pi, 3000)
    tube = rng.uniform(0, 2 * np.pi, 3000)
    queries = np.c_[
        (3 + np.cos(tube)) * np.cos(angle), (3 + np.cos(tube)) * np.sin(angle), np.sin(tube)
    ]
    query_labels = rng.integers(0, 3, len(queries))
    allowed = np.array([[True, False, True], [False, True, True], [False, False, True]])
    distance, index = PoleTree(points, labels).nearest_allowed(queries, query_labels, allowed)
    gaps = np.linalg.norm(queries[:, None] - points[None], axis=2)
    gaps[~allowed[query_labels][:, labels]] = np.inf
    np.testing.assert_allclose(distance, gaps.min(axis=1), rtol=1e-15, atol=0)
    assert np.array_equal(gaps[np.arange(len(queries)), index], distance)
    assert allowed[query_labels, labels[index]].all()
    # The k-d tree path (numba switched off) gives the same distances, bit for bit.
    compiled = module.nearest_allowed_pole(points, labels, queries, query_labels, allowed)
    module_compiled = module.compiled_poles
    try:
        module.compiled_poles = lambda: None
        plain = module.nearest_allowed_pole(points, labels, queries, query_labels, allowed)
    finally:
        module.compiled_poles = module_compiled
    assert np.array_equal(compiled, plain)
    # No allowed pole: inf and −1.
    none = PoleTree(points, np.zeros(len(points), int)).nearest_allowed(
        queries[:5], np.ones(5, int), np.array([[True, False], [False, False]])
    )
    assert np.isinf(none[0]).all() and (none[1] == -1).all()


def test_compiled_nearest_site_takes_the_lowest_of_equally_near_sites():
    """Sites repeated exactly (the circumcentres of one cospherical set): the walk returns the
    brute-force distance and, of equal sites, the lowest index, as the cluster search does."""
    pytest.importorskip("numba")
    from vorobound.sampling.lfs.medial import nearest_site

    rng = np.random.default_rng(4)
    base = rng.normal(size=(30, 3))
    sites = np.vstack([base, base[::-1], rng.normal(size=(40, 3))])
    queries = rng.normal(size=(500, 3))
    distance, index = nearest_site(sites, queries)
    gaps = np.linalg.norm(queries[:, None] - sites[None], axis=2)
    np.testing.assert_allclose(distance, gaps.min(axis=1), rtol=1e-15, atol=0)
    lowest = np.argmax(gaps == gaps.min(axis=1)[:, None], axis=1)
    assert np.array_equal(index, lowest)


@pytest.mark.parametrize("seed", [0, 1])
def test_pole_check_with_the_corner_bound_keeps_the_same_poles(seed):
    """The pole check given an upper bound on each pole's distance to the sample (the nearest
    corner of its tetrahedron) keeps exactly the poles it keeps with the exact distance, on
    candidate centres some of which the mesh enters."""
    from vorobound.sampling.lfs.estimate import SHARP_ANGLE
    from vorobound.sampling.lfs.mesh_quality import prepare_mesh
    from vorobound.sampling.lfs.patches import find_patches
    from vorobound.sampling.lfs.poles import _checked_poles
    from vorobound.sampling.lfs.thickness import RayCaster

    prepared = prepare_mesh(torus_mesh(3.0, 1.0, 48, 16, jitter=0.2, seed=seed))
    patches = find_patches(prepared, SHARP_ANGLE)
    sample = prepared.points
    tets = Delaunay(sample).simplices
    rng = np.random.default_rng(seed)
    chosen = tets[rng.choice(len(tets), 1500, replace=False)]
    corners = sample[chosen]
    # Centres of random tetrahedra, moved so that some balls hold faces and others do not.
    centres = corners.mean(axis=1) + rng.normal(size=(len(chosen), 3)) * 0.02
    owners = np.zeros(len(centres), dtype=np.int64)
    reach = np.linalg.norm(corners - centres[:, None], axis=2).min(axis=1)
    assert (reach >= cKDTree(sample).query(centres)[0]).all()
    caster = RayCaster(prepared.points, prepared.triangles)
    exact = _checked_poles(centres, owners, sample, caster, patches)
    bounded = _checked_poles(centres, owners, sample, caster, patches, reach)
    assert exact is not None and bounded is not None
    assert 0 < len(exact[0]) < len(centres)  # some dropped, some kept
    assert np.array_equal(exact[0], bounded[0]) and np.array_equal(exact[1], bounded[1])


def test_bulk_tetrahedra_are_the_delaunay_triangulation():
    """The tetrahedra read in bulk from CGAL are qhull's Delaunay tetrahedra of the same
    jittered torus vertices (indices of the input), their neighbours those of qhull."""
    from vorobound.sampling.lfs.delaunay import delaunay_tetrahedra
    from vorobound.sampling.lfs.medial import JITTER, nearest_spacing

    points = torus_mesh(3.0, 1.0, 64, 24, jitter=0.2, seed=3).points
    rng = np.random.default_rng(0)
    moved = points + (JITTER * nearest_spacing(points))[:, None] * rng.normal(size=points.shape)
    tets, neighbours = delaunay_tetrahedra(moved)
    qhull = Delaunay(moved)
    assert {tuple(t) for t in np.sort(qhull.simplices, axis=1).tolist()} == {
        tuple(t) for t in tets.tolist()
    }
    # Across the face opposite each corner: the tetrahedron sharing the other three corners.
    for t in range(0, len(tets), 97):
        for corner in range(4):
            other = neighbours[t, corner]
            face = set(np.delete(tets[t], corner).tolist())
            if other < 0:
                continue
            assert face <= set(tets[other].tolist())
    assert (neighbours >= 0).sum() == (qhull.neighbors >= 0).sum()


def test_k_nearest_poles_are_the_brute_force_ones_in_order():
    """The k nearest by distance, then by lowest index, with repeated sites (ties), and −1/inf
    past the last pole."""
    pytest.importorskip("numba")
    from vorobound.sampling.lfs.compiled_poles import PoleTree

    rng = np.random.default_rng(5)
    base = rng.normal(size=(25, 3))
    sites = np.vstack([base, base[::-1], rng.normal(size=(50, 3))])
    queries = np.vstack([rng.normal(size=(400, 3)), base[:5]])
    tree = PoleTree(sites, np.zeros(len(sites), dtype=np.int64))
    distance, index = tree.k_nearest(queries, 6)
    gaps = np.linalg.norm(queries[:, None] - sites[None], axis=2)
    # The brute force in the same order: distance first, then the site's index.
    order = np.lexsort((np.broadcast_to(np.arange(len(sites)), gaps.shape), gaps), axis=1)[:, :6]
    assert np.array_equal(index, order)
    np.testing.assert_allclose(distance, np.take_along_axis(gaps, order, 1), rtol=1e-15, atol=0)
    few = PoleTree(sites[:3], np.zeros(3, dtype=np.int64)).k_nearest(queries[:4], 5)
    assert (few[1][:, 3:] == -1).all() and np.isinf(few[0][:, 3:]).all()
    assert (few[1][:, :3] >= 0).all()


def test_the_consistency_test_with_backups_keeps_the_same_poles(monkeypatch):
    """Samples that lose their nearest pole look among their next nearest first
    (``_Backups``); without them (every search over all poles) the poles are the same, to the
    last bit, on a torus where the test runs several rounds."""
    pytest.importorskip("numba")
    from vorobound.sampling.lfs import medial
    from vorobound.sampling.surfaces.demo_meshes import torus_mesh

    mesh = torus_mesh(3.0, 1.0, 200, 50, jitter=0.2, seed=1)
    points = mesh.points / 8.0
    ring = np.c_[mesh.points[:, :2], np.zeros(len(points))]
    normals = mesh.points - ring * (3.0 / np.linalg.norm(ring, axis=1)[:, None])
    triangulate, once = medial.delaunay_tetrahedra, []

    def same_tetrahedra(moved):  # both runs on the same tetrahedra in the same row order
        once.append(once[0] if once else triangulate(moved))
        return once[-1]

    backed = []
    take = medial._Backups.take

    def counting(self, *args):
        found = take(self, *args)
        backed.append(len(found[1]))
        return found

    with monkeypatch.context() as patch:
        patch.setattr(medial, "delaunay_tetrahedra", same_tetrahedra)
        patch.setattr(medial._Backups, "take", counting)
        fast = medial.vertex_poles(points, normals, seed=2)
        patch.setattr(medial, "compiled_poles", lambda: None)
        plain = medial.vertex_poles(points, normals, seed=2)
    assert sum(backed) > 0  # the backups were used: the test bites
    assert np.array_equal(fast.points, plain.points)
    assert fast.dropped == plain.dropped


@pytest.mark.parametrize("compiled", [True, False])
def test_nearest_poles_stay_the_brute_force_ones_round_after_round(monkeypatch, compiled):
    """Rounds that drop chosen poles and choose new ones: after each, every sample's pole is
    its nearest chosen one (brute force), whether it came from a backup, a new pole or a
    search again."""
    if compiled:
        pytest.importorskip("numba")
    from vorobound.sampling.lfs import medial

    if not compiled:
        monkeypatch.setattr(medial, "compiled_poles", lambda: None)
    rng = np.random.default_rng(7)
    centres = rng.normal(size=(1500, 3))
    points = rng.normal(size=(2000, 3)) * 0.8
    nearest, gap = np.full(len(points), -1), np.full(len(points), np.inf)
    backups = medial._Backups(len(points))
    chosen = np.zeros(0, dtype=np.int64)
    pool = rng.permutation(len(centres))
    current = np.sort(pool[:300])
    for round_ in range(6):
        new = np.setdiff1d(current, chosen, assume_unique=True)
        chosen = current
        medial._renew_nearest(points, centres, chosen, new, gap, nearest, backups, round_)
        gaps = np.linalg.norm(points[:, None] - centres[chosen][None], axis=2)
        assert np.array_equal(nearest, chosen[gaps.argmin(axis=1)]), round_
        np.testing.assert_allclose(gap, gaps.min(axis=1), rtol=1e-15, atol=0)
        # Drop the poles that are nearest to many samples (as the test drops failing ones),
        # and choose a few new ones.
        popular = np.unique(nearest[rng.random(len(points)) < 0.5])
        current = np.union1d(
            np.setdiff1d(chosen, popular), pool[300 + 200 * round_ : 500 + 200 * round_]
        )
    if compiled:
        assert (backups.round >= 0).any()
