"""Delaunay tetrahedra from geogram's triangulation, compiled with the package, as one array.

The unweighted triangulations (M̂'s seeds, the Voronoi poles of ``lfs``) came from CGAL through
GUDHI's simplex tree, whose building and reading cost about twice CGAL's own time and most of
the memory (issue 35; docs/performance.md). geogram's Delaunay module (``native/geogram``,
BSD-3-Clause, built by setuptools with the package) triangulates with exact predicates and hands
its tetrahedra over as an array: on 10⁶ random points 5.3 CPU-s and 0.9 GB peak, against 9.3
CPU-s for CGAL's bare build and 30.7 CPU-s and 2.6 GB for the simplex tree route (``python
benchmarks/bench_engines.py delaunay``; docs/performance.md).

Exactness. geogram's predicates are floating-point filters backed by expansion arithmetic, exact as
long as no product underflows or overflows. The points are first multiplied by a power of two so
that the largest coordinate lies in [1/2, 1) (an exact step: it changes no predicate's sign). Every
coordinate then is a multiple of 2⁻²⁰² (its unit in the last place) when the smallest nonzero one is
at least 2⁻¹⁵⁰ (:data:`SMALLEST_SCALED`), so every term of the degree-5 in-sphere determinant and of
its error-free expansions is a multiple of 2⁻¹⁰¹⁰ ≥ 2⁻¹⁰⁷⁴, representable (subnormals included), and
no term exceeds 2¹⁰: no rounding is lost. (The floating-point filters in front of the expansions
give up, and leave the sign to them, whenever their inputs leave the range where their error bound
holds.) Between geogram's double filter and its expansions, the in-sphere test has a double-double
stage with a proven error bound (``native/insphere_dd.cpp`` states the argument): VoroCrust's seeds,
cospherical before rounding, sent many of the tests to the expansions, and the stage halves the
triangulation's time on them (:func:`set_double_double`, ``python benchmarks/bench_engines.py cells
--cube``). Other inputs (wider spreads of magnitude, non-finite values, fewer than five points)
return None, and the caller uses CGAL. Degenerate position is resolved by the lexicographic symbolic
perturbation, a function of the coordinates only, so a subset of the points is triangulated as the
whole set is wherever a tetrahedron's ball holds no other point (what :mod:`.reconstruct.slabs`
needs; CGAL's perturbation has the same property, but the two need not choose the same tetrahedra
among cospherical points). A point at the coordinates of an earlier one gets no tetrahedron.

The regular (weighted Delaunay) triangulation of the check's balls (:func:`regular_tetrahedra`,
:func:`regular_triangles`) runs on geogram's weighted mode changed by vorobound so that it is
exact for the weights given (native/power_predicates.cpp: geogram rounded each lifting |p|² − w
to a double), in :func:`weighted_frame`'s range. On the torus row sample of 10⁶ balls with the
check's filler points it takes about half of CGAL's bare build, and the check's candidate
triples, read in C++ from its cells, come with no simplex tree (``python
benchmarks/bench_engines.py check --sizes 1e6``; docs/performance.md).
"""

from __future__ import annotations

import ctypes
import functools
import importlib.util
import math
import threading

import numpy as np

SMALLEST_SCALED = 2.0**-150
"""Smallest nonzero |coordinate| (after the power-of-two scaling) geogram is given."""
WEIGHT_RANGE = (2.0**-300, 2.0**300)
"""Range of the nonzero |weights| (after the scaling, by the square of the points' factor) the
regular triangulation is given (:func:`weighted_frame`)."""
MAX_POINTS = 10**8
"""More points go to CGAL: geogram's indices are 32-bit, and its arrays of four entries per
tetrahedron (about 6.5 tetrahedra a point, many more in bad cases) would wrap past 2³²."""
MIN_POINTS = 5
"""Fewer points go to CGAL (no gain, and geogram's start needs four in general position)."""
_LOCK = threading.Lock()


