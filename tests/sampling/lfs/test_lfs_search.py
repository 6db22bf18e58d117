"""The searches behind the speed of ``vorobound lfs`` give what a brute-force loop over every
candidate gives: the largest empty tangent balls, the Lipschitz envelope with site radii, the
feature cap, and the per-site values kept from one refinement round to the next."""

import numpy as np
import pytest

from vorobound.sampling.lfs.tangent_ball import largest_empty_radius, tangent_radius


def _patches(rng):
    """Triangles of three groups: a flat square (z = 1), a curved cap (sphere of radius 2 about
    the origin, above z = 1.2) and a few long slivers (z = −1): (triangles, group)."""
    grid = np.stack(np.meshgrid(np.linspace(-1, 1, 9), np.linspace(-1, 1, 9)), -1)
    corners = grid[:-1, :-1], grid[1:, :-1], grid[1:, 1:], grid[:-1, 1:]
    quads = np.stack([c.reshape(-1, 2) for c in corners], axis=1)
    flat = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    flat = np.concatenate([flat, np.ones(flat.shape[:2] + (1,))], axis=2)
    direction = rng.normal(size=(60, 3, 3)) * 0.2 + [0, 0, 1]
    cap = 2 * direction / np.linalg.norm(direction, axis=2, keepdims=True)
    start = rng.uniform(-1, 1, (10, 2))
    sliver = np.stack(
        [
            np.c_[start, -np.ones(10)],
            np.c_[start + [3, 0.01], -np.ones(10)],
            np.c_[start + [3, 0.0], -np.ones(10)],
        ],
        axis=1,
    )
    triangles = np.concatenate([flat, cap, sliver])
    group = np.repeat([0, 1, 2], [len(flat), len(cap), len(sliver)])
    return triangles, group


def _brute(points, directions, point_group, triangles, triangle_group, allowed, limit):
    out = np.asarray(limit, dtype=float).copy()
    for i in range(len(points)):
        ok = allowed[point_group[i], triangle_group]
        if ok.any() and np.isfinite(out[i]):
            n = int(ok.sum())
            x, d = np.repeat(points[i : i + 1], n, 0), np.repeat(directions[i : i + 1], n, 0)
            t = triangles[ok]
            out[i] = min(out[i], tangent_radius(x, d, t[:, 0], t[:, 1], t[:, 2]).min())
    return out


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_largest_empty_radius_is_the_brute_force_minimum(seed):
    rng = np.random.default_rng(seed)
    triangles, group = _patches(rng)
    count = 400
    points = rng.uniform(-1.2, 1.2, (count, 3)) * [1, 1, 0.8]
    directions = rng.normal(size=(count, 3))
    directions /= np.linalg.norm(directions, axis=1)[:, None]
    point_group = rng.integers(0, 4, count)  # group 3 may touch everything
    allowed = np.ones((4, 3), dtype=bool)
    allowed[0, 0] = allowed[1, 1] = allowed[2, 2] = False
    limit = rng.choice([0.05, 0.5, 3.0, np.inf], count)
    args = (points, directions, point_group, triangles, group, allowed, limit)
    got = largest_empty_radius(*args)
    # The search cuts the long triangles into pieces (their union is the triangle), so it
    # agrees with the loop over whole triangles up to rounding.
    expected = _brute(*args)
    assert np.array_equal(np.isfinite(got), np.isfinite(expected))
    finite = np.isfinite(expected)
    np.testing.assert_allclose(got[finite], expected[finite], rtol=SPLIT_RTOL, atol=0)
    assert (got <= limit).all() and (got < limit).any()


SPLIT_RTOL = 1e-11
"""Rounding of the tangent radius when a triangle is cut into pieces."""


