"""M̂ from the seeds: the facets against independent constructions, topology, labels, the
measurements and the seed files."""

import numpy as np
import pytest

from vorobound.bounds.params import QualityParams, SamplingParams
from vorobound.errors import ReadError
from vorobound.reports.reconstruct import reconstruct_balls, reconstruct_seeds, reconstruct_surface
from vorobound.sampling.balls import make_balls
from vorobound.sampling.guides.triangles import find_guide_triangles
from vorobound.sampling.reconstruct.facets import PolygonSurface, inout_facets
from vorobound.sampling.reconstruct.labels import sheet_labels
from vorobound.sampling.reconstruct.seeds import read_seed_file, seed_table
from vorobound.sampling.reconstruct.topology import surface_topology
from vorobound.sampling.sampler.maximal import sample_surface
from vorobound.sampling.surfaces.analytic import SphereShape, TorusShape

pytest.importorskip("gudhi")

QUALITY = QualityParams()
PLANE_RTOL = 1e-9
"""Facet vertices lie in their seeds' bisector plane to this fraction of the ball radius."""


_MADE: dict = {}
"""Balls and M̂ already made in this module, by surface, ε (and half-covered): several tests
read the same ones (their arrays are read-only, so no test changes another's input)."""


def _made(key, make):
    if key not in _MADE:
        _MADE[key] = make()
    return _MADE[key]


def _balls(shape, eps):
    def make():
        sample = sample_surface(shape, eps, QUALITY.sigma, 0)
        balls = make_balls(sample.points, QUALITY.delta_ratio * eps * sample.lfs)
        balls.centers.flags.writeable = balls.radii.flags.writeable = False
        return balls

    return _made(("balls", shape.name, eps), make)


def _report(shape, eps, half_covered=False):
    """M̂ of the balls of ``shape`` at ``eps``, labelled by the surface."""
    return _made(
        ("report", shape.name, eps, half_covered),
        lambda: reconstruct_balls(
            _balls(shape, eps), SamplingParams(eps, QUALITY), shape, half_covered
        ),
    )


def _surface_report(shape, eps):
    """``reconstruct_surface`` of ``shape`` at ``eps`` with the default quality."""
    return _made(("surface", shape.name, eps), lambda: reconstruct_surface(shape, eps, QUALITY))


def _polygons(surface: PolygonSurface):
    return [
        surface.corners[surface.offsets[f] : surface.offsets[f + 1]]
        for f in range(surface.n_facets)
    ]


def test_seeds_are_mirror_images_and_their_facet_lies_in_the_plane_of_the_samples():
    shape = TorusShape(3, 1)
    balls = _balls(shape, 0.15)
    report = _report(shape, 0.15)
    seeds, surface = report.seeds, report.facets.surface
    centers = balls.centers[seeds.triples]
    normal = np.cross(centers[:, 1] - centers[:, 0], centers[:, 2] - centers[:, 0])
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    # Both seeds of a triangle: the midpoint lies in the plane, the difference is normal to it.
    first = np.flatnonzero(np.diff(seeds.triangle) == 0)  # the seeds of a triangle are adjacent
    second = first + 1
    assert 2 * len(first) == len(seeds)
    t = seeds.triangle[first]
    middle = 0.5 * (seeds.points[first] + seeds.points[second])
    height = np.einsum("ij,ij->i", middle - centers[t, 0], normal[t])
    radius = balls.radii[seeds.triples[t]].max(axis=1)
    assert np.abs(height).max() <= PLANE_RTOL * radius.max()
    gap = seeds.points[first] - seeds.points[second]
    along = np.abs(np.einsum("ij,ij->i", gap, normal[t])) / np.linalg.norm(gap, axis=1)
    assert along.min() == pytest.approx(1.0, abs=1e-9)
    # The facet of two seeds of one triangle lies in the triangle's plane.
    pairs = surface.seed_pairs
    same = seeds.triangle[pairs[:, 0]] == seeds.triangle[pairs[:, 1]]
    assert same.sum() > 0.8 * len(first)
    for f in np.flatnonzero(same):
        tri = seeds.triangle[pairs[f, 0]]
        corners = surface.vertices[surface.corners[surface.offsets[f] : surface.offsets[f + 1]]]
        offset = (corners - centers[tri, 0]) @ normal[tri]
        assert np.abs(offset).max() <= PLANE_RTOL * balls.radii.max()


