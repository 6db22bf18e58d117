"""Local feature size of a mesh: exact-L comparisons, Lipschitz property, sharp edges, bad input,
the fitted edge midpoints (``samples``) and robustness to single-precision coordinates."""

import math
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vorobound.errors import InputError, VoroboundWarning
from vorobound.sampling.io.meshes import TriangleMesh
from vorobound.sampling.lfs import poles as poles_module
from vorobound.sampling.lfs.curved import edge_midpoints
from vorobound.sampling.lfs.estimate import AUTO_SAMPLES, estimate_lfs
from vorobound.sampling.lfs.lipschitz import Envelope, lipschitz_envelope
from vorobound.sampling.lfs.mesh_quality import prepare_mesh, vertex_normals
from vorobound.sampling.lfs.patches import find_patches
from vorobound.sampling.surfaces import analytic as surfaces
from vorobound.sampling.surfaces.base import mesh_counts
from vorobound.sampling.surfaces.cad_meshes import capped_cylinder
from vorobound.sampling.surfaces.demo_meshes import cube_mesh, icosphere, torus_mesh

MEDIAN_RTOL = 1e-3
"""Target of the issue: median relative error of L at the vertices."""
WORST_RTOL = 0.02
"""Target of the issue: largest relative error of L at the vertices."""
ROUNDING = 1e-12
"""Slack for rounding in exact identities (relative to the mesh size)."""
ALL_EDGES = 10**9
"""A sample size that gives every eligible edge a midpoint."""


def quiet_estimate(mesh, **options):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", VoroboundWarning)
        return estimate_lfs(mesh, **options)


def relative_errors(estimate, exact):
    return np.abs(estimate.lfs - exact) / exact


@pytest.fixture(scope="module")
def torus_estimates():
    """Grid tori of the two kinds the issue names (L = r everywhere, and L switching to ρ),
    12 288 vertices, from the vertices only (the default would take seconds more)."""
    found = {}
    for major, minor, around, tube in ((3.0, 1.0, 192, 64), (1.5, 1.0, 192, 64)):
        mesh = torus_mesh(major, minor, around, tube)
        exact = surfaces.TorusShape(major, minor).lfs_at(mesh.points)
        found[(major, minor)] = (mesh, quiet_estimate(mesh, samples=0), exact)
    return found


@pytest.fixture(scope="module")
def coarse_torus():
    """The 3 072-vertex torus (3, 1): its vertices alone miss the median target."""
    mesh = torus_mesh(3.0, 1.0, 96, 32)
    exact = surfaces.TorusShape(3.0, 1.0).lfs_at(mesh.points)
    return mesh, quiet_estimate(mesh, samples=0), quiet_estimate(mesh), exact


@pytest.fixture(scope="module")
def jittered_torus():
    """A 3 072-vertex torus (1.5, 1), vertices moved along the surface by 0.2 grid steps."""
    mesh = torus_mesh(1.5, 1.0, 96, 32, jitter=0.2, seed=1)
    exact = surfaces.TorusShape(1.5, 1.0).lfs_at(mesh.points)
    return mesh, quiet_estimate(mesh, samples=0), quiet_estimate(mesh), exact


@pytest.fixture(scope="module")
def icosphere_default():
    """The 642-vertex icosphere and its default estimate (every edge gets a fitted midpoint)."""
    mesh = icosphere(1.0, 3)
    return mesh, estimate_lfs(mesh)


def test_sphere_is_exact_to_rounding_from_its_vertices():
    """The poles of a sphere's vertices are its centre; L at the vertices is exact to
    rounding. Between them `at` uses the face sites, which lie on the PN surface, inside the
    sphere by about 3e-5·R at this resolution: never above R."""
    mesh = icosphere(2.5, 3)
    estimate = estimate_lfs(mesh, samples=0)
    assert relative_errors(estimate, 2.5).max() < 1e-9
    probes = estimate.sites.points[estimate.sites.kind == 1]
    between = estimate.at(probes)
    assert between.max() <= 2.5 * (1 + 1e-12) and between.min() >= 2.5 * (1 - 1e-4)
    poles = estimate.medial_points
    assert np.abs(poles).max() < 1e-9 * 2.5  # the centre
    assert estimate.warnings == () and len(estimate.sharp_edges) == 0
    assert estimate.sample_count == len(mesh.points) and estimate.added_samples == 0


