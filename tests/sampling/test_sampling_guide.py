"""Guide triangles: every engine finds the same set as a brute-force search, seeds are right."""

import numpy as np
import pytest

from vorobound.sampling.balls import make_balls
from vorobound.sampling.guides import triangles as guide
from vorobound.sampling.guides.seeds import COVER_RTOL, SEED_RTOL, classify
from vorobound.sampling.sampler.maximal import sample_surface
from vorobound.sampling.surfaces.analytic import SphereShape, TorusShape

DELTA_RATIO = 2.0
SEED_ATOL = 1e-12
"""Seeds from the kernel and from a direct linear solve agree to this (lengths ~1)."""

gudhi = pytest.importorskip("gudhi")

REGULAR_ENGINES = (guide.Engine.gudhi,) + (
    (guide.Engine.geogram,) if guide.geogram_available() else ()
)
"""The engines that read a regular triangulation (geogram's where its module was built)."""


def _balls(shape, eps, seed=0):
    sample = sample_surface(shape, eps, 0.75, seed=seed)
    return make_balls(sample.points, DELTA_RATIO * eps * sample.lfs)


def _as_set(triples):
    return set(map(tuple, np.sort(np.asarray(triples), axis=1).tolist()))


def _reference_guides(balls):
    """Guide and half-covered triples by a separate computation: every triple of pairwise
    overlapping balls from a dense overlap matrix, seeds from 3×3 linear solves, coverage
    against every ball by a dense power matrix."""
    centers, radii = balls.centers, balls.radii
    dist = np.linalg.norm(centers[:, None] - centers[None], axis=2)
    overlap = np.triu(dist < radii[:, None] + radii[None], k=1)
    i, j = np.nonzero(overlap)
    both = overlap[i] & overlap[j]  # k > j adjacent to i and j (k > j since overlap is upper)
    rows, k = np.nonzero(both)
    triples = np.column_stack([i[rows], j[rows], k])
    seeds, exists = _seeds(centers[triples], radii[triples])
    triples, seeds = triples[exists], seeds[exists]
    # A ball covering a seed of (i, j, k) has its center within r_i + r_max of p_i.
    near = dist < radii[:, None] + radii.max()
    r_min_sq = radii[triples].min(axis=1) ** 2
    free = np.empty((len(triples), 2), dtype=bool)
    order = np.argsort(triples[:, 0], kind="stable")
    bounds = np.searchsorted(triples[order, 0], np.arange(len(radii) + 1))
    for first in range(len(radii)):
        rows = order[bounds[first] : bounds[first + 1]]
        if not len(rows):
            continue
        others = np.flatnonzero(near[first])
        power = ((seeds[rows, :, None] - centers[others]) ** 2).sum(3) - radii[others] ** 2
        own = (others[None, :] == triples[rows][:, :, None]).any(axis=1)
        power[np.broadcast_to(own[:, None], power.shape)] = np.inf
        free[rows] = power.min(axis=2) >= COVER_RTOL * r_min_sq[rows, None]
    return _as_set(triples[free.all(1)]), _as_set(triples[free.sum(1) == 1])


def _seeds(p, r):
    """The two points on all three spheres of each triple, and whether they exist."""
    normal = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    matrix = np.stack([2 * (p[:, 1] - p[:, 0]), 2 * (p[:, 2] - p[:, 0]), normal], axis=1)
    sq = (p * p).sum(2) - r * r
    rhs = np.column_stack([sq[:, 1] - sq[:, 0], sq[:, 2] - sq[:, 0], (normal * p[:, 0]).sum(1)])
    center = np.linalg.solve(matrix, rhs[..., None])[..., 0]
    depth_sq = r[:, 0] ** 2 - ((center - p[:, 0]) ** 2).sum(1)
    exists = depth_sq > SEED_RTOL * r.min(axis=1) ** 2
    unit = normal / np.linalg.norm(normal, axis=1, keepdims=True)
    offset = np.sqrt(np.where(exists, depth_sq, 0.0))[:, None] * unit
    return np.stack([center + offset, center - offset], axis=1), exists


def _random_surface_balls(count, seed):
    """Balls on a wavy surface with unequal radii (like someone else's VoroCrust output)."""
    rng = np.random.default_rng(seed)
    u, v = rng.uniform(0, 1, (2, count))
    points = np.column_stack([u, v, 0.1 * np.sin(6 * u) * np.cos(4 * v)])
    radii = 0.07 * (1 + 0.3 * rng.random(count))
    return make_balls(points, radii)


REFERENCE_CASES = {
    "torus-equal-radii": lambda: _balls(TorusShape(3.0, 1.0), 0.25),
    "torus-variable-radii": lambda: _balls(TorusShape(1.5, 1.0), 0.2),
    "wavy-unequal-radii": lambda: _random_surface_balls(400, 1),
}
"""Made in the test, not when the module is collected (every worker collects every module)."""