def test_sphere_mhat_is_the_guide_triangles_on_the_ball_centres():
    """No half-covered triple on a sphere: M̂'s vertices are the ball centres and its facets
    are the guide triangles (degenerate Voronoi vertices welded)."""
    shape = SphereShape(1)
    balls = _balls(shape, 0.1)
    report = _report(shape, 0.1)
    assert report.sample.half_covered == 0
    surface = report.facets.surface
    from scipy.spatial import cKDTree

    distance, ball = cKDTree(balls.centers).query(surface.vertices)
    assert distance.max() <= 1e-9 * balls.radii.max()
    facets = {tuple(sorted(ball[p])) for p in _polygons(surface)}
    guides = {tuple(row) for row in np.sort(report.seeds.triples, axis=1)}
    assert facets == guides and surface.n_facets == len(guides)
    assert len(surface.vertices) == len(balls)
    assert report.facets.collapsed > 0  # the split degenerate vertices were welded


def test_torus_with_half_covered_seeds_has_every_ball_centre_as_a_vertex():
    shape = TorusShape(3, 1)
    balls = _balls(shape, 0.15)
    report = _report(shape, 0.15, half_covered=True)
    assert report.sample.half_covered > 0 and report.topology_correct
    from scipy.spatial import cKDTree

    distance, _ = cKDTree(report.facets.surface.vertices).query(balls.centers)
    assert distance.max() <= 1e-9 * balls.radii.max()


def _facets_from_voronoi(points, inside):
    """In/out facets from scipy's full Voronoi diagram: {pair: vertex coordinates} of the
    bounded ones with area, and the set of unbounded pairs."""
    from scipy.spatial import Voronoi

    diagram = Voronoi(points)
    bounded, unbounded = {}, set()
    for (a, b), ridge in zip(diagram.ridge_points, diagram.ridge_vertices, strict=True):
        if inside[a] == inside[b]:
            continue
        pair = (a, b) if inside[a] else (b, a)
        if -1 in ridge:
            unbounded.add(pair)
            continue
        corners = diagram.vertices[ridge]
        centre = corners.mean(axis=0)
        area = sum(
            np.linalg.norm(np.cross(corners[k] - centre, corners[k - 1] - centre))
            for k in range(len(corners))
        )
        if area > 1e-12:
            bounded[pair] = corners
    return bounded, unbounded


def test_random_seeds_match_the_full_voronoi_diagram():
    rng = np.random.default_rng(5)
    points = rng.standard_normal((300, 3))
    inside = np.linalg.norm(points, axis=1) < 1.0
    found = inout_facets(points, inside)
    surface = found.surface
    expected, unbounded = _facets_from_voronoi(points, inside)
    pairs = {tuple(p) for p in surface.seed_pairs}
    assert pairs == set(expected)
    assert {tuple(p) for p in found.unbounded} == unbounded
    for f, polygon in enumerate(_polygons(surface)):
        mine = np.sort(np.round(surface.vertices[polygon], 9), axis=0)
        theirs = np.sort(np.round(expected[tuple(surface.seed_pairs[f])], 9), axis=0)
        assert np.allclose(mine, theirs, atol=1e-8)


def test_a_few_hundred_vorocrust_seeds_match_voronoi_and_the_direct_check():
    """On degenerate (cospherical) seeds: the pairs with a facet of positive area agree with
    the full Voronoi diagram, and every vertex of M̂ is equidistant from its two seeds with no
    seed closer (checked directly with a k-d tree)."""
    from scipy.spatial import cKDTree

    shape = SphereShape(1)
    balls = _balls(shape, 0.3)
    report = reconstruct_balls(balls, SamplingParams(0.3, QUALITY), shape)
    seeds, surface = report.seeds, report.facets.surface
    assert 200 <= len(seeds) <= 800
    expected, unbounded = _facets_from_voronoi(seeds.points, seeds.inside)
    assert not unbounded and {tuple(p) for p in surface.seed_pairs} == set(expected)
    nearest, _ = cKDTree(seeds.points).query(surface.vertices)
    facet = surface.facet_of_corner()
    own = np.linalg.norm(
        surface.vertices[surface.corners][:, None, :] - seeds.points[surface.seed_pairs[facet]],
        axis=2,
    )
    scale = balls.radii.max()
    assert np.abs(own[:, 0] - own[:, 1]).max() <= 1e-9 * scale
    assert np.abs(own[:, 0] - nearest[surface.corners]).max() <= 1e-9 * scale