def test_sphere_with_fitted_midpoints_keeps_the_targets():
    mesh = icosphere(2.5, 3)
    estimate = estimate_lfs(mesh)
    assert estimate.added_samples > 0 and estimate.warnings == ()
    assert relative_errors(estimate, 2.5).max() <= MEDIAN_RTOL


@pytest.mark.parametrize("shape", [(3.0, 1.0), (1.5, 1.0)])
@pytest.mark.slow
def test_torus_vertices_meet_the_accuracy_targets(torus_estimates, shape):
    _, estimate, exact = torus_estimates[shape]
    errors = relative_errors(estimate, exact)
    assert np.median(errors) <= MEDIAN_RTOL
    assert errors.max() <= WORST_RTOL


def test_fitted_midpoints_make_the_coarse_torus_meet_the_targets(coarse_torus):
    mesh, vertices_only, default, exact = coarse_torus
    before, after = relative_errors(vertices_only, exact), relative_errors(default, exact)
    # L = r on this torus: half the thickness along the normal is exact, so the vertices
    # alone now meet the targets (the poles alone missed the median, docs/lfs.md).
    assert np.median(before) <= MEDIAN_RTOL and before.max() <= WORST_RTOL
    assert default.sample_count == len(mesh.points) + len(mesh.points) * 3
    assert np.median(after) <= MEDIAN_RTOL and after.max() <= WORST_RTOL


@pytest.mark.slow
def test_fitted_midpoints_on_the_coarse_torus_with_l_switching(jittered_torus):
    """Documented: the median meets the target; the largest error (near the symmetry axis)
    falls with the midpoints but stays near the target."""
    _, vertices_only, default, exact = jittered_torus
    before = relative_errors(vertices_only, exact)
    after = relative_errors(default, exact)
    assert np.median(after) <= MEDIAN_RTOL
    assert after.max() < 0.05 and after.max() < before.max()


def test_overestimates_stay_small_where_the_largest_error_misses_the_target():
    """Documented in docs/lfs.md: on the 3 072-vertex grid torus (1.5, 1) the default sample
    misses the 2 % target by underestimating L; its largest overestimate (at the inner equator,
    where L is smallest) stays below 1 %."""
    mesh = torus_mesh(1.5, 1.0, 96, 32)
    exact = surfaces.TorusShape(1.5, 1.0).lfs_at(mesh.points)
    signed = (quiet_estimate(mesh).lfs - exact) / exact
    assert signed.min() < -WORST_RTOL  # the documented miss
    assert signed.max() < 0.01


@pytest.mark.slow
def test_torus_with_l_switching_is_resolved_on_both_branches(torus_estimates):
    mesh, estimate, exact = torus_estimates[(1.5, 1.0)]
    near_axis = exact < 0.9  # L = distance to the axis there, not the tube radius
    assert near_axis.sum() > 100 and (~near_axis).sum() > 100
    assert np.median(relative_errors(estimate, exact)[near_axis]) < 1e-2
    assert estimate.lfs.min() == pytest.approx(0.5, rel=WORST_RTOL)


@pytest.mark.slow
def test_jittered_torus_keeps_the_median_target():
    mesh = torus_mesh(1.5, 1.0, 192, 64, jitter=0.2, seed=3)
    errors = relative_errors(
        quiet_estimate(mesh, samples=0), surfaces.TorusShape(1.5, 1.0).lfs_at(mesh.points)
    )
    assert np.median(errors) <= MEDIAN_RTOL
    assert errors.max() < 0.05  # documented: off-axis poles near the symmetry axis


