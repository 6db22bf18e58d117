"""geogram's compiled Delaunay module against CGAL (GUDHI), and the exact range it is given."""

import numpy as np
import pytest

from vorobound.errors import InputError
from vorobound.sampling import geogram_delaunay
from vorobound.sampling.simplices import delaunay_tetrahedra

pytestmark = pytest.mark.skipif(
    not geogram_delaunay.available(), reason="the compiled module was not built"
)


def _cgal(points):
    return delaunay_tetrahedra(points, engine="cgal")


def _circumballs(points, tets):
    """Centre (t, 3) and radius (t,) of each tetrahedron's circumscribed sphere."""
    a, b, c, d = (points[tets[:, i]] for i in range(4))
    m = np.stack([b - a, c - a, d - a], axis=1)
    rhs = 0.5 * np.stack([((b - a) ** 2).sum(1), ((c - a) ** 2).sum(1), ((d - a) ** 2).sum(1)], 1)
    centre = a + np.linalg.solve(m, rhs[..., None])[..., 0]
    return centre, np.linalg.norm(centre - a, axis=1)


def _in_sphere_slack(points, tets):
    """For each tetrahedron, min over the other points of (distance to its circumcentre −
    circumradius) / circumradius: ≥ −1e-9 everywhere for a Delaunay triangulation."""
    from scipy.spatial import cKDTree

    centre, radius = _circumballs(points, tets)
    nearest, _ = cKDTree(points).query(centre)
    return (nearest - radius) / radius


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_random_points_give_cgals_tetrahedra_exactly(seed):
    points = np.random.default_rng(seed).normal(size=(3000, 3))
    found = geogram_delaunay.delaunay_tetrahedra(points)
    assert found is not None and found.dtype == np.int64
    np.testing.assert_array_equal(found, _cgal(points))  # same rows, same order


def test_far_from_origin_and_tiny_scales_give_the_same_triangulation():
    points = np.random.default_rng(3).random((2000, 3))
    reference = geogram_delaunay.delaunay_tetrahedra(points)
    for scale in (2.0**-600, 2.0**-1000, 2.0**40, 2.0**600):  # powers of two: the same points
        np.testing.assert_array_equal(
            geogram_delaunay.delaunay_tetrahedra(points * scale), reference
        )
    np.testing.assert_array_equal(
        geogram_delaunay.delaunay_tetrahedra(points + 1e6), _cgal(points + 1e6)
    )


def test_a_lattice_is_a_delaunay_triangulation_of_the_same_count():
    """Cospherical everywhere: geogram and CGAL perturb differently, each gives a Delaunay
    triangulation: no point strictly inside a circumsphere, the volume of the box, as many
    tetrahedra."""
    g = np.arange(8.0)
    points = np.array(np.meshgrid(g, g, g, indexing="ij")).reshape(3, -1).T.copy()
    found = geogram_delaunay.delaunay_tetrahedra(points)
    assert found is not None and len(found) == len(_cgal(points))
    a, b, c, d = (points[found[:, i]] for i in range(4))
    volume = np.abs(np.einsum("ij,ij->i", b - a, np.cross(c - a, d - a))).sum() / 6
    assert volume == pytest.approx(7.0**3)
    assert _in_sphere_slack(points, found).min() > -1e-9
    shuffled = np.random.default_rng(0).permutation(len(points))
    again = geogram_delaunay.delaunay_tetrahedra(points[shuffled])
    as_before = geogram_delaunay.lexicographic_rows(shuffled[again], len(points))
    np.testing.assert_array_equal(as_before, found)  # the perturbation follows the coordinates


def test_a_subset_keeps_the_tetrahedra_whose_ball_is_empty_of_the_rest():
    """What M̂'s slabs rely on, in degenerate position: a window of a lattice is triangulated
    as the whole lattice wherever a tetrahedron's ball (closed, widened) lies in the window."""
    g = np.arange(10.0)
    points = np.array(np.meshgrid(g, g, g, indexing="ij")).reshape(3, -1).T.copy()
    whole = {tuple(t) for t in geogram_delaunay.delaunay_tetrahedra(points)}
    window = np.flatnonzero(points[:, 0] <= 5)
    part = window[geogram_delaunay.delaunay_tetrahedra(points[window])]
    centre, radius = _circumballs(points, part)
    inside = centre[:, 0] + radius * (1 + 1e-9) < 5.5  # the ball in the window's closed slab
    kept = [tuple(np.sort(t)) for t in part[inside]]
    assert len(kept) > 100
    assert all(t in whole for t in kept)


