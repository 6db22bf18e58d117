"""Sample-count estimates and surfaces, checked against an actual sample of a sphere."""

import math

import numpy as np
import pytest

from vorobound import VoroboundError
from vorobound.api.surfaces import count_surface
from vorobound.reports.advisor import covering_count, packing_count
from vorobound.sampling.surfaces.analytic import SphereShape, TorusShape
from vorobound.sampling.surfaces.base import planar_area


def maximal_sparse_sample(radius: float, spacing: float, rng, stall: int = 4000) -> np.ndarray:
    """Dart throwing on a sphere until ``stall`` darts in a row fail: a maximal spacing-packing.

    Maximality makes it a covering of radius ``spacing`` as well: any point farther than that
    from every sample could still be added.
    """
    pts = np.empty((0, 3))
    failures = 0
    while failures < stall:
        darts = rng.standard_normal((256, 3))
        darts *= radius / np.linalg.norm(darts, axis=1, keepdims=True)
        for dart in darts:
            if len(pts) == 0 or np.min(np.sum((pts - dart) ** 2, axis=1)) >= spacing**2:
                pts = np.vstack([pts, dart])
                failures = 0
            else:
                failures += 1
    return pts


@pytest.mark.parametrize("eps", [0.2, 0.3])
def test_sphere_counts_bracket_an_actual_sparse_eps_sample(eps):
    radius, sigma = 1.0, 0.75
    surface = SphereShape(radius).counts()  # L = R
    sample = maximal_sparse_sample(radius, sigma * eps * radius, np.random.default_rng(1))
    # It is σ-sparse by construction and an ε-sample because σ < 1 (see the docstring).
    count = len(sample)
    assert covering_count(surface, eps) <= count <= packing_count(surface, eps, sigma)
    # exact Archimedes form: 4R²/(εL)² and 16R²/(σεL)²
    assert covering_count(surface, eps) == pytest.approx(4 / eps**2)
    assert packing_count(surface, eps, sigma) == pytest.approx(16 / (sigma * eps) ** 2)


def test_torus_integral_matches_closed_forms():
    # R ≥ 2r: L = r everywhere, ∫ dA / L² = area / r².
    fat = TorusShape(3.0, 1.0).counts()
    assert fat.inv_lfs_sq_integral == pytest.approx(4 * math.pi**2 * 3.0, rel=1e-10)
    # R < 2r: on the inner side L = distance to the axis; compare with a fine midpoint rule.
    thin = TorusShape(1.5, 1.0).counts()
    phi = (np.arange(200_000) + 0.5) * (2 * math.pi / 200_000)
    rho = 1.5 + np.cos(phi)
    midpoint = 2 * math.pi * np.sum(rho / np.minimum(1.0, rho) ** 2) * (2 * math.pi / 200_000)
    assert thin.inv_lfs_sq_integral == pytest.approx(midpoint, rel=1e-6)
    assert thin.lfs_min == pytest.approx(0.5)


def test_mesh_area_and_sizing(tmp_path):
    meshio = pytest.importorskip("meshio")
    pts = np.array([[0, 0, 0], [2, 0, 0], [0, 2, 0], [2, 2, 0]], dtype=float)
    cells = [("triangle", np.array([[0, 1, 2], [1, 3, 2]]))]
    path = tmp_path / "square.vtk"
    meshio.write(path, meshio.Mesh(pts, cells))
    constant, source = count_surface(mesh=path, lfs=0.5)
    assert source == "given (lfs)" and constant.mesh_lattice
    assert constant.area == pytest.approx(4.0)
    assert constant.inv_lfs_sq_integral == pytest.approx(16.0)
    sizing = tmp_path / "lfs.csv"
    sizing.write_text("lfs\n1\n1\n1\n1\n")
    assert count_surface(mesh=path, sizing=sizing)[0].inv_lfs_sq_integral == pytest.approx(4.0)
    assert planar_area(4.0, 1.0).inv_lfs_sq_integral == pytest.approx(4.0)


@pytest.mark.parametrize(
    "call",
    [
        lambda: SphereShape(-1),
        lambda: TorusShape(1, 2),
        lambda: planar_area(1, 0),
        lambda: count_surface(mesh="/no/such/file.stl", lfs=1.0),
    ],
)
def test_bad_surfaces_raise(call):
    with pytest.raises(VoroboundError):
        call()