@pytest.mark.parametrize(
    "shape, eps, chi",
    [(SphereShape(1), 0.15, 2), (TorusShape(3, 1), 0.15, 0), (TorusShape(1.5, 1), 0.2, 0)],
    ids=["sphere", "torus-3-1", "torus-1.5-1"],
)
def test_moderate_eps_gives_a_closed_manifold_with_the_surface_topology(shape, eps, chi):
    report = _surface_report(shape, eps)
    top = report.topology
    assert top.closed_manifold and top.misoriented_edges == 0
    assert top.euler_characteristic == chi and top.components == 1
    assert report.topology_correct and top.genus == 1 - chi // 2
    m = report.measures
    assert 0 < m.hausdorff < 1 and m.normal_deviation.max() < 90


def test_hausdorff_is_bounded_by_the_ball_radii_inside_the_union():
    from scipy.spatial import cKDTree

    shape = TorusShape(1.5, 1)
    eps = 0.15
    balls = _balls(shape, eps)
    report = reconstruct_balls(balls, SamplingParams(eps, QUALITY), shape)
    surface = report.facets.surface
    points = np.concatenate([surface.vertices, surface.centroids()])
    distance = shape.closest(points).distance
    # The ball of smallest power: a point inside the union lies inside it.
    tree = cKDTree(balls.centers)
    near, index = tree.query(points, k=16)
    power = near**2 - balls.weights[index]
    best = np.argmin(power, axis=1)
    covered = power[np.arange(len(points)), best] < 0
    radius = balls.radii[index[np.arange(len(points)), best]]
    assert covered.mean() > 0.5
    assert (distance[covered] <= radius[covered] * (1 + 1e-12)).all()


@pytest.mark.parametrize(
    "shape, eps",
    [(SphereShape(1), 0.1), (TorusShape(3, 1), 0.15), (TorusShape(1.5, 1), 0.2)],
    ids=["sphere", "torus-3-1", "torus-1.5-1"],
)
def test_labels_from_the_sheets_agree_with_the_surface(shape, eps):
    balls = _balls(shape, eps)
    seeded = find_guide_triangles(balls).seeded
    labels = sheet_labels(balls, seeded)
    truth = shape.inside(seeded.seeds.reshape(-1, 3)).reshape(-1, 2)
    assert np.array_equal(labels[seeded.uncovered], truth[seeded.uncovered])


def test_sheet_labels_swap_for_a_cavity():
    """A hollow ball (solid between spheres of radius 1 and 2): the inner surface's inside
    seeds are the ones outside radius 1."""
    inner, outer = _balls(SphereShape(1), 0.1), _balls(SphereShape(2), 0.05)
    balls = make_balls(
        np.concatenate([inner.centers, outer.centers]),
        np.concatenate([inner.radii, outer.radii]),
    )
    seeded = find_guide_triangles(balls, "gudhi").seeded
    labels = sheet_labels(balls, seeded)
    radius = np.linalg.norm(seeded.seeds, axis=2)
    truth = (radius > 1) & (radius < 2)
    assert np.array_equal(labels[seeded.uncovered], truth[seeded.uncovered])
    report = reconstruct_balls(balls)
    assert report.seeds.labels == "sheets"
    assert report.topology.closed_manifold and report.topology.components == 2
    assert report.topology.euler_characteristic == 4


def _two_tetrahedra(pinched: bool):
    """Two tetrahedron surfaces, sharing one vertex when ``pinched``."""
    base = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    faces = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]
    second = [[i + (3 if pinched else 4) for i in f] for f in faces]
    if pinched:
        second = [[0 if i == 3 else i for i in f] for f in second]
    vertices = np.concatenate([base, -base[1:] if pinched else base + 5])
    corners = np.array(faces + second).reshape(-1)
    offsets = np.arange(0, len(corners) + 1, 3)
    blank = np.zeros((8, 2), dtype=np.int64)
    return PolygonSurface(vertices, corners, offsets, blank, np.zeros((8, 3)))


