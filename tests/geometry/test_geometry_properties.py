"""Invariances and identities of the weighted-triangle kernel (hypothesis)."""

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from vorobound import weighted_triangles

RTOL = 1e-9
ATOL_REL = 1e-12  # absolute tolerance relative to the circumradius

coords = st.floats(-10, 10, allow_nan=False, allow_infinity=False)
triangles = arrays(np.float64, (3, 3), elements=coords)
weight_sets = arrays(np.float64, (3,), elements=st.floats(-1, 1, allow_nan=False))


def _well_shaped(points) -> bool:
    u, v = points[1] - points[0], points[2] - points[0]
    area2 = np.linalg.norm(np.cross(u, v))
    longest = max(np.linalg.norm(u), np.linalg.norm(v), np.linalg.norm(points[2] - points[1]))
    return longest > 1e-3 and area2 > 1e-3 * longest**2


def _close(x, y, scale):
    np.testing.assert_allclose(x, y, rtol=RTOL, atol=ATOL_REL * scale)


FAST_EXAMPLES = 50
"""Examples of each invariance below in the default run (about 0.4 CPU-s each)."""
FULL_EXAMPLES = 150
"""Examples of each under the slow marker (the ``..._in_full`` twin; CI runs -m slow)."""


def _twins(strategies, body):
    """``body`` as two tests: FAST_EXAMPLES examples by default, FULL_EXAMPLES slow."""
    fast = settings(max_examples=FAST_EXAMPLES, deadline=None)(given(*strategies)(body))
    full = settings(max_examples=FULL_EXAMPLES, deadline=None)(given(*strategies)(body))
    return fast, pytest.mark.slow(full)


def _rigid_motions_keep_radii_and_delta(points, weights, shift, seed):
    assume(_well_shaped(points))
    q, r = np.linalg.qr(np.random.default_rng(seed).standard_normal((3, 3)))
    rot = q * np.sign(np.diag(r))
    base = weighted_triangles(points, weights)
    moved = weighted_triangles(points @ rot.T + shift, weights)
    scale = float(base.circumradius)
    for name in ("circumradius", "shifted_orthoradius", "radius_gap", "orthoradius_sq", "k"):
        _close(
            getattr(moved, name),
            getattr(base, name),
            scale * (scale if name != "radius_gap" else 1),
        )
    _close(moved.orthocenter, base.orthocenter @ rot.T + shift, scale)


test_rigid_motions_keep_radii_and_delta, test_rigid_motions_keep_radii_and_delta_in_full = _twins(
    (triangles, weight_sets, arrays(np.float64, (3,), elements=coords), st.integers(0, 2**32 - 1)),
    _rigid_motions_keep_radii_and_delta,
)


def _vertex_order_does_not_matter(points, weights, perm):
    assume(_well_shaped(points))
    assume(len(set(weights.tolist())) == 3)  # ties would make the apex order-dependent
    base = weighted_triangles(points, weights)
    perm = list(perm)
    other = weighted_triangles(points[perm], weights[perm])
    scale = float(base.circumradius)
    _close(other.radius_gap, base.radius_gap, scale)
    _close(other.k, base.k, scale * scale)
    _close(other.circumcenter, base.circumcenter, scale)
    assert perm[int(other.min_weight_vertex)] == int(base.min_weight_vertex)


test_vertex_order_does_not_matter, test_vertex_order_does_not_matter_in_full = _twins(
    (triangles, weight_sets, st.permutations(range(3))), _vertex_order_does_not_matter
)


def _uniform_weight_shift_eq5(points, weights, alpha):
    """Eq. (5): subtracting α from every weight keeps ẑ and adds α to R̂²."""
    assume(_well_shaped(points))
    base = weighted_triangles(points, weights)
    shifted = weighted_triangles(points, weights - alpha)
    scale = float(base.circumradius)
    _close(shifted.orthocenter, base.orthocenter, scale)
    _close(shifted.orthoradius_sq, base.orthoradius_sq + alpha, scale * scale + abs(alpha))
    _close(shifted.radius_gap, base.radius_gap, scale)


test_uniform_weight_shift_eq5, test_uniform_weight_shift_eq5_in_full = _twins(
    (triangles, weight_sets, st.floats(-5, 5)), _uniform_weight_shift_eq5
)


def _scaling(points, weights, s):
    """Lengths ×s and weights ×s² multiply delta by s."""
    assume(_well_shaped(points))
    base = weighted_triangles(points, weights)
    scaled = weighted_triangles(points * s, weights * s * s)
    _close(scaled.radius_gap, s * base.radius_gap, s * float(base.circumradius))


test_scaling, test_scaling_in_full = _twins(
    (triangles, weight_sets, st.floats(1e-3, 1e3)), _scaling
)


@settings(max_examples=100, deadline=None)
@given(triangles, st.floats(-1, 1))
def test_equal_weights_give_zero_delta(points, w):
    assume(_well_shaped(points))
    result = weighted_triangles(points, [w, w, w])
    assert float(result.radius_gap) == 0.0
    np.testing.assert_allclose(result.orthocenter, result.circumcenter, rtol=0, atol=0)


@settings(max_examples=100, deadline=None)
@given(triangles, weight_sets)
def test_orthocenter_has_equal_powers(points, weights):
    """Eq. (2): |p_i − ẑ|² − w_i is the same for the three vertices."""
    assume(_well_shaped(points))
    result = weighted_triangles(points, weights)
    powers = ((points - result.orthocenter) ** 2).sum(axis=1) - weights
    scale = float(result.circumradius) ** 2 + np.abs(weights).max()
    np.testing.assert_allclose(powers, result.orthoradius_sq, rtol=0, atol=1e-10 * scale)
