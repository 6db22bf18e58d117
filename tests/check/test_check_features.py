"""A check that knows sharp features (issue 32, part 2): guide triangles within reach of a
sharp edge or corner are reported apart and do not decide the exit code; the whole-file and
the tiled check split them by the same rule."""

from __future__ import annotations

import json
import warnings

import meshio
import numpy as np
import pytest
from helpers import assert_one_line_error, run_main

import vorobound
from vorobound.errors import VoroboundWarning
from vorobound.sampling.guides.features import (
    FEATURE_REACH,
    SharpFeatures,
    _point_segment,
    feature_reach,
)
from vorobound.sampling.surfaces import cad_meshes

EPS = 0.0250621  # the cube's advised ε at ρ_f = 4 (README's Python workflow)
RHO_F = 4.0


def _brute(points, segments):
    return np.array(
        [_point_segment(p[None, :], segments[:, 0], segments[:, 1]).min() for p in points]
    )


@pytest.mark.parametrize("count", [12, 5000])  # brute-force and k-d tree paths
def test_feature_distance_is_exact(count):
    rng = np.random.default_rng(count)
    start = rng.uniform(-1, 1, (count, 3))
    segments = np.stack([start, start + rng.normal(0, 0.05, (count, 3))], axis=1)
    segments[0, 1] = segments[0, 0]  # a corner: a segment of length 0
    points = rng.uniform(-1.2, 1.2, (400, 3))
    found = SharpFeatures(segments).distance(points)
    np.testing.assert_allclose(found, _brute(points, segments), rtol=1e-12, atol=1e-15)


def test_feature_reach_is_the_smallest_over_the_vertices_in_radii():
    features = SharpFeatures(np.array([[[0.0, 0, 0], [1.0, 0, 0]]]))
    centers = np.array([[0.5, 0.3, 0], [0.5, 0, 0.1], [0.2, 2.0, 0]])
    radii = np.array([0.1, 0.1, 0.5])
    reach = feature_reach(np.array([[0, 1, 2], [0, 2, 2]]), centers, radii, features)
    np.testing.assert_allclose(reach, [1.0, 3.0], rtol=1e-12)
    assert np.isinf(feature_reach(np.array([[0, 1, 2]]), centers, radii, None)).all()


def _write(part, path):
    meshio.write_points_cells(path, part.points, [("triangle", part.triangles)])
    return path


@pytest.fixture(scope="module")
def cube(tmp_path_factory):
    folder = tmp_path_factory.mktemp("cube")
    mesh = _write(cad_meshes.cube(), folder / "cube.stl")
    balls = folder / "cube.npz"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", VoroboundWarning)  # the sharp edges, said elsewhere
        vorobound.sample(mesh=mesh, eps=EPS, output=balls)
    return mesh, balls, folder


CUBE_CHECK = ["--eps", repr(EPS), "--rho-f", "4", "--json"]


@pytest.fixture(scope="module")
def whole_check(cube):
    """The whole-file check of the cube's balls with its outputs: (exit code, stdout, stderr);
    the two tests below read the one run."""
    mesh, balls, folder = cube
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", VoroboundWarning)  # the sharp edges, said elsewhere
        return run_main(
            "check", "--balls", str(balls), "--mesh", str(mesh), *CUBE_CHECK,
            "--out", str(folder / "whole"),
        )  # fmt: skip


def test_cube_edges_are_reported_apart_and_do_not_fail_the_check(cube, whole_check):
    mesh, balls, folder = cube
    code, out, err = whole_check
    data = json.loads(out)
    smooth, features = data["violations_smooth"], data["violations_at_features"]
    assert code == 0 and data["ok"] and not any(smooth.values()), err
    assert data["failures"] == smooth
    # Before the split this check failed: guide triangles at the edges leave the constraint set.
    assert data["outside_constraint_set"] > 0
    assert features["outside_constraint_set"] == data["outside_constraint_set"]
    assert 0 < features["n_guide_triangles"] < data["n_guide_triangles"]
    worst = np.array(features["worst"]["h3_ratio"]["centroid"])
    # The cube is [0, 2]^3: an edge is where two coordinates are 0 or 2, and the worst triangle
    # at the features sits within about FEATURE_REACH ball radii (δL ≤ 2ε) of one.
    near_edge = np.sort(np.minimum(worst, 2 - worst))[:2]
    assert near_edge.max() < FEATURE_REACH * 2 * EPS + 0.05
    rows = _rows(folder / "whole")
    assert rows["at_feature"].sum() == features["n_guide_triangles"]
    assert (rows["at_feature"] == (rows["feature_reach"] <= FEATURE_REACH)).all()
    # Every triangle outside the constraint set has a ball containing an edge point.
    outside = np.asarray(rows["inside"]) == 0
    assert outside.any() and (np.asarray(rows["feature_reach"])[outside] < 1).all()
    vtu = meshio.read(folder / "whole" / "sample.vtu")
    assert "at_feature" in vtu.cell_data


def _rows(folder):
    import pandas as pd

    path = folder / "triangles.parquet"
    if path.exists():
        return pd.read_parquet(path)
    data = np.load(folder / "triangles.npz")
    return {k: data[k] for k in data.files}


def test_the_tiled_check_splits_the_triangles_the_same_way(cube, whole_check, run_cli):
    mesh, balls, folder = cube
    code, whole, _ = whole_check
    common = ["check", "--balls", str(balls), "--mesh", str(mesh), *CUBE_CHECK]
    code_tiled, tiled, err = run_cli(*common, "--workers", "1", "--out", str(folder / "tiled"))
    assert code == code_tiled == 0, err
    whole, tiled = json.loads(whole), json.loads(tiled)
    assert whole["n_guide_triangles"] == tiled["n_guide_triangles"]
    assert whole["violations_smooth"] == tiled["violations_smooth"]
    for key in ("n_guide_triangles", "outside_constraint_set", "quality", "ratio"):
        assert whole["violations_at_features"][key] == tiled["violations_at_features"][key]


@pytest.mark.slow
@pytest.mark.parametrize("name", ["cube", "cylinder"])
def test_coarse_and_fine_exports_give_the_same_smooth_verdict(name, tmp_path):
    """The issue's export dependence: the same part, two exports, the same smooth verdict at
    ε = 0.025; the cylinder is 10 long here to keep it fast (ε = 0.0094977 takes minutes)."""
    pairs = {
        "cube": (cad_meshes.cube(), cad_meshes.cube(4.0)),
        "cylinder": (
            cad_meshes.capped_cylinder(length=10.0, rings=2),
            cad_meshes.capped_cylinder(length=10.0, rings=200, fan_caps=False),
        ),
    }
    verdicts = []
    for tag, part in zip(("coarse", "fine"), pairs[name], strict=True):
        mesh = _write(part, tmp_path / f"{tag}.stl")
        with pytest.warns(VoroboundWarning, match="sharp edges"):  # new mesh, new warning
            result = vorobound.check(mesh=mesh, eps=0.025)
        verdicts.append((result.ok, result.to_dict()["violations_smooth"]))
    assert verdicts[0] == verdicts[1] == (True, dict.fromkeys(verdicts[0][1], 0))


def test_a_surface_option_other_than_a_mesh_is_refused_with_workers(run_cli, tmp_path):
    code, out, err = run_cli(
        "check", "--balls", "x.npz", "--eps", "0.1", "--workers", "2", "--lfs", "1"
    )
    assert_one_line_error(code, out, err)