def test_topology_counts_pinches_holes_and_orientation():
    apart = surface_topology(_two_tetrahedra(False))
    assert apart.closed_manifold and apart.components == 2 and apart.euler_characteristic == 4
    pinched = surface_topology(_two_tetrahedra(True))
    assert pinched.nonmanifold_vertices == 1 and not pinched.closed_manifold
    assert pinched.euler_characteristic == 3 and len(pinched.bad_facets) == 6
    s = _two_tetrahedra(False)
    holed = PolygonSurface(s.vertices, s.corners[3:], s.offsets[:-1], s.seed_pairs, s.normals)
    top = surface_topology(holed)
    assert top.boundary_edges == 3 and not top.closed_manifold
    flipped = s.corners.copy()
    flipped[:3] = flipped[:3][::-1]
    top = surface_topology(PolygonSurface(s.vertices, flipped, s.offsets, s.seed_pairs, s.normals))
    assert top.misoriented_edges == 3 and top.genus is None
    assert surface_topology(s, unbounded=1).closed_manifold is False


@pytest.fixture(scope="module")
def torus_report():
    shape = TorusShape(3, 1)
    return shape, _surface_report(shape, 0.15)


def _write_seed_csv(path, seeds, header=True, order=None, extra=False, region="region_id"):
    names, table = seed_table(seeds)
    names[-1] = region
    if extra:
        names.append("weight")
        table = np.column_stack([table, np.arange(len(table))])
    order = order or list(range(len(names)))
    lines = [",".join(names[k] for k in order)] if header else []
    lines += [",".join(f"{row[k]:.17g}" for k in order) for row in table]
    path.write_text("\n".join(lines) + "\n")


SEED_FILES = {
    "header": (True, None, False, "region_id"),
    "no-header": (False, None, False, "region_id"),
    "shuffled-extra-region": (True, [4, 3, 2, 0, 1, 5], True, "region"),
}
"""Layouts of a VoroCrust seed file: (header, column order, extra column, region name)."""


def _read_back(made, path, layout):
    _write_seed_csv(path, made.seeds, *SEED_FILES[layout])
    seeds = read_seed_file(path)
    assert np.array_equal(seeds.points, made.seeds.points)
    assert np.array_equal(seeds.inside, made.seeds.inside)
    return seeds


@pytest.mark.parametrize("layout", list(SEED_FILES))
def test_a_vorocrust_seed_file_is_read_exactly(torus_report, tmp_path, layout):
    _read_back(torus_report[1], tmp_path / "seeds.csv", layout)


# M̂ of the seeds read back (1.3 CPU-s each): the layout that differs most by default; the
# other two (read exactly by the test above) with the slow marker.
@pytest.mark.parametrize(
    "layout",
    [pytest.param(name, marks=pytest.mark.slow) for name in ("header", "no-header")]
    + ["shuffled-extra-region"],
)
def test_a_vorocrust_seed_file_gives_the_same_measurements(torus_report, tmp_path, layout):
    shape, made = torus_report
    seeds = _read_back(made, tmp_path / "seeds.csv", layout)
    read = reconstruct_seeds(seeds, shape, made.params)
    mine, theirs = made.summary(), read.summary()
    for key in (
        "n_facets",
        "closed_manifold",
        "euler_characteristic",
        "components",
        "hausdorff_over_eps_lfs",
        "normal_deviation_max_deg",
        "edge_ratio_min",
        "min_angle_min_deg",
    ):
        assert theirs[key] == mine[key], key


