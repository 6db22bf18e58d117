"""The numpy shortcuts of the check's nearest-neighbour steps give the bits of the plain forms.

The tiled check takes a tile's pair gaps from the k-d tree's distances and finds covering
balls with column-by-column minima on a tree of its own shape; these tests hold each to the
direct computation it replaces, bit for bit, so a change of scipy or numpy that breaks the
equality shows here.
"""

import numpy as np
from scipy.spatial import cKDTree

from vorobound.sampling.balls import make_balls
from vorobound.sampling.guides.seeds import LIFTED_LEAFSIZE, _row_norm, lifted_balls, other_power
from vorobound.sampling.sampler import conditions
from vorobound.tiling.plan import box_distance


def _points(count=4000, seed=5):
    rng = np.random.default_rng(seed)
    return rng.normal(size=(count, 3)) * [3.0, 1.0, 1e-3] + [1e3, -7.0, 0.5]


def test_owned_pair_gaps_are_the_norms_of_their_differences():
    points = _points()
    owned = points[:, 0] < np.quantile(points[:, 0], 0.7)
    near = conditions.neighbours(points, owned)
    first, second = near.pairs[:, 0], near.pairs[:, 1]
    assert owned[first].all() and len(near.pairs) > 5 * owned.sum()
    want = np.linalg.norm(points[first] - points[second], axis=1)
    assert want.tobytes() == near.gap.tobytes()


def test_other_power_is_the_smallest_power_outside_each_triple():
    rng = np.random.default_rng(6)
    balls = make_balls(_points(3000), 0.2 + 0.3 * rng.random(3000))
    top = float(balls.weights.max())
    tree = cKDTree(lifted_balls(balls, top))
    rows = rng.integers(0, len(balls), (2000, 3))
    # Points on or near the spheres of their rows' first ball, so that some are covered.
    direction = rng.normal(size=(2000, 3))
    direction /= np.linalg.norm(direction, axis=1, keepdims=True)
    scale = balls.radii[rows[:, 0]] * rng.uniform(0.9, 1.1, 2000)
    points = balls.centers[rows[:, 0]] + scale[:, None] * direction
    got = other_power(tree, top, points, rows)
    lifted = lifted_balls(balls, top)
    for leafsize, balanced in ((LIFTED_LEAFSIZE, False), (1, True), (256, False)):
        other = cKDTree(lifted, leafsize=leafsize, balanced_tree=balanced)
        assert other_power(other, top, points, rows).tobytes() == got.tobytes()
    # The plain form: the four nearest lifted balls, the triple's own ones left out.
    query = np.column_stack([points, np.zeros(len(points))])
    bound = np.sqrt(top * (1 + 4e-9))
    dist, index = tree.query(query, k=4, distance_upper_bound=bound)
    own = (index[:, :, None] == rows[:, None, :]).any(axis=2)
    want = np.where(own, np.inf, dist * dist - top).min(axis=1)
    assert np.isfinite(want).any() and np.isinf(want).any()
    assert want.tobytes() == got.tobytes()


def test_box_distance_sums_like_a_row_sum():
    points = _points()
    lo, hi = np.array([999.0, -8.0, 0.4995]), np.array([1001.0, -6.5, 0.5])
    outside = np.maximum(np.maximum(lo - points, points - hi), 0.0)
    want = np.sqrt((outside * outside).sum(axis=1))
    got = box_distance(points, lo, hi)
    assert (want > 0).any() and (want == 0).any()
    assert want.tobytes() == got.tobytes()


def test_seed_normals_are_normalized_like_numpy_norm():
    vectors = _points() - [1e3, -7.0, 0.5]
    want = np.linalg.norm(vectors, axis=1)
    assert want.tobytes() == _row_norm(vectors).tobytes()