@pytest.mark.parametrize("length", [0.05, 0.3, 2.0])
def test_long_triangles_are_cut_into_pieces_that_tile_them(length):
    """Longest-edge bisection: no sliver edge above the length, each triangle's pieces have
    its area and lie in it, and the piece length keeps the count within the budget per face
    (and leaves a fine mesh of fat triangles alone)."""
    from vorobound.sampling.lfs.tangent_ball import (
        PIECES_PER_FACE,
        SLIVER_ASPECT,
        piece_length,
        split_long,
    )
    from vorobound.sampling.surfaces.demo_meshes import torus_mesh

    triangles, _ = _patches(np.random.default_rng(0))
    pieces, owner = split_long(triangles, length)
    edges = np.linalg.norm(pieces - np.roll(pieces, -1, axis=1), axis=2).max(axis=1)
    doubled = np.linalg.norm(
        np.cross(pieces[:, 1] - pieces[:, 0], pieces[:, 2] - pieces[:, 0]), axis=1
    )
    assert ((edges <= length) | (edges**2 <= SLIVER_ASPECT * doubled)).all()

    def area(t):
        return 0.5 * np.linalg.norm(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), axis=1)

    summed = np.bincount(owner, area(pieces), minlength=len(triangles))
    np.testing.assert_allclose(summed, area(triangles), rtol=1e-12)
    assert set(owner.tolist()) == set(range(len(triangles)))
    # Every piece corner is a convex combination of its triangle's corners.
    base = triangles[owner]
    for corner in range(3):
        for row in range(0, len(pieces), max(1, len(pieces) // 20)):
            system = np.vstack([base[row].T, np.ones(3)])
            weights = np.linalg.lstsq(system, np.r_[pieces[row, corner], 1.0], rcond=None)[0]
            assert weights.min() > -1e-9
    # The budget is met on a CAD export's slivers; wedges (a fan's slivers) make up to a few
    # times more pieces than the estimate behind the length.
    from vorobound.sampling.surfaces.cad_meshes import gear

    count = len(split_long(triangles, piece_length(triangles))[0])
    assert count <= 4 * PIECES_PER_FACE * len(triangles)
    part = gear(faces=20_000)
    slivers = part.points[part.triangles]
    count = len(split_long(slivers, piece_length(slivers))[0])
    assert count <= PIECES_PER_FACE * len(slivers)
    torus = torus_mesh(3.0, 1.0, 64, 16, jitter=0.2)
    fine = torus.points[torus.triangles]
    assert len(split_long(fine, piece_length(fine))[0]) == len(fine)


def test_a_ball_tangent_to_a_flat_patch_stops_at_the_plane():
    """From a point one unit below the flat square, straight up: the ball of radius 1/2."""
    rng = np.random.default_rng(0)
    triangles, group = _patches(rng)
    points = np.array([[0.13, -0.21, 0.0], [0.5, 0.5, 0.0]])
    up = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 1.0]])
    allowed = np.array([[True, False, False]])
    got = largest_empty_radius(points, up, np.zeros(2, int), triangles, group, allowed, [5, 0.3])
    assert got == pytest.approx([0.5, 0.3], rel=1e-14)


@pytest.mark.parametrize("seed", [0, 1])
def test_tangent_balls_taken_over_from_the_last_round_equal_new_ones(seed):
    """The memo of the refinement rounds (vorobound/sampling/lfs/memo.py): a ball searched
    from one cap gives the ball for another cap exactly, or is searched again."""
    from types import SimpleNamespace

    from vorobound.sampling.lfs.estimate import _last_balls, _tangent_balls
    from vorobound.sampling.lfs.memo import RoundMemo, site_keys
    from vorobound.sampling.lfs.tangent_ball import TangentBalls

    rng = np.random.default_rng(seed)
    triangles, group = _patches(rng)
    count = 300
    points = rng.uniform(-1.2, 1.2, (count, 3)) * [1, 1, 0.8]
    normals = rng.normal(size=(count, 3))
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    point_group = rng.integers(0, 4, count)
    allowed = np.ones((4, 3), dtype=bool)
    allowed[0, 0] = allowed[1, 1] = allowed[2, 2] = False
    ray = SimpleNamespace(
        inward_sign=rng.choice([-1, 0, 1], count),
        outward=rng.choice([0.5, np.inf], count),
    )
    balls = TangentBalls(triangles, group, allowed)
    memo, keys = RoundMemo(), site_keys(1, np.arange(count), points)
    first_cap = rng.choice([0.05, 0.3, 1.0, 3.0], count)
    none = _last_balls(memo, memo.match(keys))
    _, remembered = _tangent_balls(balls, points, normals, ray, point_group, first_cap, none)
    memo.remember(keys, **remembered)
    cap = first_cap * rng.choice([0.5, 1.0, 2.0], count)  # lower, equal and higher caps
    again, _ = _tangent_balls(
        balls, points, normals, ray, point_group, cap, _last_balls(memo, memo.match(keys))
    )
    fresh, _ = _tangent_balls(balls, points, normals, ray, point_group, cap, none)
    assert np.array_equal(again, fresh)
    assert (fresh < cap).any()