@pytest.mark.parametrize("case", list(REFERENCE_CASES))
@pytest.mark.slow
def test_engines_agree_with_the_reference(case):
    balls = REFERENCE_CASES[case]()
    reference_guides, reference_halves = _reference_guides(balls)
    assert reference_guides  # the comparison is not vacuous
    for engine in (*REGULAR_ENGINES, guide.Engine.brute):
        found = guide.find_guide_triangles(balls, engine)
        assert _as_set(found.guide.triples) == reference_guides, engine
        halves = found.seeded.triples[found.seeded.half_covered]
        assert _as_set(halves) == reference_halves, engine


# 1 483 balls in 5 slabs of 300 by default (the brute-force reference dominates the cost);
# 3 279 balls in slabs of 800 with the slow marker.
@pytest.mark.parametrize(
    "eps, slab_points", [(0.3, 300), pytest.param(0.2, 800, marks=pytest.mark.slow)]
)
def test_gudhi_slabs_and_filler_agree_with_brute_on_a_larger_sample(monkeypatch, eps, slab_points):
    monkeypatch.setattr(guide, "SLAB_POINTS", slab_points)  # several slabs, each with filler
    balls = _balls(TorusShape(3.0, 1.0), eps)
    assert len(balls) > 3 * slab_points
    by_gudhi = guide.find_guide_triangles(balls, guide.Engine.gudhi)
    by_brute = guide.find_guide_triangles(balls, guide.Engine.brute)
    assert _as_set(by_gudhi.guide.triples) == _as_set(by_brute.guide.triples)
    assert by_gudhi.half_covered == by_brute.half_covered
    assert by_gudhi.candidates < by_brute.candidates / 10
    for slabs in (True, False):  # geogram's exact regular triangulation: the same triples
        triples = [guide.candidate_triples(balls, engine, slabs) for engine in REGULAR_ENGINES]
        assert all(np.array_equal(t, triples[0]) for t in triples)


def test_sphere_with_equal_radii_guides_are_the_hull_facets():
    from scipy.spatial import ConvexHull

    balls = _balls(SphereShape(1.0), 0.15)
    assert guide.equal_radii_on_sphere(balls, 1.0)
    facets = _as_set(ConvexHull(balls.centers).simplices)
    for engine in (guide.Engine.brute, guide.Engine.hull):
        found = guide.find_guide_triangles(balls, engine, cospherical_equal=True)
        assert _as_set(found.guide.triples) == facets
        assert found.half_covered == 0


def test_seeds_lie_on_their_three_spheres_and_match_a_linear_solve():
    balls = _random_surface_balls(300, 2)
    found = guide.find_guide_triangles(balls, guide.Engine.brute)
    seeded = found.seeded
    for row in range(0, len(seeded.triples), 37):
        tri = seeded.triples[row]
        p, r = balls.centers[tri], balls.radii[tri]
        expected, exists = _seeds(p[None], r[None])
        assert exists[0]
        expected = expected[0]
        got = seeded.seeds[row]
        assert np.allclose(got, expected, atol=SEED_ATOL) or np.allclose(
            got[::-1], expected, atol=SEED_ATOL
        )
        dist = np.linalg.norm(got[:, None] - p[None], axis=2)
        assert np.allclose(dist, r[None], atol=SEED_ATOL)


def test_filler_points_keep_their_clearance():
    balls = _balls(TorusShape(3.0, 1.0), 0.2)
    radius = float(balls.radii.max())
    filler = guide.filler_points(balls.centers, radius)
    from scipy.spatial import cKDTree

    dist, _ = cKDTree(balls.centers).query(filler)
    assert len(filler) > 0
    assert dist.min() >= guide.FILLER_CLEARANCE * radius


def test_auto_picks_geogram_where_it_was_built(monkeypatch):
    from vorobound.errors import InputError

    built = guide.geogram_available()
    assert guide.resolve_engine("auto", False) is (
        guide.Engine.geogram if built else guide.Engine.gudhi
    )
    assert guide.resolve_engine("auto", True) is guide.Engine.hull
    monkeypatch.setattr(guide, "geogram_available", lambda: False)
    assert guide.resolve_engine("auto", False) is guide.Engine.gudhi
    with pytest.raises(InputError, match="engine geogram needs"):
        guide.resolve_engine("geogram", False)


def test_classify_handles_no_triples():
    balls = _random_surface_balls(20, 3)
    seeded = classify(balls, np.empty((0, 3), dtype=np.int64))
    assert len(seeded.triples) == 0 and seeded.uncovered.shape == (0, 2)


def test_far_apart_balls_have_no_guide_triangles():
    centers = np.array([[0, 0, 0], [10, 0, 0], [0, 10, 0], [0, 0, 10], [10, 10, 10]], float)
    balls = make_balls(centers, np.ones(5))
    for engine in (*REGULAR_ENGINES, guide.Engine.brute):
        assert len(guide.find_guide_triangles(balls, engine).guide.triples) == 0