def test_copies_are_left_out_and_flat_sets_give_no_rows():
    points = np.random.default_rng(4).random((200, 3))
    with_copies = np.vstack([points, points[:30]])
    np.testing.assert_array_equal(geogram_delaunay.delaunay_tetrahedra(with_copies), _cgal(points))
    flat = points.copy()
    flat[:, 2] = 0.0
    found = geogram_delaunay.delaunay_tetrahedra(flat)
    assert found is not None and found.shape == (0, 4)


@pytest.mark.parametrize(
    "bad",
    [
        "nan",
        "inf",
        "spread",  # 1e-300 next to 1: outside the exact range
    ],
)
def test_inputs_outside_the_exact_range_go_to_cgal(bad):
    points = np.random.default_rng(5).random((100, 3))
    if bad == "spread":
        points[0, 0] = 1e-300
        assert geogram_delaunay.exact_frame(points) is None
        assert geogram_delaunay.delaunay_tetrahedra(points) is None
        np.testing.assert_array_equal(delaunay_tetrahedra(points), _cgal(points))
        return
    points[0, 0] = float(bad)
    assert geogram_delaunay.delaunay_tetrahedra(points) is None


def test_subnormal_and_huge_coordinates():
    """1e-320 and 1e308 are input too: subnormal points are scaled up exactly (as CGAL sees
    them), points near the largest double scaled down."""
    points = np.random.default_rng(7).random((300, 3))
    for scale in (1e-320, 1e308):
        given = points * scale
        np.testing.assert_array_equal(delaunay_tetrahedra(given), _cgal(given))
        assert geogram_delaunay.exact_frame(given) is not None


def test_few_points_and_an_unknown_engine():
    points = np.random.default_rng(6).random((4, 3))
    assert geogram_delaunay.delaunay_tetrahedra(points) is None
    assert delaunay_tetrahedra(points).shape == (1, 4)  # CGAL's
    with pytest.raises(InputError, match="engine"):
        delaunay_tetrahedra(points, engine="qhull")


def test_geograms_own_row_order_is_the_same_on_every_call():
    """lfs takes the rows in geogram's order; a tie between equal circumcentres is broken by
    that order, so it must not change between calls (geogram's spatial sort is randomized)."""
    g = np.arange(7.0)
    lattice = np.array(np.meshgrid(g, g, g, indexing="ij")).reshape(3, -1).T.copy()
    for points in (lattice, np.random.default_rng(8).random((3000, 3))):
        first = geogram_delaunay.delaunay_tetrahedra(points, ordered=False)
        for _ in range(3):
            again = geogram_delaunay.delaunay_tetrahedra(points, ordered=False)
            np.testing.assert_array_equal(again, first)


def test_lexicographic_rows_sorts_each_row_and_the_rows():
    rows = np.array([[5, 1, 3, 2], [0, 9, 4, 1], [3, 2, 1, 0], [1, 2, 3, 0]])
    np.testing.assert_array_equal(
        geogram_delaunay.lexicographic_rows(rows, 10),
        [[0, 1, 2, 3], [0, 1, 2, 3], [0, 1, 4, 9], [1, 2, 3, 5]],
    )


@pytest.mark.filterwarnings("ignore::vorobound.errors.VoroboundWarning")  # a coarse torus
def test_lfs_is_the_same_bit_for_bit_on_either_engine(monkeypatch):
    """L of a jittered torus from geogram's tetrahedra in its own row order, and from CGAL's."""
    import vorobound.sampling.lfs.delaunay as lfs_delaunay
    from vorobound.sampling.lfs.estimate import estimate_lfs
    from vorobound.sampling.surfaces.demo_meshes import torus_mesh

    found = {}
    mesh = torus_mesh(3.0, 1.0, 64, 16, jitter=0.2, seed=1)
    found["geogram, its adjacency"] = estimate_lfs(mesh).lfs
    # The other routes: tetrahedra from either engine, neighbours from matching their faces.
    monkeypatch.setattr(lfs_delaunay, "delaunay_neighbours", lambda points: None)
    for engine in ("geogram", "cgal"):
        monkeypatch.setattr(
            lfs_delaunay,
            "engine_tetrahedra",
            lambda points, ordered=True, engine=engine: delaunay_tetrahedra(
                points, engine=engine, ordered=ordered
            ),
        )
        found[engine] = estimate_lfs(torus_mesh(3.0, 1.0, 64, 16, jitter=0.2, seed=1)).lfs
    np.testing.assert_array_equal(found["geogram"], found["cgal"])
    np.testing.assert_array_equal(found["geogram, its adjacency"], found["cgal"])