@pytest.mark.parametrize(
    "text, message",
    [
        ("x,y,z,sizing\n0,0,0,1\n1,0,0,1\n0,1,0,1\n0,0,1,1\n1,1,1,1\n", "no labels"),
        ("0,0,0,1\n1,0,0,1\n0,1,0,1\n0,0,1,1\n1,1,1,1\n", "no labels"),
        ("0,0,0,1,1\n1,0,0,1,1\n0,1,0,1,1\n0,0,1,1,1\n1,1,1,1,1\n", "every seed"),
        ("0,0,0,1,0\n1,0,0,1,1\nnan,1,0,1,0\n0,0,1,1,1\n1,1,1,1,0\n", "not finite"),
        ("0,0,0,1,0\n1,0,0,1,2\n0,1,0,1,0\n0,0,1,1,1\n1,1,1,1,0\n", "region id 2"),
        ("0,0,0,1,0\n1,0,0,1,1\n0,0,0,1,0\n0,0,1,1,1\n1,1,1,1,0\n", "same point"),
        ("0,0,0,1,0\n1,0,0,1,1\n", "at least 5"),
        ("x,y,z,region\n0,0,0,0\n1,a,0,1\n", "not a table"),
        ("", "empty"),
    ],
    ids=[
        "header-no-region",
        "four-columns",
        "one-label",
        "nan",
        "label-2",
        "duplicate",
        "too-few",
        "text",
        "empty",
    ],
)
def test_bad_seed_files_are_refused_with_one_line(tmp_path, text, message):
    path = tmp_path / "seeds.csv"
    path.write_text(text)
    with pytest.raises(ReadError, match=message) as caught:
        read_seed_file(path)
    assert "\n" not in str(caught.value)


@pytest.mark.parametrize("scale", [1e-45, 1e40, 2e49])
def test_facets_do_not_depend_on_the_unit_of_length(scale):
    """Circumcentres are of degree up to 6 in the coordinates: at 1e40 their rounding
    errors overflowed and every facet was welded away, at 1e-45 they underflowed."""
    rng = np.random.default_rng(0)
    points = rng.random((50, 3))
    inside = np.arange(50) % 2 == 1
    unit, scaled = inout_facets(points, inside), inout_facets(points * scale, inside)
    assert scaled.collapsed == unit.collapsed == 0
    assert scaled.surface.n_facets == unit.surface.n_facets
    np.testing.assert_array_equal(scaled.surface.seed_pairs, unit.surface.seed_pairs)
    np.testing.assert_allclose(
        scaled.surface.vertices, unit.surface.vertices * scale, rtol=1e-9, atol=0
    )


@pytest.mark.parametrize(
    "text, message",
    [
        ("x,y,z,region_id\n1,2,3\n4,5,6\n1,1,1\n2,2,2\n3,3,9\n", "header names 4 columns"),
        ("x,y,z,region_id\n\n", "no rows"),
        (
            "".join(f"{k * 1e-60},{k % 3 * 1e-60},{k % 2 * 1e-60},1,{k % 2}\n" for k in range(6)),
            "span less than",
        ),
    ],
    ids=["header-wider-than-rows", "header-only", "tiny-span"],
)
def test_seed_files_that_used_to_crash_are_refused(tmp_path, text, message):
    path = tmp_path / "seeds.csv"
    path.write_text(text)
    with pytest.raises(ReadError, match=message) as caught:
        read_seed_file(path)
    assert "\n" not in str(caught.value)


def test_mhat_and_seeds_round_trip_through_meshio(tmp_path):
    import meshio

    from vorobound.files import write_set
    from vorobound.reports.reconstruct_files import output_writers

    report = reconstruct_surface(TorusShape(3, 1), 0.2, QUALITY)
    write_set(output_writers(report, tmp_path))
    surface = report.facets.surface
    expected = sorted(tuple(sorted(map(tuple, surface.vertices[p]))) for p in _polygons(surface))
    for name in ("mhat.vtu", "mhat.ply"):
        mesh = meshio.read(tmp_path / name)
        polygons = [tuple(sorted(map(tuple, mesh.points[c]))) for b in mesh.cells for c in b.data]
        assert sorted(polygons) == expected, name
    mesh = meshio.read(tmp_path / "mhat.vtu")
    facet = np.concatenate(mesh.cell_data["facet"]).astype(int)
    deviation = np.concatenate(mesh.cell_data["normal_deviation_deg"])
    assert np.array_equal(deviation, report.measures.normal_deviation[facet])
    seeds = meshio.read(tmp_path / "seeds.vtu")
    assert np.array_equal(seeds.point_data["region_id"] == 1, report.seeds.inside)
    again = read_seed_file(tmp_path / "seeds.csv")
    assert np.array_equal(again.points, report.seeds.points)


