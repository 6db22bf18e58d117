"""One surface protocol (vorobound.sampling.surfaces.base): spheres, tori and meshes answer
the same questions the same way."""

import math

import numpy as np
import pytest

from vorobound.sampling.surfaces.analytic import SphereShape, TorusShape
from vorobound.sampling.surfaces.demo_meshes import icosphere, torus_mesh
from vorobound.sampling.surfaces.mesh import MeshShape


def _torus_mesh_shape():
    mesh = torus_mesh(3.0, 1.0, 96, 32)
    exact = TorusShape(3.0, 1.0).lfs_at(mesh.points)
    return MeshShape(mesh, exact, "exact at the vertices")


SHAPES = {
    "sphere": lambda: SphereShape(2.0),
    "torus": lambda: TorusShape(3.0, 1.0),
    "thin torus": lambda: TorusShape(1.5, 1.0),
    "mesh torus": _torus_mesh_shape,
    "mesh sphere": lambda: MeshShape(icosphere(2.0, 3), np.full(642, 2.0), "constant 2"),
}
EXPECTED = {"sphere": (2, 1), "torus": (0, 1), "thin torus": (0, 1)}
EXPECTED |= {"mesh torus": (0, 1), "mesh sphere": (2, 1)}


@pytest.mark.parametrize("name", sorted(SHAPES))
def test_every_shape_answers_the_protocol(name):
    shape = SHAPES[name]()
    rng = np.random.default_rng(7)
    points, lfs = shape.random_points(2000, rng)
    assert points.shape == (2000, 3) and (lfs > 0).all()
    # Points of the surface are their own closest points, with the same L.
    found = shape.closest(points)
    assert found.distance.max() < 1e-9 * (1 + np.abs(points).max())
    np.testing.assert_allclose(found.points, points, atol=1e-9)
    np.testing.assert_allclose(found.lfs, lfs, rtol=1e-9)
    assert np.allclose(np.linalg.norm(found.normal, axis=1), 1)
    # Moving along the outward normal leaves the solid, moving against it enters it.
    step = 0.05 * lfs[:, None]
    assert shape.inside(points - step * found.normal).all()
    assert not shape.inside(points + step * found.normal).any()
    off = points + 0.3 * lfs[:, None] * rng.normal(size=points.shape)
    projected, projected_lfs = shape.project(off)
    again = shape.closest(projected)
    assert again.distance.max() < 1e-9 * (1 + np.abs(points).max())
    assert (projected_lfs > 0).all()
    top = shape.expected_topology
    assert (top.euler_characteristic, top.components) == EXPECTED[name]


@pytest.mark.parametrize("name", sorted(SHAPES))
def test_counts_agree_with_the_random_points(name):
    """∫ dA/L² = area × mean of 1/L² over points uniform by area (Monte Carlo, 1 %)."""
    shape = SHAPES[name]()
    counts = shape.counts()
    _, lfs = shape.random_points(200_000, np.random.default_rng(3))
    assert counts.inv_lfs_sq_integral == pytest.approx(
        counts.area * float(np.mean(1 / lfs**2)), rel=0.01
    )
    assert counts.lfs_min <= lfs.min() * (1 + 1e-12)


def test_the_torus_writes_its_l_once():
    """L = min(r, ρ): by point, by profile parameter and over intervals, one formula."""
    torus = TorusShape(1.5, 1.0)
    t = np.linspace(0, 2 * math.pi, 1001)
    points = torus.embed(t, np.zeros_like(t))
    np.testing.assert_array_equal(torus.profile_lfs(t), torus.lfs_at(points))
    assert torus.lfs_min(0.0, 2 * math.pi) == pytest.approx(torus.profile_lfs(t).min(), rel=1e-6)
    assert torus.counts().lfs_min == 0.5


def test_a_small_mesh_gets_the_exact_winding_number():
    """A cube (12 triangles, the exact winding number) and an icosphere (the fast one) say
    inside exactly where the shapes are."""
    from vorobound.sampling.surfaces import cad_meshes, mesh

    rng = np.random.default_rng(4)
    points = rng.uniform(-1.5, 1.5, (4000, 3))
    cube = cad_meshes.cube()
    assert len(cube.triangles) <= mesh.EXACT_WINDING_TRIANGLES
    shape = MeshShape(cube, np.ones(len(cube.points)), "constant 1")
    box = np.abs(points - 1).max(axis=1)  # the cube is [0, 2]³
    away = np.abs(box - 1) > 1e-3
    want = box < 1
    np.testing.assert_array_equal(shape.inside(points)[away], want[away])
    sphere = icosphere(1.0, 3)
    assert len(sphere.triangles) > mesh.EXACT_WINDING_TRIANGLES
    shape = MeshShape(sphere, np.ones(len(sphere.points)), "constant 1")
    radius = np.linalg.norm(points, axis=1)
    away = np.abs(radius - 1) > 0.05
    np.testing.assert_array_equal(shape.inside(points)[away], radius[away] < 1)