def test_error_falls_with_resolution(coarse_torus):
    mesh = torus_mesh(3.0, 1.0, 48, 16)
    exact = surfaces.TorusShape(3.0, 1.0).lfs_at(mesh.points)
    worst = [relative_errors(quiet_estimate(mesh, samples=0), exact).max()]
    _, vertices_only, _, exact = coarse_torus  # the same torus at 96 × 32, vertices only
    worst.append(relative_errors(vertices_only, exact).max())
    assert worst[1] < worst[0] / 3  # second order in the edge length


@pytest.mark.parametrize("samples", [0, None])
def test_single_precision_coordinates(samples):
    """STL stores float32: its rounding moves ill-conditioned circumcentres (the cocircular
    meridian rings of this torus) far off; they must not become poles."""
    mesh = torus_mesh(3.0, 1.0, 96, 32)
    rounded = TriangleMesh(mesh.points.astype(np.float32).astype(float), mesh.triangles, "f32")
    exact = surfaces.TorusShape(3.0, 1.0).lfs_at(rounded.points)
    errors = relative_errors(quiet_estimate(rounded, samples=samples), exact)
    assert np.median(errors) <= 2 * MEDIAN_RTOL and errors.max() <= WORST_RTOL


def test_noisy_sphere_stays_accurate():
    mesh = icosphere(1.0, 4)
    noise = 1 + 1e-8 * np.random.default_rng(5).standard_normal((len(mesh.points), 1))
    noisy = TriangleMesh(mesh.points * noise, mesh.triangles, "noisy")
    errors = relative_errors(quiet_estimate(noisy, samples=0), np.linalg.norm(noisy.points, axis=1))
    assert errors.max() <= MEDIAN_RTOL


@pytest.mark.parametrize(
    ("shape", "mesh", "deviation_rtol"),
    [
        (surfaces.SphereShape(1.0), icosphere(1.0, 3), 1e-4),
        (surfaces.TorusShape(3.0, 1.0), torus_mesh(3.0, 1.0, 96, 32), 1e-4),
        (surfaces.TorusShape(1.5, 1.0), torus_mesh(1.5, 1.0, 96, 32, jitter=0.2, seed=2), 1e-3),
    ],
)
def test_fitted_midpoints_lie_on_the_smooth_surface(shape, mesh, deviation_rtol):
    """Far closer than the flat triangle's midpoints (up to h²/(8L), 5·10⁻³ h here)."""
    prepared = prepare_mesh(mesh)
    none = np.zeros(len(prepared.edges), dtype=bool)
    added = edge_midpoints(prepared, vertex_normals(prepared), none, ALL_EDGES)
    points = prepared.centre + prepared.scale * added.points
    ends = prepared.points[added.edges]
    length = prepared.scale * np.linalg.norm(ends[:, 1] - ends[:, 0], axis=1)
    deviation = np.linalg.norm(points - shape.project(points)[0], axis=1)
    chord = np.linalg.norm(prepared.centre + prepared.scale * ends.mean(axis=1) - points, axis=1)
    assert len(added.points) == added.eligible >= 0.95 * len(prepared.edges)
    assert (deviation <= deviation_rtol * length).all()
    assert np.median(deviation) < 0.01 * np.median(chord)  # flat midpoints: 100 times farther


@pytest.mark.slow
def test_midpoint_budget_takes_the_longest_edges():
    mesh = torus_mesh(1.5, 1.0, 48, 16, jitter=0.2, seed=4)
    prepared = prepare_mesh(mesh)
    none = np.zeros(len(prepared.edges), dtype=bool)
    normals = vertex_normals(prepared)
    every = edge_midpoints(prepared, normals, none, ALL_EDGES)
    some = edge_midpoints(prepared, normals, none, 100)
    assert len(some.points) == 100 and edge_midpoints(prepared, normals, none, 0).edges.size == 0

    def lengths(edges):
        return np.linalg.norm(np.diff(prepared.points[edges], axis=1)[:, 0], axis=1)

    assert lengths(some.edges).min() >= np.sort(lengths(every.edges))[-100]
    estimate = quiet_estimate(mesh, samples=len(mesh.points) + 100)
    on_features = len(np.unique(estimate.feature_segments))
    assert estimate.added_samples == 100
    assert estimate.sample_count == len(mesh.points) - on_features + 100