@pytest.mark.parametrize("kind", ["random", "lattice", "sphere"])
def test_geograms_adjacency_is_the_face_matching(kind):
    """delaunay_neighbours reads the neighbours from geogram's own adjacency: the same array as
    matching the faces of its tetrahedra (scipy's layout: across the face opposite each
    corner, −1 on the hull), in geogram's row order."""
    from vorobound.sampling.simplices import face_neighbours

    rng = np.random.default_rng(11)
    if kind == "random":
        points = rng.random((4000, 3))
    elif kind == "lattice":  # cospherical everywhere: the symbolic perturbation decides
        g = np.arange(6.0)
        points = np.array(np.meshgrid(g, g, g, indexing="ij")).reshape(3, -1).T.copy()
    else:
        points = rng.normal(size=(1500, 3))
        points /= np.linalg.norm(points, axis=1)[:, None]
    tetrahedra, neighbours = geogram_delaunay.delaunay_neighbours(points)
    np.testing.assert_array_equal(
        tetrahedra, geogram_delaunay.delaunay_tetrahedra(points, ordered=False)
    )
    np.testing.assert_array_equal(neighbours, face_neighbours(tetrahedra))
    assert (neighbours == -1).any() and (neighbours >= 0).any()


def test_geograms_adjacency_is_refused_where_points_repeat():
    points = np.random.default_rng(12).random((200, 3))
    assert geogram_delaunay.delaunay_neighbours(np.vstack([points, points[:3]])) is None
    assert geogram_delaunay.delaunay_neighbours(np.zeros((3, 3))) is None  # too few points


# Review (branch georeview): the three tests below failed before the fixes committed after them.


def test_keyboard_interrupt_survives_the_first_call(tmp_path):
    """Bug: GEO::initialize reset SIGINT to its default action (Process::enable_cancel), so after
    the first geogram call Ctrl-C killed the process (exit 130) instead of raising
    KeyboardInterrupt."""
    import subprocess
    import sys

    script = (
        "import os, signal, time\n"
        "import numpy as np\n"
        "from vorobound.sampling import geogram_delaunay\n"
        "assert geogram_delaunay.delaunay_tetrahedra(np.random.default_rng(0).random((20, 3)))"
        " is not None\n"
        "try:\n"
        "    os.kill(os.getpid(), signal.SIGINT)\n"
        "    time.sleep(5)\n"
        "except KeyboardInterrupt:\n"
        "    print('interrupted')\n"
    )
    # Run outside the checkout: `python -c` puts the working folder first on the path, and the
    # source tree holds no built module where the package was installed without -e.
    done = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=60, cwd=tmp_path
    )
    assert (done.returncode, done.stdout, done.stderr) == (0, "interrupted\n", "")


@pytest.mark.parametrize("shape", [(50, 2), (50, 4), (60,)])
def test_points_not_in_three_columns_are_refused(shape):
    """Bug: (n, 2) points were read as n rows of three doubles (past the end of the array) and
    gave tetrahedra; (n, 4) points were triangulated in 4-D by CGAL; a 1-D array hung."""
    points = np.random.default_rng(8).random(shape)
    assert geogram_delaunay.delaunay_tetrahedra(points) is None
    for engine in (None, "geogram", "cgal"):
        with pytest.raises(InputError, match="points"):
            delaunay_tetrahedra(points, engine=engine)


def test_a_copy_is_replaced_by_the_first_point_on_either_engine():
    """Bug: CGAL kept whichever copy its spatial sort met first (the docstring's "a point equal
    to an earlier one is no vertex" held for geogram only), so the engines differed."""
    points = np.random.default_rng(9).random((100, 3))
    with_copies = np.vstack([points[:3], points, points[::7]])
    for ordered in (True, False):
        cgal = delaunay_tetrahedra(with_copies, engine="cgal", ordered=ordered)
        # rows 3..5 and 103.. copy earlier rows
        assert not np.isin(cgal, [3, 4, 5]).any() and cgal.max() < 103
        geogram = delaunay_tetrahedra(with_copies, engine="geogram", ordered=ordered)
        same = np.array_equal if ordered else _same_rows
        assert same(cgal, geogram)


