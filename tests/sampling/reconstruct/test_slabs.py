"""M̂ from overlapping slabs of the seeds against M̂ from the whole set: the same facets, bit for
bit, on VoroCrust seeds (cospherical by construction), random, lattice and sphere seeds; the
fall-backs to the whole set."""

import numpy as np
import pytest

from vorobound.bounds.params import QualityParams, SamplingParams
from vorobound.errors import InputError
from vorobound.reports.reconstruct import reconstruct_balls
from vorobound.sampling.balls import make_balls
from vorobound.sampling.reconstruct import facets, slabs
from vorobound.sampling.reconstruct.facets import inout_facets
from vorobound.sampling.reconstruct.topology import surface_topology
from vorobound.sampling.sampler.maximal import sample_surface
from vorobound.sampling.surfaces.analytic import SphereShape, TorusShape

pytest.importorskip("gudhi")
pytest.importorskip("numba")

QUALITY = QualityParams()


def _voro_seeds(shape, eps):
    sample = sample_surface(shape, eps, QUALITY.sigma, 0)
    balls = make_balls(sample.points, QUALITY.delta_ratio * eps * sample.lfs)
    report = reconstruct_balls(balls, SamplingParams(eps, QUALITY), shape)
    return report.seeds.points, report.seeds.inside


def _lattice(count):
    axis = np.arange(count, dtype=float)
    return np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), axis=-1).reshape(-1, 3)


def _ball_labels(points):
    """Inside: a ball about the middle, away from the hull (no unbounded facet)."""
    centre = points.mean(axis=0)
    distance = np.linalg.norm(points - centre, axis=1)
    return distance < 0.4 * distance.max()


SEED_SETS = {
    "torus": lambda rng: _voro_seeds(TorusShape(3, 1), 0.2),
    "sphere": lambda rng: _voro_seeds(SphereShape(1), 0.15),
    "random": lambda rng: (p := rng.standard_normal((3000, 3)), _ball_labels(p)),
    "lattice": lambda rng: (p := _lattice(12), _ball_labels(p)),
}


def _same(one, two):
    """Equal M̂: polygons, vertices (bit for bit), seed pairs and counts."""
    for name in ("corners", "offsets", "seed_pairs", "vertices", "normals"):
        np.testing.assert_array_equal(getattr(one.surface, name), getattr(two.surface, name))
    np.testing.assert_array_equal(one.unbounded, two.unbounded)
    for name in ("collapsed", "unresolved", "non_simple", "skipped_seeds", "duplicate_seeds"):
        assert getattr(one, name) == getattr(two, name), name
    assert one.delaunay_edges == two.delaunay_edges


_WHOLE: dict = {}
"""Each seed set and M̂ of it in one piece, made once for both slab counts below."""


def _whole_set(name):
    if name not in _WHOLE:
        points, inside = SEED_SETS[name](np.random.default_rng(3))
        _WHOLE[name] = points, inside, inout_facets(points, inside, slabs=1)
    return _WHOLE[name]


@pytest.mark.parametrize("name", sorted(SEED_SETS))
@pytest.mark.parametrize("count", [2, 5])
def test_slabs_give_the_whole_sets_facets(name, count, monkeypatch):
    """Slabs of a few hundred seeds each build M̂ of the whole set exactly."""
    points, inside, whole = _whole_set(name)
    calls = []
    real = slabs._merged
    monkeypatch.setattr(slabs, "_merged", lambda *a: calls.append(a) or real(*a))
    split = inout_facets(points, inside, slabs=count)
    assert calls, "the slabs fell back to the whole set"
    _same(split, whole)
    assert whole.surface.n_facets > 0
    if name in ("torus", "sphere"):
        assert surface_topology(split.surface).closed_manifold


def test_edges_left_out_by_a_narrow_window_are_built_in_boxes(monkeypatch):
    """A probe that measures too short a reach leaves windows too narrow: the edges whose balls
    leave them are built in boxes with wider margins, and M̂ is still the whole set's."""
    points, inside = SEED_SETS["torus"](None)
    real_probe = slabs._probe_reach
    monkeypatch.setattr(slabs, "_probe_reach", lambda *a: 0.05 * real_probe(*a))
    calls = []
    real = slabs._slab
    monkeypatch.setattr(slabs, "_slab", lambda *a: calls.append(a) or real(*a))
    split = inout_facets(points, inside, slabs=3)
    boxes = [a for a in calls if len(a) > 6]
    assert boxes, "no edge was left out"
    assert max(a[4] for a in boxes) > calls[-len(boxes) - 1][4]
    _same(split, inout_facets(points, inside, slabs=1))