def _fixture_seeds(name):
    """Labelled seeds of the reconstruct fixtures (seeds of sampled spheres and tori)."""
    shape, eps, half = {
        "sphere-0.1": (SphereShape(1), 0.1, False),
        "torus-3-1-0.15": (TorusShape(3, 1), 0.15, False),
        "torus-3-1-0.15-half": (TorusShape(3, 1), 0.15, True),
        "torus-1.5-1-0.2": (TorusShape(1.5, 1), 0.2, False),
    }[name]
    report = _report(shape, eps, half)
    return report.seeds.points, report.seeds.inside, report


FIXTURES = [
    "sphere-0.1",
    pytest.param("torus-3-1-0.15", marks=pytest.mark.slow),
    pytest.param("torus-3-1-0.15-half", marks=pytest.mark.slow),
    "torus-1.5-1-0.2",
]
"""The larger tori take 10–15 s each under load: in the slow set."""


@pytest.mark.parametrize("engine", ["exact", "cgal"])
@pytest.mark.parametrize("name", FIXTURES)
def test_exact_engines_and_qhull_give_the_same_facets(name, engine):
    """qhull stays the cross-check of the exact tetrahedralizations (geogram's, the default,
    and CGAL's): the same in/out facets with area, on the same welded vertices, and no seed
    left out by either."""
    points, inside, _ = _fixture_seeds(name)
    cgal = inout_facets(points, inside, triangulation=engine)
    qhull = inout_facets(points, inside, triangulation="qhull")
    assert cgal.skipped_seeds == qhull.skipped_seeds == 0
    mine = {tuple(p): f for f, p in enumerate(cgal.surface.seed_pairs)}
    theirs = {tuple(p): f for f, p in enumerate(qhull.surface.seed_pairs)}
    assert set(mine) == set(theirs) and len(mine) == cgal.surface.n_facets
    scale = np.ptp(points, axis=0).max()
    for pair, f in mine.items():
        a = cgal.surface.vertices[cgal.surface.corners[cgal.surface.offsets[f] :][:3]]
        g = theirs[pair]
        b = qhull.surface.vertices[qhull.surface.corners[qhull.surface.offsets[g] :][:3]]
        # The same polygon (first corners may differ): every corner of one is a corner of the
        # other.
        ca = cgal.surface.vertices[
            cgal.surface.corners[cgal.surface.offsets[f] : cgal.surface.offsets[f + 1]]
        ]
        cb = qhull.surface.vertices[
            qhull.surface.corners[qhull.surface.offsets[g] : qhull.surface.offsets[g + 1]]
        ]
        assert len(ca) == len(cb) and len(a) == len(b) == 3
        gap = np.linalg.norm(ca[:, None, :] - cb[None, :, :], axis=2).min(axis=1)
        assert gap.max() <= 1e-9 * scale


@pytest.mark.parametrize("name", FIXTURES)
def test_compiled_and_numpy_steps_give_the_same_facets(name):
    """The compiled neighbours, circumcentres and walks (numba) against the numpy steps on
    VoroCrust's seeds (cospherical by construction, with flat tetrahedra): the same polygons
    corner by corner, the same counts, vertices within rounding."""
    pytest.importorskip("numba")
    points, inside, _ = _fixture_seeds(name)
    compiled = inout_facets(points, inside, compiled=True)
    plain = inout_facets(points, inside, compiled=False)
    for field in ("corners", "offsets", "seed_pairs"):
        np.testing.assert_array_equal(
            getattr(compiled.surface, field), getattr(plain.surface, field)
        )
    scale = np.ptp(points, axis=0).max()
    np.testing.assert_allclose(
        compiled.surface.vertices, plain.surface.vertices, rtol=0, atol=1e-12 * scale
    )
    assert compiled.collapsed == plain.collapsed > 0
    assert compiled.unresolved == plain.unresolved
    assert compiled.delaunay_edges == plain.delaunay_edges