def test_default_sample_is_all_midpoints_or_none(monkeypatch, icosphere_default):
    mesh, estimate = icosphere_default  # 642 vertices, 1 920 edges, the default estimate
    assert len(mesh.points) + 1920 <= AUTO_SAMPLES
    assert estimate.added_samples == 1920
    monkeypatch.setattr(poles_module, "AUTO_SAMPLES", 2561)
    mesh = icosphere(1.0, 3)  # a new mesh object: the first one keeps its estimate
    assert estimate_lfs(mesh).added_samples == 0
    assert estimate_lfs(mesh, samples=2562).added_samples == 1920


def test_flat_patches_get_no_midpoints():
    """A cube's faces are flat: their thickness bound is exact, so no poles are fitted."""
    estimate = quiet_estimate(cube_mesh(1.0, 8))
    assert estimate.added_samples == 0 and estimate.patches == 6


def test_no_midpoint_on_a_feature_edge():
    """Fitted midpoints go on the curved wall of a capped cylinder, never on its rims."""
    mesh = capped_cylinder(radius=1.0, length=4.0, segments=24, rings=12)
    estimate = quiet_estimate(mesh)
    prepared = prepare_mesh(mesh)
    patches = find_patches(prepared, 30.0)
    excluded = np.zeros(len(prepared.edges), dtype=bool)
    rims = {tuple(e) for e in np.sort(patches.feature_edges, axis=1).tolist()}
    excluded = np.array([tuple(e) in rims for e in prepared.edges.tolist()])
    added = edge_midpoints(prepared, vertex_normals(prepared), excluded, ALL_EDGES)
    assert excluded.sum() == 2 * 24 and 0 < estimate.added_samples <= len(added.points)
    points = prepared.centre + prepared.scale * added.points
    assert (np.abs(points[:, 2] - 0) > 1e-9).all() and (np.abs(points[:, 2] - 4.0) > 1e-9).all()


def test_vertex_normals_are_exact_on_a_sphere_and_blind_to_orientation():
    mesh = icosphere(1.0, 2)
    flipped = mesh.triangles.copy()
    flipped[::2] = flipped[::2, ::-1]
    for triangles in (mesh.triangles, flipped):
        prepared = prepare_mesh(TriangleMesh(mesh.points, triangles, "s"))
        normals = vertex_normals(prepared)
        cosine = np.abs((normals * prepared.points).sum(axis=1)) / np.linalg.norm(
            prepared.points, axis=1
        )
        assert np.allclose(cosine, 1.0, rtol=0, atol=1e-12)


def test_vertex_values_are_one_lipschitz_and_at_stays_at_or_below_them():
    mesh = torus_mesh(1.5, 1.0, 40, 16)
    estimate = quiet_estimate(mesh)
    _assert_lipschitz(mesh.points, estimate.lfs, 1.0)
    # `at` spreads site values over their pieces: at a vertex it is never above the vertex's
    # own L, and below it only by the face sites' own error (they lie on the PN surface,
    # a few per cent off on this very coarse torus, edges up to 0.6·L).
    at = estimate.at(mesh.points)
    assert (at <= estimate.lfs * (1 + ROUNDING)).all()
    assert (at >= estimate.lfs * 0.95).all()
    probes = np.random.default_rng(0).uniform(-2.5, 2.5, (300, 3))
    _assert_lipschitz(
        np.vstack([mesh.points, probes]), estimate.at(np.vstack([mesh.points, probes])), 1.0
    )