def _same_rows(a, b):
    return a.shape == b.shape and np.array_equal(
        geogram_delaunay.lexicographic_rows(a, 10**6), geogram_delaunay.lexicographic_rows(b, 10**6)
    )


def _side4_exact(points) -> int:
    """geogram's side4 sign of five points in rationals: sign(Δ4) · sign(r), with a_i = p_i − p0,
    Δ_k the 3×3 determinant of the a_i without a_k, q_i = |a_i|² and
    r = −Δ1 q1 + Δ2 q2 − Δ3 q3 + Δ4 q4 (geogram's side4_3d_exact_SOS)."""
    from fractions import Fraction

    p = [[Fraction(float(c)) for c in row] for row in points]
    a = [[p[i][j] - p[0][j] for j in range(3)] for i in range(1, 5)]

    def det3(r0, r1, r2):
        return (
            r0[0] * (r1[1] * r2[2] - r1[2] * r2[1])
            - r1[0] * (r0[1] * r2[2] - r0[2] * r2[1])
            + r2[0] * (r0[1] * r1[2] - r0[2] * r1[1])
        )

    deltas = [det3(*[a[i] for i in range(4) if i != k]) for k in range(4)]
    q = [sum(c * c for c in row) for row in a]
    r = -deltas[0] * q[0] + deltas[1] * q[1] - deltas[2] * q[2] + deltas[3] * q[3]
    sign = lambda v: (v > 0) - (v < 0)  # noqa: E731
    return sign(deltas[3]) * sign(r)


def _orientation(points) -> int:
    """Sign of the orientation of the first four points, in rationals."""
    from fractions import Fraction

    a = [[Fraction(float(points[i][j])) - Fraction(float(points[0][j])) for j in range(3)]
         for i in range(1, 4)]  # fmt: skip
    det = (
        a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
        - a[1][0] * (a[0][1] * a[2][2] - a[0][2] * a[2][1])
        + a[2][0] * (a[0][1] * a[1][2] - a[0][2] * a[1][1])
    )
    return (det > 0) - (det < 0)


def _positive(points):
    """The five points with the first four positively oriented (the first two swapped when
    they are not): geogram asks the in-sphere test only so."""
    return points[[1, 0, 2, 3, 4]] if _orientation(points) < 0 else points


def _on_sphere(rng, n, centre, radius):
    direction = rng.normal(size=(n, 3))
    return centre + radius * direction / np.linalg.norm(direction, axis=1)[:, None]


@pytest.mark.skipif(not geogram_delaunay.available(), reason="compiled module not built")
def test_the_double_double_stage_never_contradicts_rational_arithmetic():
    """Five points on a sphere, rounded (cospherical before rounding: the double filter gives
    up on them), at several scales and distances from the origin: the stage's sign is the
    rational one or 0, and it decides most of them; the whole predicate is always right."""
    rng = np.random.default_rng(7)
    decided = tried = 0
    for scale in (1.0, 2.0**-40, 2.0**30):
        for offset in (0.0, 1.0, 1e6):
            for _ in range(60):
                centre = rng.uniform(-1, 1, 3) * offset * scale
                points = _positive(_on_sphere(rng, 5, centre, scale * rng.uniform(0.01, 1)))
                exact = _side4_exact(points)
                staged, full = geogram_delaunay.side4_stages(points)
                if exact:
                    assert full == exact
                assert staged in (0, exact)
                tried += exact != 0
                decided += staged != 0
    assert decided >= 0.9 * tried


@pytest.mark.skipif(not geogram_delaunay.available(), reason="compiled module not built")
def test_exactly_cospherical_points_are_left_to_the_exact_stage():
    """Lattice points on the sphere x² + y² + z² = 50, scaled by powers of two: r is exactly 0,
    so the stage cannot decide (it answers 0) and the symbolic perturbation gives ±1."""
    lattice = np.array(
        [[x, y, z] for x in range(-8, 9) for y in range(-8, 9) for z in range(-8, 9)]
    )
    sphere = lattice[(lattice**2).sum(axis=1) == 50].astype(float)
    rng = np.random.default_rng(3)
    for exponent in (-300, -20, 0, 40, 300):
        for _ in range(40):
            points = np.ldexp(sphere[rng.choice(len(sphere), 5, replace=False)], exponent)
            if _orientation(points) == 0:
                continue  # a flat first four: geogram's callers never ask
            points = _positive(points)
            staged, full = geogram_delaunay.side4_stages(points)
            assert staged == 0
            assert full in (-1, 1)


