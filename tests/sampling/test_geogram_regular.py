"""geogram's regular triangulation, exact for the weights given: its conflict test against
rational arithmetic, its triangulations against CGAL's (GUDHI)."""

from fractions import Fraction

import numpy as np
import pytest

from vorobound.sampling import geogram_delaunay
from vorobound.sampling.balls import make_balls
from vorobound.sampling.guides.triangles import filler_points
from vorobound.sampling.sampler.maximal import sample_surface
from vorobound.sampling.sampler.torus_rows import torus_rows
from vorobound.sampling.surfaces.analytic import TorusShape

pytestmark = pytest.mark.skipif(
    not geogram_delaunay.available(), reason="the compiled module was not built"
)


def _rows(tetrahedra):
    return set(map(tuple, np.sort(np.asarray(tetrahedra), axis=1).tolist()))


def _gudhi(points, weights):
    pytest.importorskip("gudhi")
    from vorobound.sampling.simplices import delaunay_simplices

    _, tetrahedra, _ = delaunay_simplices(points, weights, triangles=False)
    return tetrahedra


def _orthosphere(points, weights):
    """Centre and power radius ρ (|p_i − c|² − w_i = ρ for the four points) of four weighted
    points, in rationals."""
    p = [[Fraction(float(x)) for x in row] for row in points[:4]]
    w = [Fraction(float(x)) for x in weights[:4]]
    # 2 (p_i − p_0)·c = |p_i|² − |p_0|² − (w_i − w_0), i = 1..3, by Cramer's rule.
    rows = [[2 * (p[i][j] - p[0][j]) for j in range(3)] for i in (1, 2, 3)]
    rhs = [sum(x * x for x in p[i]) - sum(x * x for x in p[0]) - (w[i] - w[0]) for i in (1, 2, 3)]

    def det(m):
        return (
            m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
        )

    whole = det(rows)
    centre = []
    for j in range(3):
        swapped = [[rhs[i] if k == j else rows[i][k] for k in range(3)] for i in range(3)]
        centre.append(det(swapped) / whole)
    rho = sum((p[0][j] - centre[j]) ** 2 for j in range(3)) - w[0]
    return centre, rho


def _power_sign(points, weights):
    """Sign of the fifth point's power distance to the orthosphere of the first four: the
    side4 sign geogram's predicate computes (+1: no conflict)."""
    centre, rho = _orthosphere(points, weights)
    q = [Fraction(float(x)) for x in points[4]]
    power = sum((q[j] - centre[j]) ** 2 for j in range(3)) - Fraction(float(weights[4])) - rho
    return (power > 0) - (power < 0)


def _on_the_orthosphere(rng, offset, spread, nudge):
    """Five weighted points whose fifth lies on the orthosphere of the first four up to the
    rounding of its weight, moved by ``nudge`` units in the last place: the exact sign then
    depends on bits of the weight far below the rounding of |p|² − w."""
    points = offset + spread * rng.random((5, 3))
    weights = spread**2 * rng.random(5) * 0.1
    centre, rho = _orthosphere(points, weights)
    q = [Fraction(float(x)) for x in points[4]]
    exact = sum((q[j] - centre[j]) ** 2 for j in range(3)) - rho
    weight = float(exact)
    for _ in range(abs(nudge)):
        weight = np.nextafter(weight, np.inf if nudge > 0 else -np.inf)
    weights[4] = weight
    return points, weights


def test_the_predicate_matches_rational_arithmetic_on_random_inputs():
    rng = np.random.default_rng(0)
    decided = 0
    for _ in range(300):
        points = rng.normal(size=(5, 3))
        weights = rng.random(5) * rng.choice([0.0, 0.1, 3.0])
        filtered, full, _ = geogram_delaunay.side4w_stages(points, weights)
        expected = _power_sign(points, weights)
        assert full == expected
        assert filtered in (0, expected)
        decided += filtered != 0
    assert decided > 250  # the filter decides nearly every generic test


@pytest.mark.parametrize("offset", [0.0, 0.75, 1000.0])
def test_the_predicate_is_exact_where_rounding_the_lifting_flips_the_sign(offset):
    """The point of the change: the fifth point on the orthosphere up to a few units in the
    last place of its weight. The exact predicate follows the weight's bits; geogram's
    original, on |p|² − w rounded to doubles, gets some of these wrong."""
    rng = np.random.default_rng(1)
    lifted_wrong = 0
    for trial in range(200):
        nudge = int(rng.integers(-3, 4))
        points, weights = _on_the_orthosphere(rng, offset, 1e-3 if offset else 1.0, nudge)
        filtered, full, lifted = geogram_delaunay.side4w_stages(points, weights)
        expected = _power_sign(points, weights)
        assert full == expected or (expected == 0 and full != 0), trial  # 0: perturbation
        assert filtered in (0, expected)
        lifted_wrong += expected != 0 and lifted != expected
    assert lifted_wrong > 20  # the flaw the exact weights repair (about a third of them)