def test_an_edge_on_the_hull_falls_back_to_the_whole_set():
    """Labels split by a plane: in/out edges on the hull have unbounded facets, which no slab
    can certify; the whole set is triangulated and the unbounded facets are listed."""
    rng = np.random.default_rng(5)
    points = rng.random((600, 3))
    inside = points[:, 0] < 0.5
    kernel = facets._facets_kernel()
    frame = (points - facets.seed_frame(points)[0]) / facets.seed_frame(points)[1]
    assert slabs.slab_fans(frame, inside, kernel, facets.flat_circumcentres, 3) is None
    split = inout_facets(points, inside, slabs=3)
    assert len(split.unbounded) > 0
    _same(split, inout_facets(points, inside, slabs=1))


@pytest.mark.parametrize("bad", [0, -2, 1.5, True, "3"])
def test_a_bad_slab_count_is_refused(bad):
    points = np.random.default_rng(0).random((50, 3))
    with pytest.raises(InputError, match="slabs"):
        inout_facets(points, points[:, 0] < 0.5, slabs=bad)


def test_slab_count_follows_the_seeds():
    assert slabs.slab_count(10) == 1
    assert slabs.slab_count(slabs.WHOLE_SEEDS) == 1
    above = slabs.WHOLE_SEEDS + 1
    assert slabs.slab_count(above) == -(-above // slabs.SLAB_SEEDS) > 1


def _part(centre, required=()):
    """A slab's part holding tetrahedron (0, 1, 2, 3) around the in/out edge (0, 1)."""
    return slabs._SlabPart(
        quads=np.array([[0, 1, 2, 3]]),
        centres=np.array([centre], dtype=float),
        radius=np.ones(1),
        error=np.zeros(1),
        flat=np.zeros(1, dtype=bool),
        inner=np.array([0]),
        outer=np.array([1]),
        lengths=np.array([1]),
        corners=np.array([0]),
        required=np.array(required, dtype=np.int64),
        tetrahedra=1,
    )


def test_the_merge_refuses_disagreeing_or_incomplete_slabs():
    """Two slabs with different circumcentres for one tetrahedron, or an in/out edge of a kept
    tetrahedron that no slab built, send the caller back to the whole set (None)."""
    present = np.ones(4, dtype=bool)
    merged = slabs._merged([_part([0, 0, 0]), _part([0, 0, 0])], present, 4, 2)
    assert merged is not None and len(merged.centres) == 1
    assert slabs._merged([_part([0, 0, 0]), _part([1, 0, 0])], present, 4, 2) is None
    missing = 2 * 4 + 3  # the key of edge (2, 3): no part built it
    assert slabs._merged([_part([0, 0, 0], [missing])], present, 4, 1) is None
    assert slabs._merged([_part([0, 0, 0], [1])], present, 4, 1) is not None


def _patch_seeds(rng):
    """An inside patch (3 × 3 seeds, 2 apart, in the plane x = 0.5) between outside planes at
    x = −5.5, −3.5, −1.5, 2.5, 4.5, 6.5 (5 × 5 seeds, 2 apart): every in/out Delaunay edge
    joins the patch to a plane 2 away along x, and the outside seeds hold the hull."""
    grid = np.arange(-4.0, 4.01, 2.0)
    plane = np.stack(np.meshgrid(grid, grid, indexing="ij"), axis=-1).reshape(-1, 2)
    patch = plane[(np.abs(plane) <= 2).all(axis=1)]
    rows, labels = [], []
    for x, yz, label in [(0.5, patch, True)] + [
        (x, plane, False) for x in (-5.5, -3.5, -1.5, 2.5, 4.5, 6.5)
    ]:
        rows.append(np.column_stack([np.full(len(yz), x), yz]))
        labels.append(np.full(len(yz), label))
    points = np.concatenate(rows)
    return points + rng.uniform(-0.01, 0.01, points.shape), np.concatenate(labels)


def test_a_component_no_window_holds_is_not_lost(monkeypatch):
    """Cores cut at x = −1.6, 0.4, 0.6, 2.6 with a margin of 0.05: no window holds both seeds
    of any in/out edge of the patch, so no slab sees its facets (a closed component of M̂).
    The rule before the certificate built M̂ without them; the certificate (the seeds are not
    connected through certified edges) sends the whole set to CGAL, and M̂ is the whole set's."""
    points, inside = _patch_seeds(np.random.default_rng(1))
    whole = inout_facets(points, inside, slabs=1)
    assert whole.surface.n_facets > 0 and len(whole.unbounded) == 0
    unit = facets.seed_frame(points)[1]
    assert np.array_equal(facets.seed_frame(points)[0], np.zeros(3))
    monkeypatch.setattr(slabs, "_cuts", lambda x, n: np.array([-1.6, 0.4, 0.6, 2.6]) / unit)
    monkeypatch.setattr(slabs, "_probe_reach", lambda *a: 0.04 / unit)
    calls = []
    real = slabs._merged
    monkeypatch.setattr(slabs, "_merged", lambda *a: calls.append(a) or real(*a))
    _same(inout_facets(points, inside, slabs=5), whole)
    assert not calls, "the slabs did not see the gap"
    # Without the certificate's checks 3 and 4 (the rule before), the patch is lost.
    monkeypatch.setattr(slabs, "_complete", lambda *a: True)
    blind = inout_facets(points, inside, slabs=5)
    assert calls, "the slabs fell back for another reason"
    assert blind.surface.n_facets < whole.surface.n_facets


def _sparse_pairs(rng):
    """Dense VoroCrust seeds of a sphere, and far-apart seeds of both labels around it inside
    a box of outside seeds (long in/out edges, large empty balls)."""
    points, inside = _voro_seeds(SphereShape(1), 0.15)
    loose = rng.uniform(-3, 3, (60, 3))
    loose = loose[np.linalg.norm(loose, axis=1) > 1.5]
    grid = np.arange(-4.0, 4.01, 2.0)
    box = np.stack(np.meshgrid(grid, grid, grid, indexing="ij"), axis=-1).reshape(-1, 3)
    box = box[(np.abs(box) == 4).any(axis=1)] + rng.uniform(-0.01, 0.01, (98, 3))
    points = np.concatenate([points, loose, box])
    labels = np.concatenate([inside, rng.random(len(loose)) < 0.5, np.zeros(len(box), bool)])
    return points, labels


def _shells(rng):
    """Cospherical seeds: icosahedron-like shells of 42 points on spheres of radius 1 … 6 about
    one centre (the inside two shells), each shell turned at random."""
    from scipy.spatial.transform import Rotation

    golden = (1 + 5**0.5) / 2
    base = np.array(
        [[0, s, t * golden] for s in (-1, 1) for t in (-1, 1)]
        + [[s, t * golden, 0] for s in (-1, 1) for t in (-1, 1)]
        + [[t * golden, 0, s] for s in (-1, 1) for t in (-1, 1)],
        dtype=float,
    )
    edges = [
        (i, j)
        for i in range(12)
        for j in range(i)
        if np.isclose(np.linalg.norm(base[i] - base[j]), 2.0)
    ]
    shell = np.concatenate([base, [base[i] + base[j] for i, j in edges]])
    shell /= np.linalg.norm(shell, axis=1)[:, None]
    rows = [Rotation.random(random_state=rng).apply(shell) * r for r in range(1, 7)]
    return np.concatenate(rows), np.repeat(np.arange(1, 7) <= 2, len(shell))


ADVERSARIAL = {
    "patch": _patch_seeds,
    "sparse pairs": _sparse_pairs,
    "shells": _shells,
    "lattice": lambda rng: (p := _lattice(10), _ball_labels(p)),
}


@pytest.mark.parametrize("name", sorted(ADVERSARIAL))
@pytest.mark.parametrize("count", [2, 3, 7])
def test_adversarial_layouts_give_the_whole_sets_facets(name, count):
    """Sparse components, far-apart in/out pairs, cospherical shells, a lattice: the slabs
    (certified, or falling back) give the whole set's M̂ for any slab count."""
    points, inside = ADVERSARIAL[name](np.random.default_rng(7))
    _same(inout_facets(points, inside, slabs=count), inout_facets(points, inside, slabs=1))


@pytest.mark.parametrize("name", ["random", "lattice", "torus", "sphere"])
@pytest.mark.parametrize("count", [2, 5])
def test_the_certificate_holds_on_ordinary_seeds(name, count):
    """On ordinary seeds every check of the certificate passes: no fall-back to the whole set
    (the Gabriel edges join the random set's lone hull seeds)."""
    points, inside = SEED_SETS[name](np.random.default_rng(3))
    shift, unit = facets.seed_frame(points)
    fans = slabs.slab_fans(
        (points - shift) / unit, inside, facets._facets_kernel(), facets.flat_circumcentres, count
    )
    assert fans is not None


def test_a_flat_tetrahedron_is_certified_through_all_four_faces(monkeypatch):
    """Found by an independent review: a flat tetrahedron T = (v, g) whose centre was borrowed
    from the one face it tried first was certified by its neighbour's ball, though its own
    circumscribed ball (radius about 10) holds a seed outside slab 0's window: T was in the
    slab's triangulation and not in the whole set's, every check passed, and M̂ lost the facet
    of edge (1, 2). Certifying flat tetrahedra through all four faces sends this case back to
    the whole set."""
    r, h, d, phi = 0.1, 1e-12, 1e-10, np.pi / 3
    v = [0.9 + h, (r + d) * np.cos(phi), (r + d) * np.sin(phi)]  # just off the circle's plane
    g = [[0.9, r * np.cos(t), r * np.sin(t)] for t in (0, 2 * np.pi / 3, 4 * np.pi / 3)]
    u = [0.8 - 0.02**0.5, 0, 0]  # the neighbour across face 0: ball about (0.8, 0, 0)
    fill = np.random.default_rng(0).uniform([-1, -1, -1], [0.5, 1, 1], (40, 3))
    side = [[0.9, y, z] for y in (-0.8, 0.8) for z in (-0.8, 0.8)]
    far = [[1.5, 0, 0]]  # outside slab 0's window, inside T's own circumscribed ball
    points = np.concatenate([[v], g, [u], fill, side, far])
    inside = np.zeros(len(points), bool)
    inside[1] = True
    unit = facets.seed_frame(points)[1]
    monkeypatch.setattr(slabs, "_cuts", lambda x, n: np.array([0.95]) / unit)
    monkeypatch.setattr(slabs, "_probe_reach", lambda *a: 0.05 / unit / slabs.MARGIN_GROWTH)
    whole = inout_facets(points, inside, slabs=1)
    split = inout_facets(points, inside, slabs=2)
    assert whole.surface.n_facets == 10
    assert _pairs(split) == _pairs(whole)
    assert split.surface.n_facets == whole.surface.n_facets and split.collapsed == 0


def test_seeds_of_both_labels_on_the_hull_are_refused():
    """Check 3: both labels among the seeds on the hull (an unbounded facet of M̂) fail it;
    seeds of the other label inside the hull do not."""
    corners = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)
    points = np.concatenate([corners, [[0.5, 0.5, 0.5]], [[0.5, 0.5, 0.0]]])
    candidates = np.arange(len(points))
    inside = np.zeros(len(points), bool)
    inside[8] = True  # the centre: not on the hull
    assert slabs._one_hull_label(points, inside, candidates)
    inside[9] = True  # the middle of a face: on the hull
    assert not slabs._one_hull_label(points, inside, candidates)


def _pairs(mesh):
    """The in/out seed pairs of M̂'s facets, sorted."""
    return sorted(map(tuple, mesh.surface.seed_pairs.tolist()))


def test_slabs_without_the_compiled_steps_say_so(monkeypatch):
    """Slabs need numba's kernels: without them the whole set is triangulated (the same M̂),
    and the user who asked for slabs is told why memory is not bounded by a slab."""
    from vorobound.errors import VoroboundWarning

    rng = np.random.default_rng(3)
    points = rng.normal(size=(300, 3))
    inside = np.linalg.norm(points, axis=1) < 1.0
    whole = inout_facets(points, inside, slabs=1)
    monkeypatch.setattr(facets, "_facets_kernel", lambda: None)
    with pytest.warns(VoroboundWarning, match="7 slabs need exact predicates and numba"):
        split = inout_facets(points, inside, slabs=7)
    assert _pairs(split) == _pairs(whole)
