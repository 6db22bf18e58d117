"""Library entry points refuse what is not a real number instead of guessing."""

import numpy as np
import pytest

from vorobound import theorem1_from_edges, weighted_triangles
from vorobound.errors import InputError

POINTS = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]


@pytest.mark.parametrize(
    "points",
    [
        "0,0 1,0 0,1",
        {"a": 1},
        np.array(POINTS) + 0j,
        [[0, 0], [1, 0], [0]],
    ],
)
def test_non_numeric_or_complex_points_raise_input_error(points):
    with pytest.raises(InputError):
        weighted_triangles(points, [0.0, 0.0, 0.0])


def test_complex_weights_and_edges_raise():
    with pytest.raises(InputError, match="complex"):
        weighted_triangles(POINTS, np.array([0, 0.1, 0.2]) + 1e-3j)
    with pytest.raises(InputError, match="complex"):
        theorem1_from_edges(np.array([3.0, 4.0, 5.0]) + 0j, [0, 0, 0])


def test_masked_entries_make_their_rows_invalid():
    points = np.ma.array(np.tile(np.array(POINTS), (3, 1, 1)))
    points[1, 2, 0] = np.ma.masked
    weights = np.ma.array(np.zeros((3, 3)), mask=[[0, 0, 0], [0, 0, 0], [0, 1, 0]])
    result = weighted_triangles(points, weights)
    assert result.valid.tolist() == [True, False, False]
    assert np.isnan(result.radius_gap[1:]).all()
    assert result.circumradius[0] == pytest.approx(np.sqrt(0.5))