def test_repeated_crossings_are_dropped_in_order():
    """A hit within the gap of the last kept hit of its ray is the same crossing (edges and
    vertices are hit by every face around them); a chain of close hits keeps every one that is
    past the gap from the last kept one."""
    from vorobound.sampling.lfs.thickness import _distinct_crossings

    rng = np.random.default_rng(0)
    ray = np.sort(rng.integers(0, 200, 3000))
    t = rng.uniform(0, 1, 3000)
    t[::3] = t[1::3][: len(t[::3])]  # exact repeats
    t[2::7] += 1e-9
    gap = 1.5e-9
    # A chain: the third hit is within the gap of the second, past it from the first.
    ray = np.r_[ray, [500] * 4]
    t = np.r_[t, 0.5 + gap * np.array([0.0, 0.9, 1.8, 2.0])]
    order = np.lexsort((t, ray))
    ray, t = ray[order], t[order]
    expected = np.zeros(len(t), dtype=bool)
    last = {}
    for row in range(len(t)):
        if t[row] - last.get(ray[row], -np.inf) > gap:
            expected[row] = True
            last[ray[row]] = t[row]
    got = _distinct_crossings(ray, t, gap)
    assert np.array_equal(got, expected)
    assert got[ray == 500].tolist() == [True, False, True, False]
    assert (~got).sum() > 100


@pytest.mark.parametrize("kind", ["envelope", "cap"])
@pytest.mark.slow
def test_envelope_and_cap_with_radii_match_brute_force(kind):
    """Several chunks of queries (run on threads), sites with radii, from the nearest sites'
    cones as first bounds: the branch and bound gives the brute-force minimum."""
    from vorobound.sampling.lfs.lipschitz import QUERY_CHUNK, DistanceCap, Envelope

    rng = np.random.default_rng(3)
    sites = rng.normal(size=(1500, 3)) * [3, 1, 0.2]
    values = rng.uniform(0.1, 2, len(sites))
    radii = rng.uniform(0, 0.3, len(sites))
    queries = np.vstack([sites[:100], rng.normal(size=(2 * QUERY_CHUNK + 7, 3)) * 2])
    beyond = np.maximum(np.linalg.norm(queries[:, None] - sites[None], axis=2) - radii, 0)
    if kind == "envelope":
        got = Envelope(sites, values, 0.7, radii)(queries)
        brute = (values + 0.7 * beyond).min(axis=1)
    else:
        upper = rng.uniform(0.5, 3, len(queries))
        got = DistanceCap(sites, values, radii)(queries, upper=upper)
        brute = np.minimum(np.maximum(values, beyond).min(axis=1), upper)
    assert np.array_equal(got, brute)


def test_an_envelope_sharing_the_tree_shape_of_another_is_the_same():
    from vorobound.sampling.lfs.lipschitz import Envelope

    rng = np.random.default_rng(4)
    sites = rng.normal(size=(3000, 3))
    queries = rng.normal(size=(500, 3))
    first = Envelope(sites, rng.uniform(0, 1, len(sites)), 1.0)
    values, radii = rng.uniform(0, 1, len(sites)), rng.uniform(0, 0.1, len(sites))
    shared = Envelope(sites, values, 0.5, radii, like=first)
    assert shared.tree.order is first.tree.order
    assert np.array_equal(shared(queries), Envelope(sites, values, 0.5, radii)(queries))


def test_nearest_site_among_coinciding_sites_is_exact():
    """Sites in clusters that coincide to rounding (the circumcentres of cospherical samples)
    and lone ones: the nearest is the brute-force nearest."""
    from vorobound.sampling.lfs.medial import nearest_site

    rng = np.random.default_rng(5)
    centre = rng.normal(size=(40, 3))
    sites = np.vstack(
        [
            np.repeat(centre, 50, axis=0) + 1e-13 * rng.normal(size=(2000, 3)),
            rng.normal(size=(99, 3)),
        ]
    )
    queries = np.vstack([rng.normal(size=(700, 3)), centre[:5] + 1e-12])
    distance, index = nearest_site(sites, queries)
    gaps = np.linalg.norm(queries[:, None] - sites[None], axis=2)
    assert np.array_equal(distance, gaps.min(axis=1))
    assert np.array_equal(gaps[np.arange(len(queries)), index], distance)


