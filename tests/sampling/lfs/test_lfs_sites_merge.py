"""Issue 35: fewer face sites on CAD parts of long thin triangles, with what L promises kept:
merged thin pieces still tile the faces and lie within s/√3 of their site (as one piece of
the spacing s does), and the feature cap bounds L at every point, not only at the sites."""

import warnings

import numpy as np
import pytest

from vorobound.errors import VoroboundWarning
from vorobound.sampling.lfs.estimate import estimate_lfs
from vorobound.sampling.lfs.face_sites import face_sites, merge_thin
from vorobound.sampling.surfaces import cad_meshes
from vorobound.sampling.surfaces.demo_meshes import torus_mesh
from vorobound.sampling.surfaces.mesh import points_on_mesh


def quiet(mesh, **options):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", VoroboundWarning)
        return estimate_lfs(mesh, **options)


def fan(count: int = 40, length: float = 8.0):
    """A flat fan of ``count`` slivers (length ``length``, width about length·π/2/count) in
    one plane, plus a second fan: two patches."""
    angle = np.linspace(0, np.pi / 2, count + 1)
    rim = length * np.c_[np.cos(angle), np.sin(angle), np.zeros(count + 1)]
    points = np.vstack([np.zeros(3), rim, rim + [0, 0, 5], [0, 0, 5]])
    faces = [(0, k + 1, k + 2) for k in range(count)]
    top = len(points) - 1
    faces += [(top, count + 2 + k, count + 3 + k) for k in range(count)]
    groups = np.r_[np.zeros(count, np.int64), np.ones(count, np.int64)]
    return points, np.array(faces), groups


@pytest.mark.parametrize("batch", [None, 50])
@pytest.mark.parametrize("spacing", [1.0, 4.0])
def test_merged_thin_pieces_tile_the_faces_within_the_spacing(spacing, batch, monkeypatch):
    """Also when the faces are cut in batches (``batch`` first pieces each)."""
    import vorobound.sampling.lfs.face_sites as module

    if batch is not None:
        monkeypatch.setattr(module, "CHUNK_PIECES", batch)
    points, faces, groups = fan()
    normals = np.broadcast_to([0.0, 0.0, 1.0], (len(faces), 3, 3)).copy()
    curved = np.zeros(len(faces), dtype=bool)

    def constant(x, face):
        return np.full(len(x), spacing)

    plain = face_sites(points, faces, normals, curved, constant)
    merged = face_sites(points, faces, normals, curved, constant, groups=groups)
    assert len(merged.points) < len(plain.points)  # slivers: far fewer sites
    assert merged.areas.sum() == pytest.approx(plain.areas.sum(), rel=1e-12)
    # No more surface than one piece of the spacing stands for (its centroid within s/√3).
    assert (merged.reach <= spacing / np.sqrt(3) * (1 + 1e-12)).all()
    # Every corner of every piece lies within the reach of a site of its own patch.
    corners = plain.corners.reshape(-1, 3)
    patch = np.repeat(groups[plain.face], 3)
    from scipy.spatial import cKDTree

    near = cKDTree(merged.points).query_ball_point(corners, merged.reach.max() * (1 + 1e-12))
    site_patch = groups[merged.face]
    for corner, mine, found in zip(corners, patch, near, strict=True):
        found = np.asarray(found, dtype=np.int64)
        gap = np.linalg.norm(merged.points[found] - corner, axis=1)
        assert ((gap <= merged.reach[found] * (1 + 1e-12)) & (site_patch[found] == mine)).any()


def test_merge_thin_leaves_well_shaped_pieces_alone():
    corners = np.array([[[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 0], [0, 1, 0]]])
    area = np.full(2, 0.5)
    chosen, areas, reach = merge_thin(
        corners.astype(float), area, np.full(2, 2**0.5), np.full(2, 5.0), np.zeros(2, np.int64)
    )
    assert chosen.tolist() == [0, 1] and areas.tolist() == [0.5, 0.5] and np.isnan(reach).all()


def strips(count: int = 60, length: float = 6.0, width: float = 0.01):
    """A flat bundle of ``count`` parallel strips (two slivers each, ``length`` long and
    ``width`` wide, side by side), as the walls of an extruded CAD part are meshed."""
    x = width * np.arange(count + 1)
    bottom = np.c_[x, np.zeros(count + 1), np.zeros(count + 1)]
    top = bottom + [0.0, length, 0.0]
    points = np.vstack([bottom, top])
    faces = []
    for k in range(count):
        faces += [(k, k + 1, count + 2 + k), (k, count + 2 + k, count + 1 + k)]
    return points, np.array(faces)


