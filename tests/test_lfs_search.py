"""The searches behind the speed of ``vorobound lfs`` give what a brute-force loop over every
candidate gives: the largest empty tangent balls, the Lipschitz envelope with site radii, the
feature cap, and the per-site values kept from one refinement round to the next."""

import numpy as np
import pytest

from vorobound.sampling.lfs.tangent_ball import largest_empty_radius, tangent_radius


def _patches(rng):
    """Triangles of three groups: a flat square (z = 1), a curved cap (sphere of radius 2 about
    the origin, above z = 1.2) and a few long slivers (z = −1): (triangles, group)."""
    grid = np.stack(np.meshgrid(np.linspace(-1, 1, 9), np.linspace(-1, 1, 9)), -1)
    corners = grid[:-1, :-1], grid[1:, :-1], grid[1:, 1:], grid[:-1, 1:]
    quads = np.stack([c.reshape(-1, 2) for c in corners], axis=1)
    flat = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    flat = np.concatenate([flat, np.ones(flat.shape[:2] + (1,))], axis=2)
    direction = rng.normal(size=(60, 3, 3)) * 0.2 + [0, 0, 1]
    cap = 2 * direction / np.linalg.norm(direction, axis=2, keepdims=True)
    start = rng.uniform(-1, 1, (10, 2))
    sliver = np.stack(
        [
            np.c_[start, -np.ones(10)],
            np.c_[start + [3, 0.01], -np.ones(10)],
            np.c_[start + [3, 0.0], -np.ones(10)],
        ],
        axis=1,
    )
    triangles = np.concatenate([flat, cap, sliver])
    group = np.repeat([0, 1, 2], [len(flat), len(cap), len(sliver)])
    return triangles, group


def _brute(points, directions, point_group, triangles, triangle_group, allowed, limit):
    out = np.asarray(limit, dtype=float).copy()
    for i in range(len(points)):
        ok = allowed[point_group[i], triangle_group]
        if ok.any() and np.isfinite(out[i]):
            n = int(ok.sum())
            x, d = np.repeat(points[i : i + 1], n, 0), np.repeat(directions[i : i + 1], n, 0)
            t = triangles[ok]
            out[i] = min(out[i], tangent_radius(x, d, t[:, 0], t[:, 1], t[:, 2]).min())
    return out


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_largest_empty_radius_is_the_brute_force_minimum(seed):
    rng = np.random.default_rng(seed)
    triangles, group = _patches(rng)
    count = 400
    points = rng.uniform(-1.2, 1.2, (count, 3)) * [1, 1, 0.8]
    directions = rng.normal(size=(count, 3))
    directions /= np.linalg.norm(directions, axis=1)[:, None]
    point_group = rng.integers(0, 4, count)  # group 3 may touch everything
    allowed = np.ones((4, 3), dtype=bool)
    allowed[0, 0] = allowed[1, 1] = allowed[2, 2] = False
    limit = rng.choice([0.05, 0.5, 3.0, np.inf], count)
    args = (points, directions, point_group, triangles, group, allowed, limit)
    got = largest_empty_radius(*args)
    assert np.array_equal(got, _brute(*args))
    assert (got <= limit).all() and (got < limit).any()


def test_a_ball_tangent_to_a_flat_patch_stops_at_the_plane():
    """From a point one unit below the flat square, straight up: the ball of radius 1/2."""
    rng = np.random.default_rng(0)
    triangles, group = _patches(rng)
    points = np.array([[0.13, -0.21, 0.0], [0.5, 0.5, 0.0]])
    up = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 1.0]])
    allowed = np.array([[True, False, False]])
    got = largest_empty_radius(points, up, np.zeros(2, int), triangles, group, allowed, [5, 0.3])
    assert got == pytest.approx([0.5, 0.3], rel=1e-14)