@pytest.mark.skipif(not geogram_delaunay.available(), reason="compiled module not built")
@pytest.mark.parametrize("bad", [np.nan, np.inf, 1e308])
def test_the_stage_gives_up_on_non_finite_or_overflowing_differences(bad):
    points = _positive(_on_sphere(np.random.default_rng(1), 5, np.zeros(3), 1.0))
    points[2, 1] = bad
    points[0, 1] = -1e308 if bad == 1e308 else points[0, 1]
    assert geogram_delaunay.side4_stages(points)[0] == 0


@pytest.mark.skipif(not geogram_delaunay.available(), reason="compiled module not built")
def test_the_stage_changes_no_tetrahedron_on_cospherical_families():
    """Points on the circles where spheres of a lattice meet (VoroCrust's seeds are such
    families), rounded, plus lattice points (exactly cospherical): the triangulation is the
    same array with the double-double stage on and off."""
    rng = np.random.default_rng(11)
    centres = np.array([[x, y, 0.0] for x in range(6) for y in range(6)])
    points = [np.array([[x, y, z] for x in range(5) for y in range(5) for z in range(3)], float)]
    for c in centres:
        angle = rng.uniform(0, 2 * np.pi, 40)
        points.append(c + [0.5, 0, 0] + 0.7 * np.c_[np.zeros(40), np.cos(angle), np.sin(angle)])
    assert _the_stage_changes_nothing(np.concatenate(points))


def _the_stage_changes_nothing(points) -> bool:
    """True when geogram's triangulation of ``points`` is the same array with the double-double
    stage on and off."""
    try:
        geogram_delaunay.set_double_double(False)
        exact_only = delaunay_tetrahedra(points, engine="geogram")
    finally:
        geogram_delaunay.set_double_double(True)
    return np.array_equal(delaunay_tetrahedra(points, engine="geogram"), exact_only)


def _sphere_lattice(radius2, bound):
    """Integer points (k, 3) with x² + y² + z² = radius2 and |coordinates| ≤ bound."""
    axis = np.arange(-bound, bound + 1)
    x, y, z = np.meshgrid(axis, axis, axis, indexing="ij")
    on = x**2 + y**2 + z**2 == radius2
    return np.c_[x[on], y[on], z[on]].astype(float)


@pytest.mark.skipif(not geogram_delaunay.available(), reason="compiled module not built")
def test_the_stage_at_its_threshold_never_contradicts_rational_arithmetic():
    """Exactly cospherical lattice points (x² + y² + z² = 1105) at scales 2^±600, with one or
    two zero coordinates moved by 2^-36..2^-56 of the size: |r| over the sum of its monomials'
    sizes falls around 2^-95, where the stage's bound puts its threshold, so it both decides and
    gives up; whatever it decides is the rational sign (and geogram's whole predicate agrees in
    the exact frame)."""
    sphere = _sphere_lattice(1105, 34)
    sphere = sphere[(sphere == 0).any(axis=1)]
    rng = np.random.default_rng(0)
    answers = {0: 0, 1: 0}
    for _ in range(200):
        points = sphere[rng.choice(len(sphere), 5, replace=False)]
        if _orientation(points) == 0:
            continue  # a flat first four: geogram's callers never ask
        exponent = int(rng.integers(-600, 600))
        points = np.ldexp(points, exponent)
        zeros = np.argwhere(points == 0)
        for i, j in zeros[rng.choice(len(zeros), min(2, len(zeros)), replace=False)]:
            shift = exponent - int(rng.integers(36, 56))
            points[i, j] = np.ldexp(rng.uniform(0.5, 1) * rng.choice([-1, 1]), shift)
        points = _positive(points)
        exact = _side4_exact(points)
        staged = geogram_delaunay.side4_stages(points)[0]
        assert staged in (0, exact)
        if exact:
            answers[abs(staged)] += 1
            assert geogram_delaunay.side4_stages(geogram_delaunay.exact_frame(points))[1] == exact
    assert answers[1] >= 10 and answers[0] >= 10