# One path for every slope: 0.5 by default, 0.1 with the slow marker (0.8 CPU-s).
@pytest.mark.parametrize("slope", [pytest.param(0.1, marks=pytest.mark.slow), 0.5])
def test_lipschitz_repair_is_the_envelope_of_the_site_values(slope):
    """L at the sites is min over sites of raw + λ·distance (brute force), and ``at`` is
    min over sites of value + max(a·(x − y), λ·(distance − piece radius)), a the site's
    fitted gradient (at most λ long), everywhere."""
    mesh = torus_mesh(1.5, 1.0, 40, 16)
    repaired = quiet_estimate(mesh, lipschitz=slope)
    assert repaired.lipschitz == slope
    _assert_lipschitz(mesh.points, repaired.lfs, slope)
    sites = repaired.sites
    rows = np.random.default_rng(0).choice(len(sites.points), 300, replace=False)
    distance = np.linalg.norm(sites.points[rows, None] - sites.points[None], axis=2)
    brute = (sites.raw[None, :] + slope * distance).min(axis=1)
    assert np.allclose(sites.lfs[rows], brute, rtol=ROUNDING, atol=0)
    assert (sites.lfs <= sites.raw * (1 + ROUNDING)).all()
    assert (np.linalg.norm(sites.planes, axis=1) <= slope * (1 + ROUNDING)).all()
    assert (np.abs(sites.planes[sites.kind != 1]) == 0).all()
    assert (np.linalg.norm(sites.planes[sites.kind == 1], axis=1) > 0).mean() > 0.5
    probes = np.random.default_rng(1).uniform(-2, 2, (200, 3))
    offset = probes[:, None] - sites.points[None]
    gap = np.linalg.norm(offset, axis=2) - sites.radii
    along = (offset * sites.planes[None]).sum(axis=2)
    expected = (sites.values + np.maximum(along, slope * gap)).min(axis=1)
    assert np.allclose(repaired.at(probes), expected, rtol=ROUNDING, atol=0)


@settings(max_examples=40, deadline=None)
@given(
    count=st.integers(1, 200),
    slope=st.floats(0, 3),
    seed=st.integers(0, 2**31),
)
def test_envelope_matches_brute_force(count, slope, seed):
    rng = np.random.default_rng(seed)
    sites = rng.normal(size=(count, 3)) * rng.choice([1e-3, 1.0, 1e3])
    values = rng.uniform(0, 10, count)
    queries = np.vstack([sites[:5], rng.normal(size=(50, 3))])
    got = lipschitz_envelope(sites, values, slope, queries)
    brute = (values + slope * np.linalg.norm(queries[:, None] - sites[None], axis=2)).min(1)
    assert np.allclose(got, brute, rtol=1e-13, atol=1e-300)


@settings(max_examples=40, deadline=None)
@given(
    count=st.integers(1, 200),
    slope=st.floats(0.01, 3),
    seed=st.integers(0, 2**31),
)
def test_envelope_with_radii_and_gradients_matches_brute_force(count, slope, seed):
    """The tree's search (nodes bounded by the floors) finds the smallest cone exactly."""
    rng = np.random.default_rng(seed)
    scale = rng.choice([1e-3, 1.0, 1e3])
    sites = rng.normal(size=(count, 3)) * scale
    values = rng.uniform(0, 10, count) * scale
    radii = rng.uniform(0, 1, count) * scale * rng.choice([0.0, 0.3, 3.0])
    gradients = rng.normal(size=(count, 3))
    gradients *= (slope * rng.uniform(0, 1, count) / np.linalg.norm(gradients, axis=1))[:, None]
    gradients[rng.uniform(size=count) < 0.3] = 0.0
    queries = np.vstack([sites[:5], rng.normal(size=(50, 3)) * scale])
    got = Envelope(sites, values, slope, radii, gradients=gradients)(queries)
    offset = queries[:, None] - sites[None]
    gap = np.linalg.norm(offset, axis=2) - radii
    cones = values + np.maximum((offset * gradients[None]).sum(axis=2), slope * gap)
    assert np.allclose(got, cones.min(axis=1), rtol=1e-12, atol=1e-300)
    # Each cone is slope-Lipschitz, so their minimum is.
    a, b = queries[:-1], queries[1:]
    rise = np.abs(got[1:] - got[:-1])
    assert (rise <= slope * np.linalg.norm(a - b, axis=1) * (1 + 1e-9) + 1e-300).all()