@pytest.mark.parametrize("name", FIXTURES)
def test_seeds_far_from_the_origin_give_the_same_mhat(name):
    """Issue 34: a seed set shifted by 10⁵ lost 272 seeds in qhull and gained 507 facets with
    ``ok: true``; at 10⁷ M̂ was empty. Shifted by 10³ … 10⁹ (each coordinate rounded to the
    shifted position), every fixture keeps every seed and its topology, and its facet count
    to within the tiny facets the rounding of the shifted coordinates makes or hides."""
    points, inside, report = _fixture_seeds(name)
    base = inout_facets(points, inside)
    top = surface_topology(base.surface)
    assert top.closed_manifold and base.skipped_seeds == 0
    direction = np.array([1.0, -0.6, 0.3])
    for shift in [1e3, 1e5, 1e7, 1e9]:
        moved = inout_facets(points + shift * direction, inside)
        assert moved.skipped_seeds == 0, shift
        assert abs(moved.surface.n_facets - base.surface.n_facets) <= max(
            3, 0.005 * base.surface.n_facets
        ), (shift, moved.surface.n_facets, base.surface.n_facets)
        assert moved.unbounded.shape == base.unbounded.shape
        got = surface_topology(moved.surface)
        assert got.closed_manifold, shift
        assert (got.euler_characteristic, got.components) == (
            top.euler_characteristic,
            top.components,
        ), shift
        # M̂ moves with the seeds (to the rounding of the shifted coordinates).
        from scipy.spatial import cKDTree

        gap, _ = cKDTree(base.surface.vertices).query(moved.surface.vertices - shift * direction)
        assert np.median(gap) <= 1e-6 * np.ptp(points, axis=0).max(), shift


def test_balls_far_from_the_origin_keep_every_seed():
    """Issue 34: ``reconstruct --balls`` on balls at 10⁸ skipped 17,045 seeds while ``check``
    passed the same balls. Shifted by 10⁵ and 10⁸, a sphere's balls give the same seeds, all
    triangulated, and M̂ a sphere."""
    sample = sample_surface(SphereShape(1), 0.1, QUALITY.sigma, 0)
    radii = QUALITY.delta_ratio * 0.1 * sample.lfs
    base = reconstruct_balls(make_balls(sample.points, radii))
    for shift in [1e5, 1e8]:
        moved = reconstruct_balls(make_balls(sample.points + shift, radii))
        assert len(moved.seeds) == len(base.seeds)
        assert moved.facets.skipped_seeds == 0 and moved.ok  # no surface: a closed 2-manifold
        assert moved.topology.euler_characteristic == 2
        assert abs(moved.facets.surface.n_facets - base.facets.surface.n_facets) <= max(
            3, 0.01 * base.facets.surface.n_facets
        )


def test_a_seed_left_out_makes_mhat_not_correct_and_an_exact_copy_does_not():
    """With CGAL only exact copies are left out: a copy with its seed's label is counted apart
    (one Voronoi cell), a copy with the other label is skipped, and a skipped seed makes the
    reconstruction not correct."""
    from dataclasses import replace

    rng = np.random.default_rng(4)
    points = rng.standard_normal((200, 3))
    inside = np.linalg.norm(points, axis=1) < 1
    same = inout_facets(np.vstack([points, points[:1]]), np.append(inside, inside[0]))
    assert (same.duplicate_seeds, same.skipped_seeds) == (1, 0)
    other = inout_facets(np.vstack([points, points[:1]]), np.append(inside, ~inside[0]))
    assert other.duplicate_seeds + other.skipped_seeds == 1 and other.skipped_seeds == 1
    report = reconstruct_surface(SphereShape(1), 0.2, QUALITY)
    assert report.topology_correct
    broken = replace(report, facets=replace(report.facets, skipped_seeds=1))
    assert not broken.topology_correct and broken.summary()["skipped_seeds"] == 1


def test_the_seed_frame_is_exact():
    """The shift of a far axis is exact (Sterbenz), a straddling axis is not shifted, and the
    frame's coordinates are below 1 in size."""
    from vorobound.sampling.reconstruct.facets import seed_frame

    rng = np.random.default_rng(6)
    for offset in [0.0, 3.0, 1e5, -1e9, 1e300]:
        points = rng.standard_normal((500, 3)) + np.array([offset, 0.0, -offset])
        shift, unit = seed_frame(points)
        moved = points - shift
        np.testing.assert_array_equal(moved + shift, points)
        assert shift[1] == 0 and (abs(offset) > 100) == (shift[0] != 0)
        assert np.abs(moved / unit).max() <= 1 and unit == 2.0 ** np.round(np.log2(unit))