@functools.cache
def _library() -> ctypes.CDLL | None:
    spec = importlib.util.find_spec(f"{__package__}._geogram")
    if spec is None or spec.origin is None:
        return None
    try:
        library = ctypes.CDLL(spec.origin)
    except OSError:
        return None
    library.vb_delaunay_cells.argtypes = [
        ctypes.c_void_p,
        ctypes.c_int64,
        ctypes.c_int,
        ctypes.POINTER(ctypes.POINTER(ctypes.c_int64)),
        ctypes.POINTER(ctypes.POINTER(ctypes.c_int64)),
        ctypes.POINTER(ctypes.c_int64),
    ]
    library.vb_delaunay_cells.restype = ctypes.c_int
    library.vb_free_cells.argtypes = [ctypes.POINTER(ctypes.c_int64)]
    library.vb_free_cells.restype = None
    library.vb_side4_stages.argtypes = [ctypes.c_void_p] + [ctypes.POINTER(ctypes.c_int)] * 2
    library.vb_side4_stages.restype = None
    library.vb_regular_cells.argtypes = [
        ctypes.c_void_p,
        ctypes.c_void_p,
        ctypes.c_int64,
        ctypes.c_int,
        ctypes.POINTER(ctypes.POINTER(ctypes.c_int64)),
        ctypes.POINTER(ctypes.c_int64),
    ]
    library.vb_regular_cells.restype = ctypes.c_int
    library.vb_regular_facets.argtypes = [
        ctypes.c_void_p,
        ctypes.c_void_p,
        ctypes.c_int64,
        ctypes.c_int64,
        ctypes.c_int,
        ctypes.POINTER(ctypes.POINTER(ctypes.c_int64)),
        ctypes.POINTER(ctypes.c_int64),
    ]
    library.vb_regular_facets.restype = ctypes.c_int
    library.vb_side4w_stages.argtypes = [ctypes.c_void_p] * 2 + [ctypes.POINTER(ctypes.c_int)] * 3
    library.vb_side4w_stages.restype = None
    library.vb_set_double_double.argtypes = [ctypes.c_int]
    library.vb_set_double_double.restype = None
    return library


def side4_stages(points: np.ndarray) -> tuple[int, int]:
    """geogram's side4 sign of five points (5, 3) (+1 when the last lies outside the sphere
    through the first four, which must be positively oriented), as (the double-double stage's
    sign, 0 when it is not sure; the whole predicate's, exact with the symbolic perturbation, 0
    when geogram failed). For tests: the points are not moved into the exact frame, and outside
    it (:func:`exact_frame`) geogram's own expansions may overflow or underflow, so only the
    stage's sign is meaningful there."""
    library = _library()
    if library is None:
        from ..errors import MissingDependency

        raise MissingDependency("geogram's module was not built with the package")
    five = np.ascontiguousarray(points, dtype=np.float64).reshape(15)
    staged, full = ctypes.c_int(), ctypes.c_int()
    with _LOCK:
        library.vb_side4_stages(five.ctypes.data, ctypes.byref(staged), ctypes.byref(full))
    return staged.value, full.value


def set_double_double(on: bool) -> None:
    """Turn the double-double stage of the in-sphere test on (the default) or off (benchmarks
    and tests: every test the double filter leaves then goes to the exact expansions)."""
    library = _library()
    if library is not None:
        with _LOCK:
            library.vb_set_double_double(int(on))


def available() -> bool:
    """True when the compiled module was built with the package and loads."""
    return _library() is not None