def test_envelope_refuses_gradients_steeper_than_the_slope():
    with pytest.raises(InputError, match="gradients"):
        Envelope(np.zeros((1, 3)), np.ones(1), 0.5, gradients=np.array([[0.6, 0.0, 0.0]]))


def test_cube_sharp_edges_are_found_and_warned():
    mesh = cube_mesh(1.0, 4)
    with pytest.warns(VoroboundWarning, match="sharp edges"):
        estimate = estimate_lfs(mesh)
    assert len(estimate.sharp_edges) == 12 * 4
    assert estimate.max_dihedral == pytest.approx(90.0)
    ends = mesh.points[estimate.sharp_edges]
    on_cube_edge = (np.isclose(np.abs(ends), 1.0).sum(axis=2) >= 2).all()
    assert on_cube_edge
    assert any("piecewise-smooth" in w for w in estimate.warnings)
    # L of the piecewise-smooth cube [-1, 1]^3: half its side (faces) and half the distance
    # between non-adjacent edges (feature size), whatever the mesh resolution.
    assert np.allclose(estimate.lfs, 1.0, rtol=1e-6)


@pytest.mark.slow
def test_sharp_angle_is_a_threshold():
    mesh = cube_mesh(1.0, 2)
    assert len(quiet_estimate(mesh, sharp_angle=89.0).sharp_edges) == 24
    assert len(quiet_estimate(mesh, sharp_angle=91.0).sharp_edges) == 0


@pytest.mark.slow
def test_advise_surface_from_the_estimate_matches_the_analytic_torus(torus_estimates):
    """The quantity advise uses, ∫ dA / L², from the estimate vs the analytic torus."""
    mesh, estimate, exact = torus_estimates[(1.5, 1.0)]
    analytic = surfaces.TorusShape(1.5, 1.0).counts().inv_lfs_sq_integral
    from_estimate = estimate.surface().inv_lfs_sq_integral
    tri_exact = exact[mesh.triangles].mean(axis=1)
    with_exact_l = mesh_counts("t", mesh.triangle_areas(), tri_exact)
    quadrature = abs(with_exact_l.inv_lfs_sq_integral / analytic - 1)
    estimator = abs(from_estimate / with_exact_l.inv_lfs_sq_integral - 1)
    assert quadrature < 0.01  # flat triangles and the mean L per triangle
    assert estimator < 2 * MEDIAN_RTOL + 0.002
    assert from_estimate == pytest.approx(analytic, rel=0.012)


INCIDENTAL_FLIPPED = (
    r"ignore:mesh flipped. \d+ (edges of curved patches are longer|sharp edges):"
    "vorobound.errors.VoroboundWarning"
)
"""What else the flipped torus's estimate says (coarse edges, a 30.1° edge): true, and not what
the orientation tests are about."""


@pytest.mark.filterwarnings(INCIDENTAL_FLIPPED)
def test_orientation_does_not_matter():
    mesh = torus_mesh(3.0, 1.0, 48, 16)
    flipped = mesh.triangles.copy()
    flipped[::3] = flipped[::3, ::-1]
    with pytest.warns(VoroboundWarning, match="opposite orientation"):
        other = estimate_lfs(TriangleMesh(mesh.points, flipped, "flipped"), samples=0)
    assert np.allclose(other.lfs, quiet_estimate(mesh, samples=0).lfs, rtol=1e-9)