@pytest.mark.parametrize("seed", [0, 1])
def test_faces_nearer_than_a_bound_are_the_nearest_faces_of_the_mesh(seed):
    """The bounded search of the pole check finds a face exactly where the mesh comes closer
    than the bound, at the distance libigl's AABB tree gives (long thin triangles of a CAD
    export; the face may differ only where several are equally near)."""
    from vorobound.sampling.lfs.thickness import RayCaster
    from vorobound.sampling.surfaces.cad_meshes import gear

    mesh = gear(teeth=20, faces=2000, bore=3.0)
    caster = RayCaster(mesh.points, mesh.triangles)
    rng = np.random.default_rng(seed)
    queries = rng.uniform(mesh.points.min(axis=0), mesh.points.max(axis=0), (1500, 3))
    distance, face, _ = caster.closest(queries)
    bound = distance * rng.uniform(0.5, 1.5, len(queries))
    got, got_face = caster.nearer_than(queries, bound)
    inside = distance < bound
    assert inside.any() and (~inside).any()
    assert np.array_equal(got_face >= 0, inside)
    np.testing.assert_allclose(got[inside], distance[inside], rtol=1e-12, atol=1e-12)
    assert np.isinf(got[~inside]).all()
    same = got_face[inside] == face[inside]
    tied = ~same
    assert same.mean() > 0.5
    # A different face is an equally near one.
    other = caster.points[caster.faces[got_face[inside][tied]]]
    from vorobound.sampling.lfs.thickness import point_triangle_distance

    again = point_triangle_distance(queries[inside][tied], other[:, 0], other[:, 1], other[:, 2])
    np.testing.assert_allclose(again, distance[inside][tied], rtol=1e-12, atol=1e-12)


def test_compiled_and_numpy_searches_agree(monkeypatch):
    """The compiled tree (numba) and the numpy searches give the same tangent balls (to the
    last bit: the same operations in the same order) and the same nearest distances on a CAD
    export's long thin triangles (issue 35)."""
    pytest.importorskip("numba")
    from vorobound.sampling.lfs.tangent_ball import TangentBalls
    from vorobound.sampling.lfs.thickness import RayCaster
    from vorobound.sampling.surfaces.cad_meshes import gear

    mesh = gear(teeth=20, faces=2000, bore=3.0)
    rng = np.random.default_rng(3)
    triangles = mesh.points[mesh.triangles]
    group = rng.integers(0, 3, len(triangles))
    allowed = (rng.random((3, 3)) < 0.7) & ~np.eye(3, dtype=bool)  # never the site's own
    count = 800
    face = rng.integers(0, len(triangles), count)
    points = triangles[face].mean(axis=1)
    directions = rng.normal(size=(count, 3))
    directions /= np.linalg.norm(directions, axis=1)[:, None]
    point_group = group[face]
    limit = rng.choice([0.3, 2.0, 20.0, np.inf], count)
    queries = rng.uniform(mesh.points.min(axis=0), mesh.points.max(axis=0), (800, 3))
    bound = rng.uniform(0.1, 5.0, len(queries))
    answers = []
    for numpy_only in ("", "1"):
        monkeypatch.setenv("VOROBOUND_PURE_NUMPY", numpy_only)
        balls = TangentBalls(triangles, group, allowed)
        radius = balls(points, directions, point_group, limit)
        distance, _ = RayCaster(mesh.points, mesh.triangles).nearer_than(queries, bound)
        assert (balls._compiled is False) == bool(numpy_only)
        answers.append((radius, distance))
    (radius, distance), (radius_np, distance_np) = answers
    assert (radius < limit).any() and np.isfinite(distance).any()
    assert np.array_equal(radius, radius_np)
    assert np.array_equal(distance, distance_np)


