"""Batch behaviour: shapes, bad rows, chunking, errors."""

import numpy as np
import pytest

from vorobound import VoroboundError, theorem1_from_edges, weighted_triangles
from vorobound.geometry import triangle as triangle_module


def test_bad_rows_are_masked_not_fatal():
    points = np.array(
        [
            [[0, 0], [1, 0], [0, 1]],  # fine
            [[0, 0], [1, 0], [2, 0]],  # collinear
            [[0, 0], [0, 0], [0, 1]],  # coincident
            [[0, 0], [np.nan, 0], [0, 1]],  # NaN
            [[0, 0], [np.inf, 0], [0, 1]],  # inf
        ],
        dtype=float,
    )
    result = weighted_triangles(points, [0.0, 0.1, 0.2])
    assert result.valid.tolist() == [True, False, False, False, False]
    assert np.isfinite(result.radius_gap[0])
    assert np.isnan(result.radius_gap[1:]).all()
    assert np.isnan(result.circumcenter[1:]).all()


def test_edges_violating_triangle_inequality_are_masked():
    result = theorem1_from_edges([[3, 4, 5], [1, 1, 3], [0, 1, 1], [-1, 1, 1]], [0, 0.1, 0.2])
    assert result.valid.tolist() == [True, False, False, False]


def test_leading_batch_shape_and_broadcast_weights():
    rng = np.random.default_rng(0)
    points = rng.standard_normal((4, 5, 3, 2))
    result = weighted_triangles(points, [0.0, 0.01, 0.02])
    assert result.radius_gap.shape == (4, 5)
    assert result.circumcenter.shape == (4, 5, 2)
    assert result.edges.shape == (4, 5, 3)
    single = weighted_triangles(points[2, 3], [0.0, 0.01, 0.02])
    np.testing.assert_allclose(result.radius_gap[2, 3], single.radius_gap, rtol=1e-15)


def test_chunked_threads_match_one_chunk(monkeypatch):
    rng = np.random.default_rng(1)
    points = rng.standard_normal((1000, 3, 3))
    weights = rng.random((1000, 3)) * 0.1
    whole = weighted_triangles(points, weights)
    monkeypatch.setattr(triangle_module, "CHUNK_ROWS", 64)
    chunked = weighted_triangles(points, weights)
    np.testing.assert_array_equal(chunked.radius_gap, whole.radius_gap)
    np.testing.assert_array_equal(chunked.orthocenter, whole.orthocenter)


def test_extreme_magnitudes_scale_exactly():
    base = weighted_triangles([[1, 0], [-1, 0], [0, 1]], [0, 0.1, 0.2])
    for s in (2.0**400, 2.0**-400):
        far = weighted_triangles([[s, 0], [-s, 0], [0, s]], [0, 0.1 * s * s, 0.2 * s * s])
        assert far.valid
        np.testing.assert_allclose(far.radius_gap / s, base.radius_gap, rtol=1e-15)


@pytest.mark.parametrize(
    "points, weights",
    [(np.zeros((3, 4)), [0, 0, 0]), (np.zeros((2, 2)), [0, 0, 0]), (np.zeros((3, 2)), [0, 0])],
)
def test_wrong_shapes_raise_vorobound_error(points, weights):
    with pytest.raises(VoroboundError):
        weighted_triangles(points, weights)
    assert issubclass(VoroboundError, ValueError)


def test_delta_unshifted_is_nan_when_the_orthoradius_is_imaginary():
    # Equal weights larger than R²: the orthocenter (= circumcenter) is inside all three balls.
    result = weighted_triangles([[0, 0], [1, 0], [0, 1]], [1.0, 1.0, 1.0])
    assert result.orthoradius_sq == pytest.approx(0.5 - 1.0, rel=1e-15)
    assert result.radius_gap == 0.0
    assert np.isnan(result.radius_gap_unshifted)
    real = weighted_triangles([[0, 0], [1, 0], [0, 1]], [0.25, 0.25, 0.25])
    assert real.radius_gap_unshifted == pytest.approx(np.sqrt(0.5) - np.sqrt(0.25), rel=1e-14)