@pytest.mark.filterwarnings(INCIDENTAL_FLIPPED)
@pytest.mark.parametrize(
    "jittered",
    [
        # 768 vertices, jittered as the fixture's: the default run's case (2 s of CPU).
        pytest.param(lambda _: torus_mesh(3.0, 1.0, 48, 16, jitter=0.2, seed=1), id="small"),
        # The 3 072-vertex torus with L switching (50 s of CPU).
        pytest.param(
            lambda request: request.getfixturevalue("jittered_torus")[0],
            id="jittered_torus",
            marks=pytest.mark.slow,
        ),
    ],
)
def test_orientation_does_not_matter_to_the_fitted_midpoints(jittered, request):
    """Up to rounding: the fits of flipped faces differ in the last bits, which can move a
    pole of a nearly degenerate configuration (measured up to 1e-5 on fine meshes)."""
    mesh = jittered(request)
    default = quiet_estimate(mesh)
    flipped = mesh.triangles.copy()
    flipped[::3] = flipped[::3, ::-1]
    with pytest.warns(VoroboundWarning, match="opposite orientation"):
        other = estimate_lfs(TriangleMesh(mesh.points, flipped, "flipped"))
    assert other.added_samples == default.added_samples > 0
    assert np.allclose(other.lfs, default.lfs, rtol=1e-6)


def test_unwelded_mesh_is_merged():
    mesh = icosphere(1.0, 2)
    points = mesh.points[mesh.triangles].reshape(-1, 3)  # STL-like: three points per face
    triangles = np.arange(len(points)).reshape(-1, 3)
    with pytest.warns(VoroboundWarning, match="duplicate vertices were merged"):
        estimate = estimate_lfs(TriangleMesh(points, triangles, "soup"), samples=0)
    assert estimate.mesh_report.boundary_edges == 0
    assert np.allclose(estimate.lfs, 1.0, rtol=1e-9)


@pytest.fixture(scope="module")
def unit_torus():
    """The 48 × 16 torus (3, 1) and its vertices-only L, shared by the four scales below."""
    mesh = torus_mesh(3.0, 1.0, 48, 16)
    return mesh, quiet_estimate(mesh, samples=0).lfs


@pytest.mark.parametrize("scale", [1e-150, 1e-6, 1e6, 1e150])
def test_units_scale(scale, unit_torus):
    mesh, base = unit_torus
    scaled = TriangleMesh(mesh.points * scale, mesh.triangles, "scaled")
    assert np.allclose(quiet_estimate(scaled, samples=0).lfs / scale, base, rtol=1e-6)


@pytest.mark.parametrize("scale", [1e-150, 1e150])
def test_units_scale_with_fitted_midpoints(scale, icosphere_default):
    """Up to rounding of the fits (see the orientation test)."""
    mesh, estimate = icosphere_default
    scaled = TriangleMesh(mesh.points * scale, mesh.triangles, "scaled")
    assert np.allclose(estimate_lfs(scaled).lfs / scale, estimate.lfs, rtol=1e-4)


@pytest.mark.filterwarnings(
    r"ignore:mesh cap. (\d+ vertices belong|the medial estimate|\d+ edges of curved):"
    "vorobound.errors.VoroboundWarning"
)  # what else the cut sphere's estimate says: true, and not what this test is about
def test_open_mesh_warns_but_estimates():
    mesh = icosphere(1.0, 3)
    keep = mesh.points[mesh.triangles].mean(axis=1)[:, 2] > -0.5
    with pytest.warns(VoroboundWarning, match="open"):
        estimate = estimate_lfs(TriangleMesh(mesh.points, mesh.triangles[keep], "cap"))
    assert estimate.mesh_report.boundary_edges > 0 and (estimate.lfs > 0).all()