def test_the_merge_grids_join_what_one_grid_leaves(monkeypatch):
    """Several grids (large cubes first, each also shifted) merge the slivers of a bundle of
    strips into far fewer sites than one grid of small cubes, within the same conditions."""
    import vorobound.sampling.lfs.face_sites as module

    points, faces = strips()
    normals = np.broadcast_to([0.0, 0.0, 1.0], (len(faces), 3, 3)).copy()
    curved = np.zeros(len(faces), dtype=bool)
    groups = np.zeros(len(faces), dtype=np.int64)

    def constant(x, face):
        return np.full(len(x), 0.5)

    merged = face_sites(points, faces, normals, curved, constant, groups=groups)
    monkeypatch.setattr(module, "MERGE_PASSES", ((0.25, 0.0),))
    one_grid = face_sites(points, faces, normals, curved, constant, groups=groups)
    assert len(merged.points) < 0.6 * len(one_grid.points)
    assert merged.areas.sum() == pytest.approx(one_grid.areas.sum(), rel=1e-12)
    assert (merged.reach <= 0.5 / np.sqrt(3) * (1 + 1e-12)).all()


def test_pieces_of_different_spacing_are_not_merged():
    """Two sets of slivers interleaved in the same cubes, their spacings 1 % apart (more than
    MERGE_FLAT): every merged site stands for pieces of one set only (its area a multiple of
    that set's piece area)."""
    rng = np.random.default_rng(3)
    count = 4000
    start = rng.uniform(0, 4, (count, 3)) * [1, 1, 0]
    along = np.c_[np.zeros(count), np.full(count, 0.3), np.zeros(count)]
    across = np.c_[np.full(count, 0.002), np.zeros(count), np.zeros(count)]
    xyz = np.stack([start, start + along, start + across], axis=1)
    first = rng.random(count) < 0.5
    area = np.where(first, 1.0, np.pi)  # stand-ins: sums of one kind stay recognizable
    spacing = np.where(first, 1.0, 1.01)
    size = np.linalg.norm(along, axis=1)
    chosen, areas, reach = merge_thin(xyz, area * 1e-6 * size**2, size, spacing, np.zeros(count))
    merged = np.isfinite(reach)
    assert merged.sum() > 50
    units = areas[merged] / (1e-6 * size[chosen][merged] ** 2)
    of_first = np.isclose(units, np.round(units), rtol=0, atol=1e-6)
    of_second = np.isclose(units / np.pi, np.round(units / np.pi), rtol=0, atol=1e-6)
    assert (of_first | of_second).all()
    assert of_first.any() and of_second.any()


@pytest.fixture(scope="module")
def bracket():
    mesh = cad_meshes.l_bracket()
    return mesh, quiet(mesh)


def feature_cap(estimate, x):
    """min over cap points of max(|x − p| − h, L_F(p)), h = radius − L_F."""
    s = estimate.sites
    half = s.cap_radii - s.cap_values
    distance = np.linalg.norm(x[:, None] - s.cap_points[None], axis=2) - half[None]
    return np.maximum(distance, s.cap_values[None]).min(axis=1)


def test_the_feature_cap_bounds_l_everywhere(bracket):
    mesh, estimate = bracket
    assert len(estimate.sites.cap_points)
    x = points_on_mesh(mesh, 3000, np.random.default_rng(5))
    # Near the surface and off it: the cones of the cap hold at every point.
    x = np.vstack([x, x + np.random.default_rng(6).normal(scale=0.3, size=x.shape)])
    assert (estimate.at(x) <= feature_cap(estimate, x) * (1 + 1e-9)).all()


def test_without_features_there_is_no_cap():
    estimate = quiet(torus_mesh(3.0, 1.0, 48, 16, jitter=0.2, seed=1))
    assert len(estimate.sites.cap_points) == 0


@pytest.mark.slow
def test_a_small_gear_has_far_fewer_face_sites_on_its_caps(monkeypatch):
    """The caps of a gear are fans of slivers from the bore to the teeth: merged, their sites
    follow the area, not the faces; the sites still tile the caps."""
    import vorobound.sampling.lfs.face_sites as module

    def gear():  # a new mesh object each time (the estimate is cached on it)
        return cad_meshes.gear(teeth=12, faces=400, width=3.0, bore=3.0)

    def caps(estimate):
        s = estimate.sites
        face = s.kind == 1
        z = s.points[face, 2]
        on_caps = (np.abs(z - z.min()) < 1e-9) | (np.abs(z - z.max()) < 1e-9)
        return int(on_caps.sum()), s.areas[face][on_caps].sum()

    merged_count, merged_area = caps(quiet(gear()))
    monkeypatch.setattr(module, "THIN", 0.0)  # no piece is thin: one site per piece
    plain_count, plain_area = caps(quiet(gear()))
    assert merged_count < 0.75 * plain_count
    assert merged_area == pytest.approx(plain_area, rel=1e-9)


