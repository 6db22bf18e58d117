"""Theorem 1 against a 60-digit mpmath reference, on ordinary and hard triangles."""

import numpy as np
import pytest
from hard_triangles import families
from mp_reference import reference, relative_error

from vorobound import theorem1_from_edges, weighted_triangles

DELTA_RTOL = 1e-12
RADIUS_RTOL = 1e-13
FAMILIES = families()


@pytest.mark.parametrize("name", sorted(FAMILIES))
def test_delta_matches_mpmath(name):
    points, weights = FAMILIES[name]
    result = weighted_triangles(points, weights)
    assert result.valid.all()
    for i in range(len(points)):
        ref = reference(points[i], weights[i])
        assert relative_error(result.radius_gap[i], ref["delta"]) <= DELTA_RTOL
        assert relative_error(result.circumradius[i], ref["circumradius"]) <= RADIUS_RTOL
        assert (
            relative_error(result.shifted_orthoradius[i], ref["shifted_orthoradius"]) <= RADIUS_RTOL
        )


def test_subtracting_radii_loses_the_digits_theorem1_keeps():
    points, weights = FAMILIES["tiny_weights"]
    result = weighted_triangles(points, weights)
    exact = [reference(points[i], weights[i])["delta"] for i in range(len(points))]
    err_theorem = [relative_error(result.radius_gap[i], exact[i]) for i in range(len(points))]
    err_direct = [relative_error(result.radius_gap_direct[i], exact[i]) for i in range(len(points))]
    # Two radii of size ~1 carry absolute errors ~1e-16; their difference is ~1e-12.
    assert max(err_theorem) <= DELTA_RTOL
    assert np.median(err_direct) > 1e-6


@pytest.mark.parametrize("name", ["random_3d", "obtuse", "tiny_weights"])
def test_edges_only_formula_matches_mpmath(name):
    points, weights = FAMILIES[name]
    by_coords = weighted_triangles(points, weights)
    # Edges opposite the input vertices, as the user would measure them.
    edges = np.stack(
        [np.linalg.norm(points[:, (i + 2) % 3] - points[:, (i + 1) % 3], axis=1) for i in range(3)],
        axis=1,
    )
    result = theorem1_from_edges(edges, weights)
    assert result.valid.all()
    for i in range(len(points)):
        # Reference: a planar triangle with exactly these (float) edge lengths.
        a, b, c = edges[i]
        import mpmath as mp

        with mp.workdps(60):
            a, b, c = (mp.mpf(float(x)) for x in (a, b, c))
            cx = (b * b + c * c - a * a) / (2 * c)
            planar = [[0, 0], [c, 0], [cx, mp.sqrt(b * b - cx * cx)]]
        ref = reference(planar, weights[i])
        assert relative_error(result.radius_gap[i], ref["delta"]) <= 1e-11
    np.testing.assert_allclose(result.radius_gap, by_coords.radius_gap, rtol=1e-9)
    np.testing.assert_allclose(result.k, by_coords.k, rtol=1e-9)


def test_paper_literal_is_delta_plus_min_weight():
    points, weights = FAMILIES["random_2d_signed"]
    result = weighted_triangles(points, weights)
    np.testing.assert_allclose(
        result.paper_literal, result.radius_gap + weights.min(axis=1), rtol=1e-15
    )


def test_correct_link_to_given_weights():
    """R − R̂ for the given weights is delta + w_min/(R̂_t + R̂), not delta + w_min (eq. (32))."""
    rng = np.random.default_rng(11)
    points = rng.standard_normal((50, 3, 2))
    weights = rng.uniform(0.0, 0.05, (50, 3))
    result = weighted_triangles(points, weights)
    for i in range(50):
        ref = reference(points[i], weights[i])
        import mpmath as mp

        with mp.workdps(60):
            given = ref["circumradius"] - mp.sqrt(ref["orthoradius_sq"])
        assert relative_error(result.radius_gap_unshifted[i], given) <= 1e-11


def test_eq32_as_printed_is_not_a_length():
    """Lengths ×s, weights ×s² scale every length by s; eq. (32) as printed does not."""
    rng = np.random.default_rng(12)
    points = rng.standard_normal((30, 3, 2))
    weights = rng.uniform(0.01, 0.05, (30, 3))
    base = weighted_triangles(points, weights)
    scaled = weighted_triangles(points * 10.0, weights * 100.0)
    np.testing.assert_allclose(
        scaled.radius_gap_unshifted, 10.0 * base.radius_gap_unshifted, rtol=1e-12
    )
    ratio = scaled.paper_literal / base.paper_literal
    assert np.all(np.abs(ratio - 10.0) > 0.5)


def test_identity_does_not_need_assumption_1():
    """Weights differing by more than the squared edge still satisfy Theorem 1's identity."""
    rng = np.random.default_rng(5)
    points = rng.standard_normal((60, 3, 3))
    weights = rng.uniform(0, 10, (60, 3))
    result = weighted_triangles(points, weights)
    assert (~result.assumption1_holds).sum() > 30
    for i in np.flatnonzero(~result.assumption1_holds):
        ref = reference(points[i], weights[i])
        assert relative_error(result.radius_gap[i], ref["delta"]) <= DELTA_RTOL