def test_nonmanifold_edges_are_refused_and_degenerate_faces_warn():
    """A fin on a sphere (an edge of three faces): L along that edge is 0, and the estimate
    gave the sphere's L there (issue 34); without the fin only the degenerate face warns."""
    mesh = icosphere(1.0, 2)
    extra_point = np.vstack([mesh.points, [[0.0, 0.0, 3.0]]])
    a, b, _ = mesh.triangles[0]
    fin = [[a, b, len(mesh.points)]]
    degenerate = [[a, a, b]]
    with pytest.raises(InputError, match="1 edges shared by more than two faces"):
        estimate_lfs(TriangleMesh(extra_point, np.vstack([mesh.triangles, fin]), "fin"))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        estimate = estimate_lfs(
            TriangleMesh(mesh.points, np.vstack([mesh.triangles, degenerate]), "degenerate")
        )
    text = " ".join(str(w.message) for w in caught)
    assert "degenerate faces" in text
    assert estimate.mesh_report.nonmanifold_edges == 0
    assert estimate.mesh_report.degenerate_triangles == 1


@pytest.mark.parametrize(
    ("points", "triangles", "message"),
    [
        (np.zeros((0, 3)), np.zeros((0, 3), int), "shape"),
        (np.eye(3), np.zeros((0, 3), int), "no triangles"),
        (np.array([[0, 0, 0], [1, 0, 0], [0, 1, math.nan]]), np.array([[0, 1, 2]]), "NaN"),
        (np.eye(3), np.array([[0, 1, 5]]), "does not exist"),
        (np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0]]), np.array([[0, 1, 2]]), "degenerate"),
    ],
)
def test_bad_meshes_are_refused(points, triangles, message):
    with pytest.raises(InputError, match=message):
        estimate_lfs(TriangleMesh(np.asarray(points, float), triangles, "bad"))


def test_flat_mesh_is_refused():
    grid = cube_mesh(1.0, 3)
    top = grid.points[grid.triangles].mean(axis=1)[:, 2] > 0.999
    flat = TriangleMesh(grid.points, grid.triangles[top], "square")
    with pytest.raises(InputError, match="coplanar"), warnings.catch_warnings():
        warnings.simplefilter("ignore", VoroboundWarning)
        estimate_lfs(flat)


@pytest.mark.parametrize(
    "options",
    [
        {"lipschitz": 0.0},
        {"lipschitz": math.nan},
        {"lipschitz": math.inf},
        {"lipschitz": 1e-320},
        {"lipschitz": 1e308},
        {"sharp_angle": 0.0},
        {"sharp_angle": 180.0},
        {"samples": -1},
        {"samples": 2.5},
        {"samples": True},
    ],
)
def test_bad_options_are_refused(options):
    with pytest.raises(InputError):
        estimate_lfs(icosphere(1.0, 1), **options)


def test_at_refuses_bad_points():
    estimate = estimate_lfs(icosphere(1.0, 2))
    with pytest.raises(InputError):
        estimate.at(np.array([[math.nan, 0, 0]]))
    with pytest.raises(InputError):
        estimate.at(np.zeros((3, 2)))


def _assert_lipschitz(points, values, slope):
    distance = np.linalg.norm(points[:, None] - points[None], axis=2)
    jump = np.abs(values[:, None] - values[None])
    scale = np.abs(points).max() + np.abs(values).max()
    assert (jump <= slope * distance + ROUNDING * scale).all()


# The same path at two offsets: the farther one (10⁶) by default, 10² with the slow marker.
@pytest.mark.parametrize("offset", [pytest.param(1e2, marks=pytest.mark.slow), 1e6])
def test_a_far_away_part_or_vertex_does_not_blur_the_estimate(offset):
    """Tolerances are local: two spheres far apart, or one stray vertex, keep L = R."""
    sphere = icosphere(2.0, 3)
    count = len(sphere.points)
    twins = TriangleMesh(
        np.vstack([sphere.points, sphere.points + offset]),
        np.vstack([sphere.triangles, sphere.triangles + count]),
        "twins",
    )
    stray = TriangleMesh(np.vstack([sphere.points, [[offset] * 3]]), sphere.triangles, "stray")
    for mesh, on_sphere in ((twins, slice(None)), (stray, slice(0, count))):
        values = quiet_estimate(mesh).lfs[on_sphere]
        assert np.abs(values / 2.0 - 1).max() < 2e-3, mesh.name