@pytest.mark.skipif(not geogram_delaunay.available(), reason="compiled module not built")
def test_the_stage_is_right_where_its_products_underflow():
    """A sphere through p0 = 0 and four points at distances 2^0..2^-500 from it (heights about
    the squares of those): products of the small differences fall below 2^-1022, which the
    bound's absolute term covers; most tests are still decided, all rightly."""
    rng = np.random.default_rng(0)
    decided = tried = 0
    for _ in range(300):
        points = np.zeros((5, 3))
        x, y = np.ldexp(rng.uniform(-0.7, 0.7, (2, 4)), -rng.integers(0, 500, 4))
        points[1:] = np.c_[x, y, (x * x + y * y) / (1 + np.sqrt(1 - x * x - y * y))]
        points = _positive(points)
        exact = _side4_exact(points)
        staged = geogram_delaunay.side4_stages(points)[0]
        assert staged in (0, exact)
        tried += exact != 0
        decided += staged != 0
    assert decided >= 0.3 * tried


@pytest.mark.skipif(not geogram_delaunay.available(), reason="compiled module not built")
@pytest.mark.parametrize("family", ["subnormal", "huge", "mixed"])
def test_the_stage_is_right_on_extreme_exponents(family):
    """Coordinates that are multiples of 2^-1074, near 2^1000, or a mix of 2^-1074..2^1023 with
    values near 1 and zeros: the stage's sign is the rational one or 0."""
    rng = np.random.default_rng(5)
    for _ in range(150):
        if family == "subnormal":
            points = rng.integers(-(2**20), 2**20, (5, 3)) * 2.0**-1074
        elif family == "huge":
            points = np.ldexp(_on_sphere(rng, 5, rng.uniform(-0.3, 0.3, 3), 0.5), 1000)
        else:
            exponents = np.where(rng.random((5, 3)) < 0.5, rng.integers(-1074, 1000, (5, 3)), 0)
            points = np.ldexp(rng.uniform(-2, 2, (5, 3)), exponents)
            points[rng.random((5, 3)) < 0.15] = 0.0
        if _orientation(points) == 0:
            continue
        points = _positive(points)
        assert geogram_delaunay.side4_stages(points)[0] in (0, _side4_exact(points))


@pytest.mark.skipif(not geogram_delaunay.available(), reason="compiled module not built")
@pytest.mark.parametrize("copy", [0, 1, 2, 3])
def test_a_repeated_point_is_left_to_the_exact_stage(copy):
    """p4 at the coordinates of p0..p3: r is exactly 0 (a zero row, or two equal rows), so the
    stage answers 0 and the symbolic perturbation decides."""
    points = _positive(_on_sphere(np.random.default_rng(2), 5, np.array([0.3, -0.2, 0.1]), 0.7))
    points[4] = points[copy]
    staged, full = geogram_delaunay.side4_stages(points)
    assert staged == 0
    assert full in (-1, 1)


@pytest.mark.skipif(not geogram_delaunay.available(), reason="compiled module not built")
@pytest.mark.parametrize("where", ["hi", "lo"])
def test_a_part_the_scaling_would_round_to_zero_makes_the_stage_give_up(where):
    """Differences up to 2^1000 next to one of 2^-1074 (a hi part), or a difference 2^1000 +
    2^-1074 (its lo part): the power of two that brings 2^1000 to [1, 2) rounds 2^-1074 to 0,
    so the scaling would not be exact; the stage gives up instead of deciding on other
    numbers (before the fix it answered, rightly only thanks to its absolute slack)."""
    big = 2.0**1000
    points = np.array([[0, 0, 0], [big, 0, 0], [0, big, 0], [0, 0, big], [big / 2, big / 2, 0]])
    if where == "hi":
        points[4, 2] = 2.0**-1074
    else:
        points[0, 0] = -(2.0**-1074)
    assert _orientation(points) == 1 and _side4_exact(points) == -1
    assert geogram_delaunay.side4_stages(points)[0] == 0


@pytest.mark.skipif(not geogram_delaunay.available(), reason="compiled module not built")
def test_the_stage_changes_no_tetrahedron_on_rotated_lattices_and_concentric_spheres():
    """A rotated (rounded) lattice, concentric spheres with a shared set of directions, and a
    sphere with its centre: the same array with the double-double stage on and off."""
    rng = np.random.default_rng(13)
    rotation, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    lattice = np.array([[x, y, z] for x in range(12) for y in range(12) for z in range(12)], float)
    directions = _on_sphere(rng, 1200, np.zeros(3), 1.0)
    families = [
        lattice @ rotation,
        np.concatenate([r * directions for r in (1.0, 2.0, 3.0)]),
        np.concatenate([directions, [[0.0, 0.0, 0.0]]]),
    ]
    for points in families:
        assert _the_stage_changes_nothing(points)