def test_the_filter_is_right_around_its_threshold():
    """The fifth weight moved off the orthosphere by 2⁻ᵏ (the spread about 1): the filter
    decides from about k = 40 down (its bound is about 2⁻⁴³ of the size), never wrongly."""
    rng = np.random.default_rng(3)
    decided = {}
    for trial in range(150):
        points, weights = _on_the_orthosphere(rng, 0.0, 1.0, 0)
        k = 30 + trial % 25
        weights[4] += rng.choice([-1.0, 1.0]) * 2.0**-k
        filtered, full, _ = geogram_delaunay.side4w_stages(points, weights)
        expected = _power_sign(points, weights)
        assert full == expected != 0
        assert filtered in (0, expected)
        decided[k] = decided.get(k, 0) + (filtered != 0)
    assert decided[30] == 6 and decided[54] == 0  # far above and far below the threshold
    assert 0 < sum(decided[k] for k in range(36, 46)) < 60  # some near it, not all


def test_the_filter_stays_silent_near_zero_and_out_of_range():
    rng = np.random.default_rng(2)
    points, weights = _on_the_orthosphere(rng, 0.5, 0.01, 0)
    assert geogram_delaunay.side4w_stages(points, weights)[0] == 0
    points = rng.random((5, 3))
    for bad in (np.inf, np.nan, 2.0**30):
        heavy = np.zeros(5)
        heavy[4] = bad
        assert geogram_delaunay.side4w_stages(points, heavy)[0] == 0
    tiny = points * 2.0**-70  # below the filter's smallest spread: the expansions decide
    filtered, full, _ = geogram_delaunay.side4w_stages(tiny, np.zeros(5))
    assert filtered == 0 and full == _power_sign(tiny, np.zeros(5)) != 0


def test_equal_weights_give_the_unweighted_predicate_including_its_perturbation():
    """Cospherical points (a cube's corners): the sign comes from the symbolic perturbation,
    the same in the weighted and the unweighted predicate."""
    corners = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1]], dtype=float)
    for order in ([0, 1, 2, 3, 4], [4, 1, 2, 3, 0], [1, 0, 3, 2, 4], [3, 4, 0, 1, 2]):
        points = corners[order]
        weighted = geogram_delaunay.side4w_stages(points, np.full(5, 0.375))[1]
        assert weighted != 0
        assert weighted == geogram_delaunay.side4_stages(points)[1]


@pytest.mark.parametrize("seed", [0, 1])
def test_random_weighted_points_give_cgals_tetrahedra(seed):
    rng = np.random.default_rng(seed)
    points = rng.random((2000, 3))
    weights = rng.random(2000) * 0.004
    found = geogram_delaunay.regular_tetrahedra(points, weights)
    assert found is not None and found.dtype == np.int64
    np.testing.assert_array_equal(found, geogram_delaunay.lexicographic_rows(found, 2000))
    assert _rows(found) == _rows(_gudhi(points, weights))


def test_hidden_points_are_in_no_tetrahedron_as_in_cgal():
    rng = np.random.default_rng(3)
    points = rng.random((1500, 3))
    weights = rng.random(1500) ** 4 * 0.05  # a few heavy points hide many light ones
    found = geogram_delaunay.regular_tetrahedra(points, weights)
    assert found is not None
    assert len(np.unique(found)) < 1200  # many hidden
    assert _rows(found) == _rows(_gudhi(points, weights))


@pytest.mark.parametrize("seed", [0, 1])
def test_a_lattice_with_weights_below_the_liftings_rounding_gives_cgals_tetrahedra(seed):
    """Cospherical lattice points far from the origin (|p|² about 2,000, whose unit in the last
    place is 2⁻⁴²) with weights below 2⁻⁴⁰: the weights alone decide every in-sphere tie, and a
    lifting rounded to a double would keep two of their twenty bits. Exact for the weights
    given, geogram agrees with CGAL, and not with the unweighted triangulation."""
    rng = np.random.default_rng(seed)
    side = np.arange(7.0) + 20
    points = np.array(np.meshgrid(side, side, side, indexing="ij")).reshape(3, -1).T.copy()
    weights = rng.integers(0, 2**20, len(points)) * 2.0**-60
    found = geogram_delaunay.regular_tetrahedra(points, weights)
    assert _rows(found) == _rows(_gudhi(points, weights))
    assert _rows(found) != _rows(geogram_delaunay.delaunay_tetrahedra(points))


