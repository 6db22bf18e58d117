"""L of CAD-like meshes (long thin triangles, sharp edges): the same field from a coarse and a
fine triangulation of one part, never above the part's thickness, feature sizes, and samples
made at the ε that ``advise`` recommends."""

import json
import warnings

import meshio
import numpy as np
import pytest

from vorobound.bounds.params import QualityParams
from vorobound.errors import InputError, VoroboundWarning
from vorobound.reports.advisor import advise
from vorobound.sampling.lfs.estimate import estimate_lfs
from vorobound.sampling.sampler import conditions
from vorobound.sampling.sampler.maximal import sample_surface
from vorobound.sampling.surfaces import cad_meshes
from vorobound.sampling.surfaces.mesh import FieldMeshShape, points_on_mesh

AGREE_RTOL = 0.05
"""Target of the issue: L of the coarse and fine copies agree within 5 % at common points."""
COUNT_RTOL = 0.10
"""Target of the issue: the advised sample counts agree within 10 %."""

PARTS = {
    # name: (coarse, fine, true upper bound of L)
    "cylinder": (
        cad_meshes.capped_cylinder(length=20.0, rings=2),
        cad_meshes.capped_cylinder(length=20.0, rings=60, fan_caps=False),
        1.0,
    ),
    "bar": (cad_meshes.box((20.0, 1.0, 1.0)), cad_meshes.box((20.0, 1.0, 1.0), 3.0), 0.5),
    "plate": (cad_meshes.box((12.0, 12.0, 1.0)), cad_meshes.box((12.0, 12.0, 1.0), 1.0), 0.5),
    "cube": (cad_meshes.cube(), cad_meshes.cube(4.0), 1.0),
}


def quiet(mesh, **options):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", VoroboundWarning)
        return estimate_lfs(mesh, **options)


@pytest.fixture(scope="module")
def estimates():
    return {name: (quiet(c), quiet(f), top) for name, (c, f, top) in PARTS.items()}


def surface_points(mesh, count, seed=0):
    return points_on_mesh(mesh, count, np.random.default_rng(seed))


@pytest.mark.parametrize("name", list(PARTS))
def test_coarse_and_fine_triangulations_give_the_same_l(estimates, name):
    coarse, fine, _ = estimates[name]
    points = surface_points(PARTS[name][1], 3000)
    a, b = coarse.at(points), fine.at(points)
    assert (np.abs(a - b) <= AGREE_RTOL * np.minimum(a, b)).all()
    ratio = coarse.surface().inv_lfs_sq_integral / fine.surface().inv_lfs_sq_integral
    assert abs(ratio - 1) <= COUNT_RTOL / 2


@pytest.mark.parametrize("name", list(PARTS))
def test_l_never_exceeds_the_parts_true_size(estimates, name):
    """Half the thickness (bar, plate, cube) or the radius (cylinder) bounds L everywhere;
    the old estimate put 50 on the 12-triangle bar and on the 2-ring cylinder."""
    for estimate, mesh in zip(estimates[name][:2], PARTS[name][:2], strict=True):
        top = estimates[name][2]
        assert estimate.lfs.max() <= top * (1 + 1e-3)
        assert estimate.at(surface_points(mesh, 2000, seed=3)).max() <= top * (1 + 1e-3)
        thickness = estimate.sites.thickness
        finite = np.isfinite(thickness)
        assert (estimate.sites.lfs[finite] <= thickness[finite] / 2 * (1 + 1e-6)).all()


def test_a_thin_cylinder_scales_with_its_radius():
    """r = 1e-3, length 100: L ≤ 1e-3 (it was 50)."""
    estimate = quiet(cad_meshes.capped_cylinder(radius=1e-3, length=100.0, rings=2))
    assert estimate.lfs.max() <= 1e-3 * (1 + 1e-3)
    assert estimate.lfs.min() >= 0.9e-3


def test_feature_sizes_and_integrals_of_a_bar(estimates):
    coarse, fine, _ = estimates["bar"]
    for estimate in (coarse, fine):
        assert estimate.patches == 6 and len(estimate.feature_corners) == 8
        assert estimate.feature_length == pytest.approx(4 * 20 + 8 * 1)
        # L = 0.5 on every feature edge: ∫ ds / L = 2 × length.
        assert estimate.feature_inv_lfs == pytest.approx(2 * (4 * 20 + 8 * 1), rel=1e-6)


def test_advice_is_the_same_for_both_triangulations(estimates):
    quality = QualityParams(0.75, 2.0, 1.38)
    for name in ("cylinder", "bar"):
        coarse, fine, _ = estimates[name]
        a = advise(quality, coarse.surface(), ["tight"]).recommendation
        b = advise(quality, fine.surface(), ["tight"]).recommendation
        assert a.eps == b.eps and a.ball_radius == pytest.approx(b.ball_radius, rel=AGREE_RTOL)
        assert a.samples_high == pytest.approx(b.samples_high, rel=COUNT_RTOL)
        assert a.lattice_candidates == pytest.approx(b.lattice_candidates, rel=COUNT_RTOL)