@pytest.mark.parametrize("numpy_only", ["", "1"])
def test_feature_gap_beyond_the_nearest_points_is_exact(numpy_only, monkeypatch):
    """Feature sites whose nearest few hundred feature points all lie on their own or related
    curves (a cylinder's rim, sampled finely) get the nearest point of another curve, as a
    loop over all of them gives: with numba one walk of the box tree with the curves as labels,
    without it k-d tree searches bounded by the related curves' points. Sites on two curves
    (−1 padded rows beside them) avoid both curves' relatives."""
    from vorobound.sampling.lfs import features
    from vorobound.sampling.lfs.face_sites import edge_sites
    from vorobound.sampling.lfs.mesh_quality import prepare_mesh
    from vorobound.sampling.lfs.patches import find_patches
    from vorobound.sampling.surfaces.cad_meshes import capped_cylinder

    monkeypatch.setenv("VOROBOUND_PURE_NUMPY", numpy_only)
    prepared = prepare_mesh(capped_cylinder(radius=10.0, length=10.0, segments=64))
    patches = find_patches(prepared, 30.0)
    spacing = 0.001
    feature = edge_sites(
        prepared.points, patches.feature_edges, lambda x, e: np.full(len(x), spacing)
    )
    assert len(feature.points) > 1000
    own = patches.edge_curve[feature.edge]
    curves = np.c_[own, np.full(len(own), -1)]
    curves[::7, 1] = (own[::7] + 1) % patches.curves
    radius = np.full(len(feature.points), np.inf)
    got = features.feature_lfs(feature.points, curves, radius, patches, feature)
    related = patches.curve_adjacent | np.eye(patches.curves, dtype=bool)
    expected = np.full(len(feature.points), np.inf)
    for i, point in enumerate(feature.points):
        far = np.ones(len(own), dtype=bool)
        for curve in curves[i][curves[i] >= 0]:
            far &= ~related[curve, own]
        if far.any():
            expected[i] = np.linalg.norm(feature.points[far] - point, axis=1).min() / 2
    assert np.isfinite(expected[curves[:, 1] < 0]).all()
    np.testing.assert_array_equal(got, expected)


@pytest.mark.parametrize("slope", [0.0, 0.3, 1.0])
def test_face_sites_decided_by_the_spacing_slope_are_the_same(slope):
    """Face sites made with the spacing's Lipschitz constant (pieces kept or split without
    asking the spacing where the bound from their parent decides), or with its floor, are
    the sites made by asking at every piece, and the spacing is asked at fewer points."""
    from vorobound.sampling.lfs.face_sites import face_sites
    from vorobound.sampling.surfaces.cad_meshes import gear

    mesh = gear(teeth=12, faces=800, bore=2.0)
    points, faces = mesh.points, mesh.triangles
    normals = np.repeat(np.array([[[0.0, 0.0, 1.0]]]), len(faces), axis=0).repeat(3, axis=1)
    curved = np.zeros(len(faces), dtype=bool)
    centre = np.array([4.0, 1.0, 3.0])
    asked = {}

    def spacing(x, face, key):
        # slope-Lipschitz, smallest near `centre`, at least a floor
        asked[key] = asked.get(key, 0) + len(x)
        return np.maximum(0.2 + slope * np.linalg.norm(x - centre, axis=1), 0.4)

    plain = face_sites(points, faces, normals, curved, lambda x, f: spacing(x, f, "plain"))
    bounded = face_sites(
        points, faces, normals, curved, lambda x, f: spacing(x, f, "bounded"), slope=slope
    )
    for name in ("points", "normals", "face", "areas", "sizes", "corners"):
        assert np.array_equal(getattr(plain, name), getattr(bounded, name)), name
    assert len(plain.points) > 3 * len(faces)  # the faces were cut
    assert asked["bounded"] < asked["plain"]