def test_copies_keep_the_heaviest_position():
    rng = np.random.default_rng(4)
    points = rng.random((400, 3))
    light = np.zeros(400)
    heavy = np.full(40, 2e-3)
    both = np.vstack([points, points[:40]])
    found = geogram_delaunay.regular_tetrahedra(both, np.concatenate([light, heavy]))
    used = np.unique(found)
    assert not np.isin(np.arange(40), used).any()  # the lighter copies are hidden
    assert _rows(found) == _rows(_gudhi(both, np.concatenate([light, heavy])))
    found = geogram_delaunay.regular_tetrahedra(both, np.zeros(440))
    assert np.unique(found).max() < 400  # equal weights: the first copy


def _row_balls():
    parts = list(torus_rows(3.0, 1.0, 0.1))
    return make_balls(np.concatenate([c for c, _ in parts]), np.concatenate([r for _, r in parts]))


def _surface_balls():
    sample = sample_surface(TorusShape(1.0, 0.4), 0.12, 0.75, seed=0)
    return make_balls(sample.points, 2.0 * 0.12 * sample.lfs)


@pytest.mark.parametrize("make", [_surface_balls, _row_balls])
def test_torus_balls_with_filler_points_give_cgals_tetrahedra(make):
    """The check's input: the balls of a torus sample (a maximal one, and the row sample of
    the benchmarks, near a lattice) and the filler points around them."""
    balls = make()
    filler = filler_points(balls.centers, float(balls.radii.max()))
    points = np.vstack([balls.centers, filler])
    weights = np.concatenate([balls.weights, np.zeros(len(filler))])
    found = geogram_delaunay.regular_tetrahedra(points, weights)
    assert found is not None and len(filler) > 0
    assert _rows(found) == _rows(_gudhi(points, weights))


def test_a_flat_set_gives_no_cells_and_no_triangles_from_geogram():
    """Points in one plane: geogram makes no cell, so its triangles are refused (None) and the
    check asks CGAL, whose flat triangulation has them."""
    rng = np.random.default_rng(8)
    points = np.column_stack([rng.random((60, 2)), np.zeros(60)])
    weights = rng.random(60) * 1e-3
    assert len(geogram_delaunay.regular_tetrahedra(points, weights)) == 0
    assert geogram_delaunay.regular_triangles(points, weights, 60) is None
    from vorobound.sampling.guides.triangles import Engine, regular_triangles

    pytest.importorskip("gudhi")
    found = regular_triangles(points, weights, Engine.geogram)  # the filler may be empty
    assert len(found) > 0
    np.testing.assert_array_equal(found, regular_triangles(points, weights, Engine.gudhi))


def test_equal_weights_give_the_unweighted_triangulation():
    points = np.random.default_rng(5).normal(size=(3000, 3))
    for weight in (0.0, 0.7):
        np.testing.assert_array_equal(
            geogram_delaunay.regular_tetrahedra(points, np.full(3000, weight)),
            geogram_delaunay.delaunay_tetrahedra(points),
        )


def test_scaling_by_a_power_of_two_changes_nothing():
    rng = np.random.default_rng(6)
    points, weights = rng.random((1000, 3)), rng.random(1000) * 0.01
    reference = geogram_delaunay.regular_tetrahedra(points, weights)
    for k in (-200, 30, 100):
        np.testing.assert_array_equal(
            geogram_delaunay.regular_tetrahedra(np.ldexp(points, k), np.ldexp(weights, 2 * k)),
            reference,
        )


@pytest.mark.parametrize(
    "weights",
    [
        np.array([np.nan]),
        np.array([np.inf]),
        np.array([2.0**320]),
        np.array([2.0**-320]),
        np.array([5e-324]),  # the scaling (points up to 3: by 2⁻⁴) rounds it to zero
    ],
)
def test_weights_outside_the_exact_range_give_none(weights):
    points = 3 * np.random.default_rng(7).random((50, 3))
    heavy = np.zeros(50)
    heavy[:1] = weights
    assert geogram_delaunay.regular_tetrahedra(points, heavy) is None
    assert geogram_delaunay.regular_tetrahedra(points, np.zeros(49)) is None  # wrong shape
    assert geogram_delaunay.regular_tetrahedra(points[:4], np.zeros(4)) is None  # too few
