"""GUDHI's weighted alpha complex as an independent oracle for the signed squared orthoradius."""

import numpy as np
import pytest

from vorobound import weighted_triangles

gudhi = pytest.importorskip("gudhi")
ORACLE_RTOL = 1e-9


@pytest.mark.parametrize("dim", [2, 3])
def test_lone_triangle_value_is_our_orthoradius_sq(dim):
    rng = np.random.default_rng(dim)
    checked = 0
    for _ in range(40):
        points = rng.standard_normal((3, dim))
        weights = rng.uniform(-0.1, 0.2, 3)
        complex_ = gudhi.AlphaComplex(points=points, weights=weights)
        tree = complex_.create_simplex_tree(output_squared_values=True)
        values = [v for simplex, v in tree.get_simplices() if len(simplex) == 3]
        if not values:  # a hidden vertex removes the triangle
            continue
        ours = weighted_triangles(points, weights).orthoradius_sq
        np.testing.assert_allclose(ours, values[0], rtol=ORACLE_RTOL, atol=1e-12)
        checked += 1
    assert checked >= 30