def test_the_sampler_protects_features_and_uses_the_reported_lipschitz(estimates):
    """Corners are samples (visited first), feature edges carry samples at about the sparsity
    spacing, the sample is an ε-sample of the estimated L and σ-sparse, and L at the samples
    is the field `lfs` reports (its λ)."""
    coarse = estimates["bar"][0]
    shape = FieldMeshShape(coarse, "estimated")
    eps, sigma = 0.2, 0.75
    sample = sample_surface(shape, eps, sigma, seed=2)
    assert sample.lipschitz == coarse.lipschitz == 1.0
    corners = shape.corner_points
    gap = np.linalg.norm(corners[:, None] - sample.points[None], axis=2).min(axis=1)
    assert (gap <= 1e-12).all()
    assert np.allclose(sample.lfs, coarse.at(sample.points), rtol=1e-12)
    probes, probe_lfs = shape.random_points(20_000, np.random.default_rng(5))
    coverage, _ = conditions.coverage(sample.points, eps, probes, probe_lfs)
    assert coverage < 1
    sparse = conditions.sparsity(sample.points, sample.lfs, eps, sigma)
    assert sparse.extreme >= 1 and sparse.violations == 0
    # A long edge of the bar: samples within 1e-9 of it, spaced at most 2σεL apart.
    axis = (np.abs(sample.points[:, 1]) < 1e-9) & (np.abs(sample.points[:, 2]) < 1e-9)
    on_edge = sample.points[axis]
    x = np.sort(on_edge[:, 0])
    assert x[0] <= 1e-12 and x[-1] >= 20 - 1e-12
    assert np.diff(x).max() <= 2.2 * sigma * eps * 0.5


def test_sample_works_at_the_eps_advise_recommends(tmp_path, run_cli):
    """The issue's friction: advise recommended an ε that sample then refused. Here the
    12-triangle cube of side 2 at ρ_f = 4, to keep the test fast (at the default ρ_f it takes
    a minute, docs/lfs.md)."""
    path = tmp_path / "cube.stl"
    part = cad_meshes.cube()
    meshio.write_points_cells(path, part.points, [("triangle", part.triangles)])
    code, out, _ = run_cli("advise", "--mesh", str(path), "--rho-f", "4", "--json")
    assert code == 0
    rec = json.loads(out)["recommendation"]
    assert rec["samplable"] is True and rec["feature_samples_low"] > 0
    out_file = tmp_path / "s.npz"
    eps = repr(rec["eps"])
    code, out, err = run_cli(
        "sample", "--mesh", str(path), "--eps", eps, "-o", str(out_file), "--json"
    )
    assert code == 0, err
    made = json.loads(out)
    assert rec["samples_low"] <= made["n_samples"] <= rec["samples_high"]
    # The slab sampler's certified cells save most of the plain lattice the advice counts.
    assert 0.1 * rec["lattice_candidates"] < made["n_candidates"] < rec["lattice_candidates"]
    assert made["sparsity_violations"] == 0 and made["coverage_max"] < 1


def test_check_of_the_tools_own_mesh_sample_finds_no_lipschitz_violation(tmp_path, run_cli):
    """One Lipschitz story: `check --mesh` samples with the λ `lfs` reports and says so."""
    path = tmp_path / "bar.stl"
    part = cad_meshes.box((4.0, 1.0, 1.0))
    meshio.write_points_cells(path, part.points, [("triangle", part.triangles)])
    code, out, _ = run_cli("lfs", str(path), "--json")
    reported = json.loads(out)["lipschitz"]
    code, out, err = run_cli("check", "--mesh", str(path), "--eps", "0.1", "--json")
    data = json.loads(out)
    # A handful of guide triangles at the sharp edges leave the constraint set (H3 is a
    # smooth-surface property): that, and only that, makes the check exit with 1.
    failed = {kind for kind, count in data["failures"].items() if count}
    assert failed <= {"outside_constraint_set"} and code == (1 if failed else 0), err
    assert data["lipschitz"] == reported == 1.0
    assert data["lipschitz_source"].startswith("of the estimated L")
    assert data["lipschitz_violations"] == 0 and data["sparsity_violations"] == 0
    assert data["coverage_max"] < 1


def test_a_lattice_too_large_is_refused_in_one_line_naming_eps(tmp_path, run_cli):
    """The 100-long cylinder at ε = 0.002 (about 5.9e9 plain-lattice candidates, beyond the
    slab sampler's limit): `sample` refuses before allocating, in one line naming the ε."""
    path = tmp_path / "cylinder.stl"
    part = cad_meshes.capped_cylinder(length=100.0, rings=2)
    meshio.write_points_cells(path, part.points, [("triangle", part.triangles)])
    code, out, err = run_cli("sample", "--mesh", str(path), "--eps", "0.002", "-o", "s.npz")
    assert code == 2 and out == ""
    errors = [line for line in err.strip().splitlines() if not line.startswith("warning:")]
    assert len(errors) == 1 and errors[0].startswith("error: eps=0.002 needs")
    assert "Traceback" not in err


def test_gear_is_a_closed_oriented_cad_export_of_long_thin_triangles():
    """The benchmark gear: about the faces asked for, every edge used once in each direction
    (closed, consistently oriented), positive volume near the annulus's, slivers throughout."""
    from vorobound.sampling.surfaces.cad_meshes import gear, triangle_aspect

    mesh = gear(teeth=200, faces=20_000)
    faces = mesh.triangles
    assert abs(len(faces) - 20_000) < 0.05 * 20_000
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    keys = edges[:, 0] * len(mesh.points) + edges[:, 1]
    reverse = edges[:, 1] * len(mesh.points) + edges[:, 0]
    assert len(np.unique(keys)) == len(keys)
    assert np.array_equal(np.sort(keys), np.sort(reverse))
    p = mesh.points[faces]
    volume = np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6
    root, tip = 100 - 1.25, 100 + 1.0
    assert np.pi * (root**2 - 30**2) * 20 < volume < np.pi * (tip**2 - 30**2) * 20
    assert np.median(triangle_aspect(mesh)) > 100
    with pytest.raises(InputError):
        gear(teeth=200, bore=120.0)