def exact_frame(points: np.ndarray) -> np.ndarray | None:
    """``points`` (n, 3) times the power of two that puts the largest |coordinate| in [1/2, 1),
    as a new C-contiguous float64 array; None when geogram's predicates would not be exact on
    it (module docstring): a non-finite coordinate, or a nonzero one below
    :data:`SMALLEST_SCALED` after the scaling."""
    scaled = np.array(points, dtype=np.float64, order="C", copy=True)
    if not np.isfinite(scaled).all():
        return None
    magnitude = np.abs(scaled)
    largest = float(magnitude.max()) if scaled.size else 0.0
    if largest == 0.0:
        return scaled
    exponent = math.frexp(largest)[1]  # ldexp: exact even where 2**-exponent overflows
    if math.ldexp(float(magnitude[magnitude > 0].min()), -exponent) < SMALLEST_SCALED:
        return None
    return np.ldexp(scaled, -exponent)


def weighted_frame(points: np.ndarray, weights: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """``points`` in :func:`exact_frame` and ``weights`` times the square of its factor (power
    distances scale by that square: the regular triangulation is unchanged), as new float64
    arrays; None when a weight is not finite or a nonzero |weight| leaves :data:`WEIGHT_RANGE`
    after the scaling, or :func:`exact_frame` refuses the points.

    Why that range keeps the weighted predicate exact. Its determinant has the terms
    Delta_k ((w_i - w_0) - |p_i - p_0|²) (native/power_predicates.cpp): after the scaling the
    coordinates are multiples of 2⁻²⁰² (module docstring), the weights of their unit in the last
    place, at least 2⁻³⁵² above 2⁻³⁰⁰, so every term of the expansions is a multiple of
    2⁻⁶⁰⁶·2⁻⁴⁰⁴ = 2⁻¹⁰¹⁰ ≥ 2⁻¹⁰⁷⁴, and none exceeds about 2³¹⁰."""
    scaled = exact_frame(points)
    heavy = np.array(weights, dtype=np.float64, order="C", copy=True)
    if scaled is None or not np.isfinite(heavy).all():
        return None
    largest = float(np.abs(np.asarray(points, dtype=np.float64)).max()) if len(scaled) else 0.0
    exponent = math.frexp(largest)[1] if largest else 0
    given = heavy != 0
    heavy = np.ldexp(heavy, -2 * exponent)  # rounds only below the range: refused below
    magnitude = np.abs(heavy[given])
    low, high = WEIGHT_RANGE
    if magnitude.size and not (magnitude.min() >= low and magnitude.max() <= high):
        return None
    return scaled, heavy


def delaunay_tetrahedra(points: np.ndarray, ordered: bool = True) -> np.ndarray | None:
    """The finite tetrahedra (k, 4) of the Delaunay triangulation of ``points`` (n, 3), as
    point indices (int64, ascending within a row; with ``ordered`` the rows in lexicographic
    order, the order of GUDHI's simplex tree, sorted in C++: on 10⁶ random points 0.7–1.3 CPU-s
    more than the 4.9–5.1 of the triangulation, where numpy's sort of the rows took 3.2;
    otherwise geogram's order, the same on every call); no rows when the points
    span no volume. None when the compiled module is missing, the input is outside the exact
    range (module docstring) or geogram failed: the caller then uses CGAL."""
    found = _cells(points, ordered, neighbours=False)
    if found is None:
        return None
    scaled, tetrahedra, _ = found
    # The module orders the rows (a sort of 32-byte rows in C++, docstring); copies mapped to
    # their first point need the numpy sort again.
    first = first_copies(scaled, tetrahedra)
    return lexicographic_rows(first, len(points)) if ordered and first is not tetrahedra else first


def delaunay_neighbours(points: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """:func:`delaunay_tetrahedra` in geogram's row order, and for each row the row across
    the face opposite each of its corners (−1 on the hull), read from geogram's own adjacency
    (the layout of scipy's ``Delaunay.neighbors``; the same array as matching the faces, in a
    fraction of its time). None as :func:`delaunay_tetrahedra`, and where points repeat (rows
    renamed to the first copies are sorted again, which would move their neighbours)."""
    found = _cells(points, ordered=False, neighbours=True)
    if found is None:
        return None
    scaled, tetrahedra, across = found
    if first_copies(scaled, tetrahedra) is not tetrahedra:
        return None
    return tetrahedra, across


def _cells(points, ordered: bool, neighbours: bool):
    """(the points in the exact frame, geogram's tetrahedra, their neighbours or None), or None
    (:func:`delaunay_tetrahedra`)."""
    library = _library()
    if np.ndim(points) != 2 or np.shape(points)[1] != 3:
        return None  # the compiled module reads three doubles a point
    if library is None or len(points) < MIN_POINTS or len(points) > MAX_POINTS:
        return None
    scaled = exact_frame(points)
    if scaled is None:
        return None
    cells = ctypes.POINTER(ctypes.c_int64)()
    across = ctypes.POINTER(ctypes.c_int64)()
    count = ctypes.c_int64()
    with _LOCK:  # one at a time: geogram's random engine (restarted per call) is global
        code = library.vb_delaunay_cells(
            scaled.ctypes.data,
            len(scaled),
            int(ordered),
            ctypes.byref(cells),
            ctypes.byref(across) if neighbours else None,
            ctypes.byref(count),
        )
    if code != 0:
        return None
    arrays = []
    try:
        for pointer in (cells, across) if neighbours else (cells,):
            arrays.append(
                np.ctypeslib.as_array(pointer, shape=(count.value, 4)).copy()
                if count.value
                else np.zeros((0, 4), dtype=np.int64)
            )
    finally:
        library.vb_free_cells(cells)
        if neighbours:
            library.vb_free_cells(across)
    return scaled, arrays[0], arrays[1] if neighbours else None


def _regular_input(points: np.ndarray, weights: np.ndarray):
    """(library, scaled points, scaled weights) for the regular triangulation, or None (the
    conditions of :func:`regular_tetrahedra`)."""
    library = _library()
    if np.ndim(points) != 2 or np.shape(points)[1] != 3 or np.shape(weights) != (len(points),):
        return None
    if library is None or len(points) < MIN_POINTS or len(points) > MAX_POINTS:
        return None
    frame = weighted_frame(points, weights)
    return None if frame is None else (library, *frame)


def _take_rows(library, rows, count: int, width: int) -> np.ndarray:
    """The module's array of ``count`` rows of ``width`` indices, copied, then freed."""
    try:
        return (
            np.ctypeslib.as_array(rows, shape=(count, width)).copy()
            if count
            else np.zeros((0, width), dtype=np.int64)
        )
    finally:
        library.vb_free_cells(rows)


def regular_tetrahedra(
    points: np.ndarray, weights: np.ndarray, ordered: bool = True
) -> np.ndarray | None:
    """The finite tetrahedra (k, 4) of the regular (weighted Delaunay) triangulation of
    ``points`` (n, 3) with ``weights`` (n,) (power distance |x − p|² − w, GUDHI's and CGAL's
    convention: a ball of radius r has weight r²), as point indices in the layout of
    :func:`delaunay_tetrahedra`. A hidden point (whose power cell is empty) is in no row; of
    points at one position only the heaviest, the first of those, can be.

    The predicates are exact for the doubles given: geogram's weighted mode rounds the lifting
    |p|² − w of each point to a double, and vorobound's change to it (native/power_predicates.cpp,
    native/geogram/README.md) computes the conflict test from the raw weights, with a filter in
    doubles and geogram's expansions behind it. None when the compiled module is missing, the
    input is outside the exact range (:func:`weighted_frame`) or geogram failed: the caller then
    uses GUDHI."""
    given = _regular_input(points, weights)
    if given is None:
        return None
    library, scaled, heavy = given
    cells = ctypes.POINTER(ctypes.c_int64)()
    count = ctypes.c_int64()
    with _LOCK:  # geogram's random engine (restarted per call) is global
        code = library.vb_regular_cells(
            scaled.ctypes.data,
            heavy.ctypes.data,
            len(scaled),
            int(ordered),
            ctypes.byref(cells),
            ctypes.byref(count),
        )
    return _take_rows(library, cells, count.value, 4) if code == 0 else None


def regular_triangles(
    points: np.ndarray, weights: np.ndarray, limit: int, ordered: bool = True
) -> np.ndarray | None:
    """The triangles (m, 3) of the regular triangulation of :func:`regular_tetrahedra` whose
    three vertices are below ``limit`` (the check's balls, before its filler points), each
    once, as point indices (int64, ascending within a row; with ``ordered`` the rows in
    lexicographic order, GUDHI's simplex-tree order). Read from geogram's cells and their
    neighbours in C++ (each facet from the cell of smaller index), with no sort of all faces.
    None where :func:`regular_tetrahedra` is None, and where the points span no volume (geogram
    then makes no cell, while a flat set has triangles: the caller asks CGAL)."""
    given = _regular_input(points, weights)
    if given is None:
        return None
    library, scaled, heavy = given
    facets = ctypes.POINTER(ctypes.c_int64)()
    count = ctypes.c_int64()
    with _LOCK:  # as in regular_tetrahedra
        code = library.vb_regular_facets(
            scaled.ctypes.data,
            heavy.ctypes.data,
            len(scaled),
            int(limit),
            int(ordered),
            ctypes.byref(facets),
            ctypes.byref(count),
        )
    return _take_rows(library, facets, count.value, 3) if code == 0 else None


def side4w_stages(points: np.ndarray, weights: np.ndarray) -> tuple[int, int, int]:
    """The weighted conflict test of five weighted points (5, 3) and (5,), as side4 signs (+1
    when the last point's power distance to the orthosphere of the first four, which must not
    be coplanar, is positive: no conflict): (the double filter's, 0 when it is not sure; the
    whole exact predicate's, with the symbolic perturbation; geogram's original weighted
    predicate's, on the liftings |p|² − w rounded to doubles), the last two 0 when geogram
    failed. For tests: no frame is applied (:func:`weighted_frame`)."""
    library = _library()
    if library is None:
        from ..errors import MissingDependency

        raise MissingDependency("geogram's module was not built with the package")
    five = np.ascontiguousarray(points, dtype=np.float64).reshape(15)
    heavy = np.ascontiguousarray(weights, dtype=np.float64).reshape(5)
    signs = [ctypes.c_int() for _ in range(3)]
    with _LOCK:
        library.vb_side4w_stages(five.ctypes.data, heavy.ctypes.data, *map(ctypes.byref, signs))
    filtered, full, lifted = (sign.value for sign in signs)
    return filtered, full, lifted


def first_copies(points: np.ndarray, tetrahedra: np.ndarray) -> np.ndarray:
    """``tetrahedra`` with every vertex replaced by the first point at its coordinates (rows
    sorted again): geogram keeps whichever copy it inserted first (its insertion order is
    spatial)."""
    used = np.zeros(len(points), dtype=bool)
    used[tetrahedra] = True
    if used.all() or not len(tetrahedra):
        return tetrahedra
    _, first, inverse = np.unique(points, axis=0, return_index=True, return_inverse=True)
    return np.sort(first[inverse.reshape(-1)][tetrahedra], axis=1)


def lexicographic_rows(tetrahedra: np.ndarray, n: int) -> np.ndarray:
    """``tetrahedra`` (k, 4) of vertices below ``n``, each row sorted and the rows in
    lexicographic order (two packed keys when n² fits an int64)."""
    tetrahedra = np.sort(tetrahedra, axis=1)
    if n < 2**31:
        high = tetrahedra[:, 0] * n + tetrahedra[:, 1]
        low = tetrahedra[:, 2] * n + tetrahedra[:, 3]
        order = np.lexsort((low, high))
    else:
        order = np.lexsort(tetrahedra.T[::-1])
    return tetrahedra[order]
