"""M̂ measured against a mesh with an estimated L: L evaluated only where it can change a
maximum gives the results of evaluating it everywhere."""

import warnings

import numpy as np
import pytest

from vorobound.sampling.lfs.estimate import estimate_lfs
from vorobound.sampling.reconstruct import measure
from vorobound.sampling.reconstruct.facets import inout_facets
from vorobound.sampling.surfaces import cad_meshes
from vorobound.sampling.surfaces.mesh import FieldMeshShape

pytest.importorskip("igl")
pytest.importorskip("gudhi")


@pytest.fixture(scope="module")
def measured_cube():
    """The CAD cube with its estimated L, and an M̂ near it: the seeds are the cube's surface
    points pushed in and out along the normals, jittered."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the cube's sharp edges
        shape = FieldMeshShape(estimate_lfs(cad_meshes.cube()), "estimated")
    rng = np.random.default_rng(4)
    points, triangle = shape.random_points_on(3000, rng)
    normal = shape.normals[triangle]
    offset = 0.02 + 0.01 * rng.random(len(points))
    seeds = np.vstack([points - offset[:, None] * normal, points + offset[:, None] * normal])
    inside = np.repeat([True, False], len(points))
    return shape, inout_facets(seeds, inside).surface


def _measure(shape, surface, monkeypatch, pruned):
    if not pruned:
        monkeypatch.setattr(measure, "_prunable", lambda reference: False)
    return measure.measure_against(surface, shape, 0.05, np.random.default_rng(1))


def test_pruned_measures_are_the_plain_ones(measured_cube, monkeypatch):
    shape, surface = measured_cube
    assert measure._prunable(shape)
    calls = []
    real = shape.lfs_on
    monkeypatch.setattr(shape, "lfs_on", lambda t, p: calls.append(len(p)) or real(t, p))
    pruned = _measure(shape, surface, monkeypatch, True)
    evaluated = sum(calls)
    plain = _measure(shape, surface, monkeypatch, False)
    assert evaluated < 0.8 * (sum(calls) - evaluated)  # L left out at most points
    np.testing.assert_array_equal(pruned.facet_distance, plain.facet_distance)
    np.testing.assert_array_equal(pruned.normal_deviation, plain.normal_deviation)
    for name in ("to_surface", "from_surface"):
        one, two = getattr(pruned, name), getattr(plain, name)
        assert one.value == two.value, name
        np.testing.assert_array_equal(one.where, two.where)
    assert (pruned.points, pruned.probes) == (plain.points, plain.probes)