def test_the_spacing_is_the_same_with_the_field_cut_off_at_the_floor():
    """The face spacing max(factor·L, floor) asks the field with a cutoff below which any
    value gives the floor: the spacing is the same to the last bit as with L itself."""
    from vorobound.sampling.lfs.lipschitz import Envelope
    from vorobound.sampling.lfs.sites import _cutoff, spacings

    rng = np.random.default_rng(5)
    sites = rng.uniform(0, 1, (2000, 3))
    field = Envelope(sites, rng.uniform(0.01, 0.2, 2000), 1.0, rng.uniform(0, 0.01, 2000))
    faces = rng.integers(0, 50, 30_000)
    factor = np.where(np.arange(50) % 2 == 0, 0.5, 1.0)
    floor = rng.uniform(0.01, 0.1, 50)
    face_spacing, edge_spacing = spacings(field, factor, floor, floor)
    x = rng.uniform(0, 1, (30_000, 3))
    exact = field(x)
    assert np.array_equal(face_spacing(x, faces), np.maximum(factor[faces] * exact, floor[faces]))
    assert np.array_equal(edge_spacing(x, faces), np.maximum(0.5 * exact, floor[faces]))
    assert ((factor[faces] * exact <= floor[faces]).mean()) > 0.2  # the floor is reached
    # The cutoff t has scale·t ≤ floor and lies within rounding of floor/scale, also for a
    # scale that is not a power of two (0.3: the quotient is rounded up for some floors).
    scale = np.full(10_000, 0.3)
    floors = rng.uniform(1e-3, 1, 10_000)
    cut = _cutoff(floors, scale)
    assert (scale * cut <= floors).all()
    assert np.allclose(cut, floors / scale, rtol=1e-15, atol=0)
    assert (cut < floors / scale).any()


def test_row_labels_are_the_inverse_of_unique_rows():
    """The grouping of merge_thin numbers the rows as np.unique(axis=0) does: packed, with
    ranges too wide to pack, and with values too large for exact integers."""
    from vorobound.sampling.lfs.face_sites import _row_labels

    rng = np.random.default_rng(2)
    key = np.c_[
        rng.integers(0, 5, 5000), rng.integers(-30, -20, 5000), rng.integers(-9, 9, (5000, 3))
    ].astype(float)
    key[:10, 2] = -0.0
    for rows in (key, key * np.r_[1, 2.0**20, 2.0**40, 1, 1], key * np.r_[1, 1, 2.0**48, 1, 1]):
        _, inverse = np.unique(rows, axis=0, return_inverse=True)
        assert np.array_equal(_row_labels(rows), inverse.reshape(-1))


def test_the_face_sites_are_the_same_with_the_field_cut_off_at_the_floor():
    """The sites a round cuts with the spacing of :func:`spacings` (the field's search cut
    off at the floor) are those cut with max(factor·L, floor) from L itself, bit for bit."""
    from vorobound.sampling.lfs.lipschitz import Envelope
    from vorobound.sampling.lfs.sites import spacings

    mesh = cad_meshes.gear(teeth=12, faces=800, bore=2.0)
    points, faces = mesh.points, mesh.triangles
    normals = np.repeat(np.array([[[0.0, 0.0, 1.0]]]), len(faces), axis=0).repeat(3, axis=1)
    curved = np.zeros(len(faces), dtype=bool)
    groups = np.arange(len(faces)) % 7
    rng = np.random.default_rng(4)
    lows = points.min(axis=0)
    sites = lows + np.ptp(points, axis=0) * rng.uniform(0, 1, (300, 3))
    field = Envelope(sites, rng.uniform(0.2, 2.0, 300), 0.5)
    factor = np.where(groups % 2 == 0, 0.5, 1.0)
    corners = points[faces]
    floor = np.linalg.norm(corners - np.roll(corners, -1, axis=1), axis=2).max(axis=1) / 8
    asked = {"floor": 0}

    def exact(x, face):
        value = factor[face] * field(x)
        asked["floor"] += int((value <= floor[face]).sum())
        return np.maximum(value, floor[face])

    face_spacing, _ = spacings(field, factor, floor, floor)
    slope = factor * 0.5 * (1 + 1e-6)
    cut = face_sites(points, faces, normals, curved, face_spacing, slope=slope, groups=groups)
    plain = face_sites(points, faces, normals, curved, exact, slope=slope, groups=groups)
    assert asked["floor"] > 100  # the floor decided many pieces
    for name in ("points", "normals", "face", "areas", "sizes", "reach"):
        assert np.array_equal(getattr(cut, name), getattr(plain, name)), name
    assert cut.corners is None  # with groups the pieces' corners are not kept