@pytest.mark.parametrize("slope", [None, 0.3])
def test_face_sites_kept_at_the_spacing_floor_are_the_same(slope):
    """Given a floor of the spacing, pieces no longer than it are kept without asking: the
    sites are those made by asking at every piece, and fewer points are asked; a floor given
    above the spacing's own changes them."""
    from vorobound.sampling.lfs.face_sites import face_sites
    from vorobound.sampling.surfaces.cad_meshes import gear

    mesh = gear(teeth=12, faces=800, bore=2.0)
    points, faces = mesh.points, mesh.triangles
    normals = np.repeat(np.array([[[0.0, 0.0, 1.0]]]), len(faces), axis=0).repeat(3, axis=1)
    curved = np.zeros(len(faces), dtype=bool)
    centre = points[0]
    asked = {}

    def spacing(x, face, key):
        asked[key] = asked.get(key, 0) + len(x)
        return np.maximum(0.05 + 0.3 * np.linalg.norm(x - centre, axis=1), 1.5)

    def cut(key, floor):
        return face_sites(
            points,
            faces,
            normals,
            curved,
            lambda x, f: spacing(x, f, key),
            slope=slope,
            floor=None if floor is None else np.full(len(faces), floor),
        )

    plain, floored, wrong = cut("plain", None), cut("floored", 1.5), cut("wrong", 1.6)
    for name in ("points", "normals", "face", "areas", "sizes", "corners"):
        assert np.array_equal(getattr(plain, name), getattr(floored, name)), name
    assert asked["floored"] < (0.8 if slope is None else 1.0) * asked["plain"]
    assert len(wrong.points) != len(plain.points)


def test_thickness_in_chunks_of_rays_is_the_same(monkeypatch):
    """The rays are cast and reduced RAY_CHUNK at a time (bounded memory): the thickness of a
    batch cut into chunks equals that of the whole batch, hit for hit."""
    from vorobound.sampling.lfs import thickness as module
    from vorobound.sampling.lfs.mesh_quality import prepare_mesh
    from vorobound.sampling.surfaces.cad_meshes import gear

    prepared = prepare_mesh(gear(teeth=12, faces=800, bore=2.0))
    points, faces = prepared.points, prepared.triangles
    rng = np.random.default_rng(3)
    face = rng.integers(0, len(faces), 700)
    corners = points[faces[face]]
    origins = np.einsum("nc,ncd->nd", rng.dirichlet(np.ones(3), len(face)), corners)
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    group = np.arange(len(faces)) % 3  # three groups, the first two not allowed together
    allowed = np.ones((3, 3), dtype=bool)
    allowed[0, 1] = allowed[1, 0] = False
    caster = module.RayCaster(points, faces)
    args = (caster, origins, normals, face, allowed, group, group[face])
    whole = module.thickness(*args, near=np.full(len(face), 1e-3))
    monkeypatch.setattr(module, "RAY_CHUNK", 64)
    chunked = module.thickness(*args, near=np.full(len(face), 1e-3))
    for name in module.FIELDS:
        assert np.array_equal(getattr(whole, name), getattr(chunked, name)), name
    assert np.isfinite(whole.inward).sum() > 600 and np.isfinite(whole.outward).any()


def test_site_slopes_are_the_largest_rate_over_the_nearest_sites():
    """The local rate of change at each site (one k-d tree query per site, the face sites
    asking for more neighbours for their fitted plane) is the brute-force largest
    |L(y) − L(x)|/|y − x| over its SLOPE_NEIGHBOURS nearest sites, at most λ."""
    from vorobound.sampling.lfs.sites import SLOPE_NEIGHBOURS, site_gradients

    rng = np.random.default_rng(5)
    points = rng.normal(size=(400, 3))
    points /= np.linalg.norm(points, axis=1)[:, None]
    lfs = 1 + 0.3 * np.sin(3 * points[:, 0]) + 0.01 * rng.random(len(points))
    kind = rng.integers(0, 3, len(points))
    slopes, planes = site_gradients(points, lfs, rng.integers(0, 2, len(points)), kind, points, 0.5)
    distance = np.linalg.norm(points[:, None] - points[None], axis=2)
    nearest = np.argsort(distance, axis=1)[:, 1 : SLOPE_NEIGHBOURS + 1]
    rows = np.arange(len(points))[:, None]
    rate = np.abs(lfs[nearest] - lfs[:, None]) / distance[rows, nearest]
    assert np.allclose(slopes, np.minimum(rate.max(axis=1), 0.5), rtol=1e-12, atol=0)
    assert (slopes < 0.5).any() and (slopes == 0.5).any()
    assert np.abs(planes[kind == 1]).sum() > 0 and not planes[kind != 1].any()
