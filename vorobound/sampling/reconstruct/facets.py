"""M̂: the Voronoi facets between an inside and an outside seed, as a polygon surface.

The Voronoi facet of two seeds is dual to their Delaunay edge: its vertices are the circumcentres of
the Delaunay tetrahedra around that edge, in the order the tetrahedra turn around it. Only edges
whose two seeds carry different labels are kept, so only those facets are built. The Delaunay
tetrahedralization comes from geogram's compiled module (exact predicates with a double-double
stage, :mod:`.engine`; CGAL through GUDHI where the module is missing), and the face neighbours of
the tetrahedra from matching their faces; they give the turn around each edge without any geometry.
Where numba is installed, the neighbours, the circumcentres and the walks around the in/out edges
are compiled (:mod:`.facets_kernel`: faces bucketed by their smallest vertex instead of one global
sort, each edge walked once from its first tetrahedron); the numpy steps below give the same facets
everywhere else, and the tests compare the two. qhull (:class:`scipy.spatial.Delaunay`,
``triangulation="qhull"``) gives the same facets and stays as the tests' cross-check: on 5·10⁵ seeds
it took 3.3 times CGAL's time (issue 35), and it drops seeds it finds nearly coincident, which exact
predicates never need to. docs/reconstruct.md says why the Delaunay route is preferred to
:class:`scipy.spatial.Voronoi` (which builds every facet of the diagram as Python lists). Above
``slabs.WHOLE_SEEDS`` seeds (or on request, ``slabs=``) the tetrahedralization is built in
overlapping slabs, one at a time, and only the tetrahedra around the in/out edges are kept
(:mod:`.slabs`: the same facets, certified by the empty-ball property and a completeness
certificate; memory bounded by a slab).

The frame: the seeds are moved to a frame near the origin and of unit size before anything is
computed, and M̂'s vertices moved back. Along each axis whose seeds lie far from 0 (the centre
of their range at least the range's width from 0) the shift is that centre: every coordinate
is then within a factor 2 of it, so the difference is exact (Sterbenz's lemma); then all is
divided by a power of two. Both steps are exact, so the triangulation (exact predicates) is
that of the seeds as given, and no seed is ever dropped for being nearly coincident with
another (issue 34: qhull dropped 272 seeds of a sphere's seed set shifted by 10⁵ and gained 507
facets, without a word; at 10⁷ M̂ was empty). Seeds far from the origin are known only to the
rounding of their coordinates, u·|x|: that rounding splits a degenerate Voronoi vertex (a
ball's centre, on which many seeds are cospherical) into vertices up to a few hundred units
of the last place apart, so Voronoi edges of M̂ shorter than GIVEN_WELD·u·|shift| are welded
too. The facet count of a shifted seed set then stays within a few tenths of a percent of the
unshifted one's (tiny facets the rounding creates or hides), and the topology is the same
(tests/sampling/reconstruct/test_reconstruct.py shifts every fixture by 10³ … 10⁹). A seed
left out of the triangulation makes the reconstruction not correct (``skipped_seeds``), unless
it is an exact copy of a seed with its label (``duplicate_seeds``: one Voronoi cell, nothing
lost).

VoroCrust's seeds are cospherical by construction: every seed of a ball lies on its sphere and
no seed lies inside it, so the ball's centre is one Voronoi vertex shared by many seeds. qhull's
triangulated output splits such a vertex into many tetrahedra whose circumcentres agree up to
rounding, and some of these tetrahedra are flat (four cocircular seeds), with no circumcentre of
their own. A flat tetrahedron takes the circumcentre of a face neighbour that is equidistant
from its four seeds (the same empty sphere). Then the Voronoi edges of M̂ that are too short to
tell from zero are contracted: two tetrahedra next to each other around an in/out edge become
one vertex when their circumcentres are closer than ``WELD_RTOL`` times the circumradius plus
the rounding error of both (which grows as a tetrahedron flattens). A facet left with fewer
than three distinct vertices has no area and is dropped (counted as collapsed). Each polygon is
oriented combinatorially: the tetrahedra around the edge from the inside seed a to the outside
seed b turn counter-clockwise about ab when the signed volumes of (a, b, entry, exit) add up to
a positive number, so no polygon's orientation rests on its own (possibly tiny) area. A
Delaunay edge on the convex hull has a facet that reaches infinity (unbounded): it is listed,
and M̂ is then not closed.

References
----------
The surface M̂ of VoroCrust (the Voronoi facets between inside and outside seeds), built on the
guide triangles' seeds of Section 4.1.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ...errors import InputError, warn_once
from ...progress import Counter, Progress
from .engine import delaunay_tetrahedra
from .slabs import dense_unique, slab_count, slab_fans

WELD_RTOL = 1e-9
"""Neighbouring Voronoi vertices closer than WELD_RTOL times their circumradius (plus their
rounding errors) are one vertex. The circumcentres of one degenerate vertex agree to about
1e-13 of the radius on VoroCrust seeds (docs/reconstruct.md)."""
ROUNDING_FACTOR = 64.0
"""The rounding error of a circumcentre is taken as ROUNDING_FACTOR·u·(R + |a|)/flatness
(u the unit roundoff, a the first vertex, flatness = |det(u, v, w)|/(|u||v||w|)): a generous
multiple of the error of the formula, which grows as the tetrahedron flattens."""
GIVEN_WELD = 256.0
"""Seeds far from the origin are known only to u·|x| (u the unit roundoff, x the seed as
given): neighbouring Voronoi vertices closer than GIVEN_WELD·u·|shift| are one too (module
docstring, "The frame")."""
FLAT_RTOL = 1e-10
"""A tetrahedron is flat when its volume is below FLAT_RTOL·|u||v||w|/6 (u, v, w its edges
from one vertex): its circumcentre is then not computed but borrowed from a neighbour."""
FLAT_ROUNDS = 8
"""Rounds of borrowing through chains of flat tetrahedra."""
CHUNK = 1 << 20
"""Tetrahedra, or corners of the cycles, handled at a time (bounds the memory)."""
TRIANGULATIONS = ("exact", "cgal", "qhull")
"""The Delaunay engines :func:`inout_facets` takes ("exact": geogram's module, CGAL where it is
missing)."""
EDGE_PAIRS = ((0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3))
"""The six edges of a tetrahedron as pairs of local vertex indices."""


@dataclass(frozen=True)
class PolygonSurface:
    """Convex polygons on shared vertices (M̂), each oriented by its outward normal.

    Polygon f has the vertex indices ``corners[offsets[f]:offsets[f + 1]]``, counter-clockwise
    seen from outside (the side of its outside seed).
    """

    vertices: np.ndarray
    """(V, 3) vertex coordinates."""
    corners: np.ndarray
    """(K,) vertex index of every polygon corner, polygon after polygon."""
    offsets: np.ndarray
    """(F + 1,) start of each polygon in ``corners``."""
    seed_pairs: np.ndarray
    """(F, 2) the inside and the outside seed of each facet."""
    normals: np.ndarray
    """(F, 3) unit normal of each facet, from its inside seed towards its outside seed (the
    facet lies in their bisector plane)."""

    @property
    def n_facets(self) -> int:
        return len(self.offsets) - 1

    @property
    def sizes(self) -> np.ndarray:
        """Corners per polygon."""
        return np.diff(self.offsets)

    def facet_of_corner(self) -> np.ndarray:
        """(K,) the polygon each corner belongs to."""
        return np.repeat(np.arange(self.n_facets), self.sizes)

    def next_corner(self) -> np.ndarray:
        """(K,) index in ``corners`` of the next corner of the same polygon (cyclically)."""
        index = np.arange(len(self.corners)) + 1
        ends = self.offsets[1:]
        index[ends - 1] = self.offsets[:-1]
        return index

    def fan_triangles(self) -> tuple[np.ndarray, np.ndarray]:
        """(T, 3) triangles fanning each polygon from its first corner, and (T,) their polygon.

        The polygons are convex, so the fan covers each exactly, with the same orientation.
        """
        sizes = self.sizes
        facet = np.repeat(np.arange(self.n_facets), sizes - 2)
        step = np.arange(len(facet)) - np.repeat(np.cumsum(sizes - 2) - (sizes - 2), sizes - 2)
        first = self.offsets[:-1][facet]
        triangles = np.column_stack(
            [self.corners[first], self.corners[first + step + 1], self.corners[first + step + 2]]
        )
        return triangles, facet

    def centroids(self) -> np.ndarray:
        """(F, 3) area centroid of each polygon (of its fan triangles; the mean of its
        vertices where it has no area)."""
        triangles, facet = self.fan_triangles()
        corners = self.vertices[triangles]
        area = 0.5 * np.linalg.norm(
            np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1
        )
        count = self.n_facets
        weighted = corners.mean(axis=1) * area[:, None]
        total = np.bincount(facet, area, count)
        sums = np.stack([np.bincount(facet, weighted[:, k], count) for k in range(3)], axis=1)
        owner = self.facet_of_corner()
        plain = (
            np.stack(
                [np.bincount(owner, self.vertices[self.corners, k], count) for k in range(3)],
                axis=1,
            )
            / np.maximum(self.sizes, 1)[:, None]
        )
        flat = ~(total > 0)
        with np.errstate(all="ignore"):
            return np.where(flat[:, None], plain, sums / total[:, None])


@dataclass(frozen=True)
class InOutFacets:
    """M̂ and what was left out of it, with the counts of the construction."""

    surface: PolygonSurface
    unbounded: np.ndarray
    """(U, 2) inside and outside seed of each facet that reaches infinity (its Delaunay edge is
    on the convex hull of the seeds)."""
    collapsed: int
    """In/out Delaunay edges whose facet has fewer than three distinct vertices after welding
    (no area: a degenerate Voronoi vertex seen from two seeds)."""
    unresolved: int
    """Facets dropped because a flat tetrahedron around them found no circumcentre."""
    non_simple: int
    """Facets whose welded polygon visits a vertex twice (kept; counted for the record)."""
    skipped_seeds: int
    """Seeds left out of the triangulation other than the duplicates below: with exact predicates
    (geogram, CGAL) only a seed at the very coordinates of a seed of the other label; with qhull
    also seeds it finds nearly coincident with another. M̂ misses their facets, so a result with
    skipped seeds is not correct (``ReconstructReport.topology_correct``)."""
    delaunay_edges: int
    """Delaunay edges between an inside and an outside seed."""
    tetrahedra: int
    """Tetrahedra of the Delaunay triangulation of the seeds."""
    duplicate_seeds: int = 0
    """Seeds at the very coordinates of another seed with the same label: one Voronoi cell,
    triangulated once (the copies change nothing in M̂)."""
    slabs: int = 1
    """Slabs the seeds were triangulated in (1: the whole set at once, also when the slabs
    asked for could not certify their facets)."""


def inout_facets(
    points: np.ndarray,
    inside: np.ndarray,
    progress: Progress | None = None,
    triangulation: str = "exact",
    compiled: bool | None = None,
    slabs: int | None = None,
) -> InOutFacets:
    """The Voronoi facets between seeds labelled inside and seeds labelled outside.

    Parameters
    ----------
    points : numpy.ndarray, shape (n, 3)
        The seeds (finite, distinct; at least five, not all in a plane).
    inside : numpy.ndarray, shape (n,)
        True for a seed inside the surface.
    progress : Progress, optional
        Reports the stages.
    triangulation : {"exact", "cgal", "qhull"}
        The Delaunay tetrahedralization: "exact" (the default) geogram's compiled module,
        exact predicates, CGAL's where the module is missing or the seeds leave its exact
        range (:mod:`.engine`); "cgal" CGAL's through GUDHI; "qhull" scipy's, kept as the
        cross-check of the tests.
    compiled : bool, optional
        True builds the neighbours, circumcentres and cycles with the compiled kernels of
        :mod:`.facets_kernel` (numba), False with numpy; None (default) compiled where numba
        is installed. Both give the same facets (the tests compare them).
    slabs : int, optional
        Triangulate the seeds in this many overlapping slabs, one at a time (exact engines and the
        compiled kernels only; :mod:`.slabs`: the same facets, certified complete, memory bounded by
        a slab; where a check fails, the whole set at once). 1: the whole set at once. None
        (default): ``slabs.slab_count(n)``, one slab up to ``WHOLE_SEEDS`` (1,500,000) seeds, where
        the whole set is faster, then one per ``SLAB_SEEDS``.

    Returns
    -------
    InOutFacets
        M̂ as welded, oriented polygons, and the facets left out of it.

    References
    ----------
    The surface M̂ of VoroCrust (module docstring).
    """
    points = np.ascontiguousarray(points, dtype=float)
    inside = np.asarray(inside, dtype=bool)
    if triangulation not in TRIANGULATIONS:
        raise InputError(
            f"triangulation must be one of {', '.join(TRIANGULATIONS)}, got {triangulation!r}"
        )
    engine = "cgal" if triangulation == "cgal" else None
    # Every product below (circumcentres, signed volumes) is of degree up to 6 in the
    # coordinates: the seeds are first moved to a frame near the origin and near unit size,
    # exactly (module docstring), and the results moved back.
    shift, unit = seed_frame(points)
    points = (points - shift) / unit
    # The seeds are known to the rounding of their given coordinates, which the shift hides.
    given = float(np.linalg.norm(shift)) / unit
    kernel = _facets_kernel() if compiled is None or compiled else None
    if compiled and kernel is None:
        raise InputError("compiled: the kernels need numba (pip install vorobound[fast])")
    if slabs is None:
        slabs = slab_count(len(points))
    elif isinstance(slabs, bool) or not isinstance(slabs, int | np.integer) or slabs < 1:
        raise InputError(f"slabs must be a whole number ≥ 1, got {slabs!r}")
    fans = None
    if slabs > 1 and (triangulation == "qhull" or kernel is None):
        warn_once(
            f"{slabs} slabs need exact predicates and numba's compiled steps (pip install "
            "vorobound[fast]): the whole set is triangulated at once (more memory)"
        )
    if triangulation != "qhull" and kernel is not None and slabs > 1:
        fans = slab_fans(points, inside, kernel, flat_circumcentres, slabs, progress, engine)
    if fans is not None:
        duplicates, skipped = _absent_seeds(points, inside, fans.present)
        counter = Counter(progress, "in/out facets", 3)
        centres, radius, error = fans.centres, fans.radius, fans.error
        empty = np.empty((0, 2), dtype=np.int64)
        cycles = _Cycles(fans.pairs, fans.tets, fans.offsets, empty, len(fans.pairs))
        tetrahedra = fans.tetrahedra
        counter.step(2)
    else:
        if triangulation != "qhull":
            Counter(progress, "Delaunay", None)
            simplices, neighbors, present = _exact_tetrahedra(points, kernel, engine)
        else:
            Counter(progress, "Delaunay (qhull)", None)
            simplices, neighbors, present = _qhull_tetrahedra(points)
        duplicates, skipped = _absent_seeds(points, inside, present)
        counter = Counter(progress, "in/out facets", 3)
        centres, radius, error = circumcentres(points, simplices, neighbors, kernel)
        counter.step()
        if kernel is None:
            cycles = _edge_cycles(simplices, neighbors, inside)
            cycles = _oriented(points, simplices, inside, cycles)
        else:
            cycles = _compiled_cycles(kernel, points, simplices, neighbors, inside)
        tetrahedra = len(simplices)
        del simplices, neighbors
        counter.step()
    surface, collapsed, unresolved, non_simple = _weld(
        points, inside, centres, radius, error, cycles, given
    )
    counter.step()
    surface = replace(surface, vertices=surface.vertices * unit + shift)
    return InOutFacets(
        surface=surface,
        unbounded=cycles.unbounded,
        collapsed=collapsed,
        unresolved=unresolved,
        non_simple=non_simple,
        skipped_seeds=skipped,
        duplicate_seeds=duplicates,
        delaunay_edges=cycles.edge_count,
        tetrahedra=tetrahedra,
        slabs=1 if fans is None else fans.slabs,
    )


def seed_frame(points: np.ndarray) -> tuple[np.ndarray, float]:
    """Shift (3,) and power-of-two unit such that ``(points - shift) / unit`` is exact and
    has coordinates below 1 in size (module docstring, "The frame").

    Along an axis whose centre c lies at least the axis's extent from 0, the shift is c (then
    every coordinate x has c/2 ≤ x ≤ 2c, so x − c is exact by Sterbenz's lemma); elsewhere it
    is 0 (the seeds already straddle the origin, or nearly so).
    """
    if not len(points):
        return np.zeros(3), 1.0
    low, high = points.min(axis=0), points.max(axis=0)
    with np.errstate(all="ignore"):
        centre = low + 0.5 * (high - low)
        far = np.isfinite(centre) & (np.abs(centre) >= high - low) & (low * high > 0)
    shift = np.where(far, centre, 0.0)
    return shift, _power_of_two_scale(points - shift)


def _power_of_two_scale(points: np.ndarray) -> float:
    """The power of two nearest above the largest absolute coordinate (1 for none or zero)."""
    largest = float(np.abs(points).max()) if points.size else 0.0
    if not (np.isfinite(largest) and largest > 0):
        return 1.0
    return float(np.ldexp(1.0, int(np.frexp(largest)[1])))


def circumcentres(
    points, simplices, neighbors, kernel=None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Circumcentre, circumradius and rounding error of the circumcentre of every tetrahedron;
    a flat one borrows the circumcentre of a face neighbour equidistant from its four vertices
    (and that neighbour's error; NaN where none is found). ``kernel``: :mod:`.facets_kernel`
    computes the circumcentres (else numpy, by chunks)."""
    centres, radius, error, _, _ = flat_circumcentres(points, simplices, neighbors, kernel)
    return centres, radius, error


def flat_circumcentres(points, simplices, neighbors, kernel=None):
    """:func:`circumcentres`, (t,) which tetrahedra are flat (their circumcentre borrowed from
    a neighbour), and (t,) the last face whose neighbour a flat tetrahedron's centre depends on
    (int8: k when it was found across face k in the first round, after trying faces 0 … k − 1;
    3 otherwise, when every face was tried)."""
    count = len(simplices)
    if kernel is not None:
        centres, error, flat = kernel.circumcentres(points, simplices, ROUNDING_FACTOR, FLAT_RTOL)
    else:
        centres, error = np.empty((count, 3)), np.empty(count)
        flat = np.empty(count, dtype=bool)
        for start in range(0, count, CHUNK):
            part = slice(start, start + CHUNK)
            centres[part], error[part], flat[part] = _circumcentres(points[simplices[part]])
    centres[flat] = np.nan
    error[flat] = np.nan
    todo = np.flatnonzero(flat)
    last = np.full(count, 3, dtype=np.int8)
    for round_ in range(FLAT_ROUNDS):
        if len(todo) == 0:
            break
        found = np.zeros(len(todo), dtype=bool)
        seeds = points[simplices[todo]]
        for k in range(4):
            other = neighbors[todo, k]
            candidate = centres[np.maximum(other, 0)]
            distance = np.linalg.norm(seeds - candidate[:, None, :], axis=2)
            with np.errstate(invalid="ignore"):
                spread = distance.max(axis=1) - distance.min(axis=1)
                fits = (other >= 0) & ~found & (spread <= WELD_RTOL * distance.max(axis=1))
            centres[todo[fits]] = candidate[fits]
            error[todo[fits]] = error[np.maximum(other, 0)][fits]
            if round_ == 0:
                last[todo[fits]] = k
            found |= fits
        todo = todo[~found]
    radius = np.linalg.norm(centres - points[simplices[:, 0]], axis=1)
    return centres, radius, error, flat, last


def _circumcentres(corner: np.ndarray):
    """Circumcentres (k, 3), their rounding errors (k,) and flatness (k,) of tetrahedra given
    by their corners (k, 4, 3)."""
    origin = corner[:, 0]
    u, v, w = (corner[:, k] - origin for k in (1, 2, 3))
    vw, wu, uv = np.cross(v, w), np.cross(w, u), np.cross(u, v)
    det = np.einsum("ij,ij->i", u, vw)
    scale = np.linalg.norm(u, axis=1) * np.linalg.norm(v, axis=1) * np.linalg.norm(w, axis=1)
    flat = ~(np.abs(det) > FLAT_RTOL * scale)
    numerator = (
        (u * u).sum(1)[:, None] * vw + (v * v).sum(1)[:, None] * wu + (w * w).sum(1)[:, None] * uv
    )
    with np.errstate(all="ignore"):
        centres = origin + numerator / (2 * det[:, None])
        offset = np.linalg.norm(numerator, axis=1) / (2 * np.abs(det))
        error = (
            ROUNDING_FACTOR
            * np.finfo(float).eps
            * (offset + np.linalg.norm(origin, axis=1))
            * scale
            / np.abs(det)
        )
    return centres, error, flat


def _exact_tetrahedra(points: np.ndarray, kernel=None, engine: str | None = None):
    """Tetrahedra, their face neighbours and which seeds are vertices, from the exact engine
    of :mod:`.engine` (the neighbours from ``kernel``, :mod:`.facets_kernel`, where given)."""
    from ..simplices import face_neighbours

    simplices = delaunay_tetrahedra(points, engine)
    if not len(simplices):
        raise InputError(
            "seeds: they cannot be tetrahedralized (fewer than five distinct seeds, or all "
            "in a plane)"
        )
    if kernel is not None:
        neighbors, ok = kernel.face_neighbours(simplices, len(points))
        neighbors = neighbors if ok else None
    else:
        neighbors = face_neighbours(simplices)
    if neighbors is None:
        raise InputError("seeds: the triangulation has a face of more than two tetrahedra")
    present = np.zeros(len(points), dtype=bool)
    present[simplices.reshape(-1)] = True
    return simplices, neighbors, present


def _qhull_tetrahedra(points: np.ndarray):
    """Tetrahedra, their face neighbours and which seeds are vertices, from qhull."""
    from scipy.spatial import Delaunay, QhullError

    try:
        triangulation = Delaunay(points)
    except (QhullError, ValueError) as exc:
        reason = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise InputError(f"seeds: qhull cannot triangulate them ({reason})") from None
    simplices = triangulation.simplices.astype(np.int64)
    neighbors = triangulation.neighbors.astype(np.int64)
    present = np.zeros(len(points), dtype=bool)
    present[simplices.reshape(-1)] = True
    return simplices, neighbors, present


def _absent_seeds(points: np.ndarray, inside: np.ndarray, present: np.ndarray) -> tuple[int, int]:
    """(duplicates, skipped) among the seeds that are no vertex of the triangulation: a
    duplicate has the very coordinates of a vertex with its label, anything else is skipped."""
    absent = np.flatnonzero(~present)
    if not len(absent):
        return 0, 0
    rows = np.column_stack([points, inside.astype(float)])
    _, group = np.unique(rows, axis=0, return_inverse=True)
    group = group.reshape(-1)
    covered = np.zeros(int(group.max()) + 1, dtype=bool)
    covered[group[present]] = True
    duplicates = int(covered[group[absent]].sum())
    return duplicates, len(absent) - duplicates


@dataclass(frozen=True)
class _Cycles:
    """The tetrahedra around each bounded in/out Delaunay edge, in turning order."""

    pairs: np.ndarray
    """(E, 2) the two seeds of each bounded edge."""
    tets: np.ndarray
    """Tetrahedra around the edges, edge after edge, in order."""
    offsets: np.ndarray
    """(E + 1,) start of each edge in ``tets``."""
    unbounded: np.ndarray
    """(U, 2) the two seeds of each edge on the convex hull."""
    edge_count: int


def _edge_cycles(simplices, neighbors, inside) -> _Cycles:
    """Every Delaunay edge between differently labelled seeds, with its tetrahedra in order.

    Around an edge ab, tetrahedron (a, b, c, d) touches the next ones through its faces abc and
    abd: the neighbours opposite d and opposite c. Walking from one tetrahedron and never back
    visits them all in turning order; a neighbour -1 (the hull) makes the facet unbounded.
    """
    count = len(simplices)
    label = inside[simplices]
    parts = []
    for p, q in EDGE_PAIRS:
        tet = np.flatnonzero(label[:, p] != label[:, q])
        c, d = (k for k in range(4) if k not in (p, q))
        a, b = simplices[tet, p], simplices[tet, q]
        parts.append(
            np.column_stack(
                [
                    np.minimum(a, b),
                    np.maximum(a, b),
                    tet,
                    np.full_like(tet, c),
                    np.full_like(tet, d),
                ]
            )
        )
    rows = np.concatenate(parts)
    seeds_n = int(simplices.max()) + 1 if len(simplices) else 0
    edge_key = rows[:, 0] * seeds_n + rows[:, 1]
    order = np.lexsort((rows[:, 2], edge_key))
    rows, edge_key = rows[order], edge_key[order]
    keys, start, sizes = np.unique(edge_key, return_index=True, return_counts=True)
    edge = np.repeat(np.arange(len(keys)), sizes)
    lookup = edge * count + rows[:, 2]
    tet = rows[:, 2]
    across = [neighbors[tet, rows[:, 3]], neighbors[tet, rows[:, 4]]]
    adjacent = []
    open_edge = np.zeros(len(keys), dtype=bool)
    for nb in across:
        spot = np.searchsorted(lookup, edge * count + np.maximum(nb, 0))
        spot = np.minimum(spot, len(lookup) - 1)
        missing = (nb < 0) | (lookup[spot] != edge * count + nb)
        open_edge[edge[missing]] = True
        adjacent.append(np.where(missing, -1, spot))
    pairs = np.column_stack([keys // max(seeds_n, 1), keys % max(seeds_n, 1)])
    bounded = np.flatnonzero(~open_edge)
    first, length = start[bounded], sizes[bounded]
    out_offsets = np.concatenate([[0], np.cumsum(length)])
    walked = np.empty(int(out_offsets[-1]), dtype=np.int64)
    current, previous = first.copy(), adjacent[1][first]
    alive = np.arange(len(bounded))
    for step in range(int(length.max()) if len(length) else 0):
        alive = alive[length[alive] > step]
        cur, prev = current[alive], previous[alive]
        walked[out_offsets[alive] + step] = tet[cur]
        one, two = adjacent[0][cur], adjacent[1][cur]
        current[alive] = np.where(one != prev, one, two)
        previous[alive] = cur
    if not np.array_equal(current, first):  # a walk that did not close: a broken triangulation
        raise InputError("seeds: the triangulation is inconsistent around an edge")
    return _Cycles(
        pairs=pairs[bounded],
        tets=walked,
        offsets=out_offsets,
        unbounded=_inside_first(pairs[open_edge], inside),
        edge_count=len(keys),
    )


def _facets_kernel():
    """:mod:`.facets_kernel`, or None where numba is missing (or ``VOROBOUND_PURE_NUMPY`` set)."""
    from ...geometry.kernels import load_kernel
    from ..simplices import kernel_available

    return load_kernel(f"{__package__}.facets_kernel") if kernel_available() else None


def _compiled_cycles(kernel, points, simplices, neighbors, inside) -> _Cycles:
    """The oriented cycles of :func:`_oriented` (of :func:`_edge_cycles`), from the compiled
    walk: edges in the order of their keys, each cycle from its first tetrahedron, reversed
    where it turns clockwise about the edge from the inside to the outside seed."""
    first, inner, outer, length, turn, found, ok = kernel.find_edges(
        points, simplices, neighbors, inside
    )
    if not ok:
        raise InputError("seeds: the triangulation is inconsistent around an edge")
    first, inner, outer, length, turn = (x[:found] for x in (first, inner, outer, length, turn))
    seeds_n = max(int(simplices.max()) + 1, 1)
    order = np.argsort(np.minimum(inner, outer) * seeds_n + np.maximum(inner, outer))
    first, inner, outer, length, turn = (x[order] for x in (first, inner, outer, length, turn))
    bounded = length >= 0
    offsets = np.concatenate([[0], np.cumsum(length[bounded])])
    tets = np.empty(int(offsets[-1]), dtype=np.int64)
    kernel.write_cycles(
        simplices,
        neighbors,
        first[bounded],
        inner[bounded],
        outer[bounded],
        turn[bounded] < 0,
        offsets,
        tets,
    )
    pairs = np.column_stack([inner, outer])
    return _Cycles(
        pairs=pairs[bounded],
        tets=tets,
        offsets=offsets,
        unbounded=pairs[~bounded],
        edge_count=int(found),
    )


def _inside_first(pairs: np.ndarray, inside: np.ndarray) -> np.ndarray:
    """Each pair ordered (inside seed, outside seed)."""
    swap = ~inside[pairs[:, 0]]
    return np.where(swap[:, None], pairs[:, ::-1], pairs)


def _oriented(points, simplices, inside, cycles: _Cycles) -> _Cycles:
    """The cycles turned counter-clockwise about the edge from the inside seed to the outside
    seed, and their pairs ordered (inside, outside).

    Consecutive tetrahedra around edge ab share a face abx; tetrahedron k is entered through
    x_{k−1} and left through x_k, and det(b − a, x_{k−1} − a, x_k − a) is positive when the
    walk turns counter-clockwise about a → b. The sum over the cycle decides (flat tetrahedra
    add next to nothing).
    """
    pairs = _inside_first(cycles.pairs, inside)
    sizes = np.diff(cycles.offsets)
    edge = np.repeat(np.arange(len(sizes)), sizes)
    nxt = np.arange(len(cycles.tets)) + 1
    nxt[cycles.offsets[1:] - 1] = cycles.offsets[:-1]
    exit_ = np.empty(len(cycles.tets), dtype=np.int64)
    for start in range(0, len(cycles.tets), CHUNK):
        part = slice(start, start + CHUNK)
        here, there = simplices[cycles.tets[part]], simplices[cycles.tets[nxt[part]]]
        a, b = pairs[edge[part], 0], pairs[edge[part], 1]
        shared = (here[:, :, None] == there[:, None, :]).any(axis=2)
        shared &= (here != a[:, None]) & (here != b[:, None])
        exit_[part] = here[np.arange(len(here)), np.argmax(shared, axis=1)]
    prv = np.empty_like(nxt)
    prv[nxt] = np.arange(len(nxt))
    turn = np.zeros(len(sizes))
    for start in range(0, len(cycles.tets), CHUNK):
        part = slice(start, start + CHUNK)
        a, b = pairs[edge[part], 0], pairs[edge[part], 1]
        base = points[a]
        det = np.einsum(
            "ij,ij->i",
            points[b] - base,
            np.cross(points[exit_[prv[part]]] - base, points[exit_[part]] - base),
        )
        turn += np.bincount(edge[part], det, len(sizes))
    index = np.arange(len(cycles.tets))
    mirrored = cycles.offsets[edge] + cycles.offsets[edge + 1] - 1 - index
    tets = cycles.tets[np.where((turn < 0)[edge], mirrored, index)]
    return replace(cycles, pairs=pairs, tets=tets)


def _weld(points, inside, centres, radius, error, cycles: _Cycles, given: float = 0.0):
    """Polygons on welded vertices: (surface, collapsed, unresolved, non-simple)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    used, corner_vertex = dense_unique(cycles.tets, len(centres))
    position = centres[used]
    slack = WELD_RTOL * radius[used] + error[used]
    sizes = np.diff(cycles.offsets)
    polygon = np.repeat(np.arange(len(sizes)), sizes)
    previous = np.roll(corner_vertex, 1)
    previous[cycles.offsets[:-1]] = corner_vertex[cycles.offsets[1:] - 1]
    # Contract the Voronoi edges of M̂ shorter than their vertices' slack (by chunks: the
    # corners of M̂ number about five per in/out edge).
    short = np.empty(len(corner_vertex), dtype=bool)
    for start in range(0, len(short), CHUNK):
        here, there = corner_vertex[start : start + CHUNK], previous[start : start + CHUNK]
        gap = np.linalg.norm(position[here] - position[there], axis=1)
        with np.errstate(invalid="ignore"):
            part = gap <= np.maximum(slack[here], slack[there])
        if given > 0:
            # Seeds far from the origin: their coordinates as given are rounded to u·|x|.
            part |= gap <= GIVEN_WELD * np.finfo(float).eps * given
        short[start : start + CHUNK] = part
    count = len(used)
    graph = coo_matrix(
        (np.ones(int(short.sum())), (corner_vertex[short], previous[short])), shape=(count, count)
    )
    del previous, short
    _, cluster = connected_components(graph, directed=False)
    del graph
    known = np.isfinite(position).all(axis=1)
    cluster = np.where(known, cluster, -1)
    vertex = cluster[corner_vertex]
    before = np.roll(vertex, 1)
    before[cycles.offsets[:-1]] = vertex[cycles.offsets[1:] - 1]
    keep = vertex != before
    vertex, polygon = vertex[keep], polygon[keep]
    distinct = np.bincount(polygon, minlength=len(sizes))
    broken = np.bincount(polygon, vertex < 0, minlength=len(sizes)) > 0
    collapsed_mask = (distinct < 3) & ~broken
    good = (distinct >= 3) & ~broken
    keep = good[polygon]
    vertex, polygon = vertex[keep], polygon[keep]
    offsets = np.concatenate([[0], np.cumsum(distinct[good])])
    # Renumber the clusters that polygons use; a vertex is the mean of its cluster.
    used_clusters, vertex = dense_unique(vertex, count)
    is_used = np.zeros(count, dtype=bool)
    is_used[used_clusters] = True
    member = np.flatnonzero(known & is_used[np.maximum(cluster, 0)])
    slot = np.searchsorted(used_clusters, cluster[member])
    total = np.bincount(slot, minlength=len(used_clusters))
    vertices = np.stack(
        [np.bincount(slot, position[member, k], len(used_clusters)) / total for k in range(3)],
        axis=1,
    )
    pairs = cycles.pairs[good]
    normals = points[pairs[:, 1]] - points[pairs[:, 0]]
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    non_simple = _non_simple(vertex, offsets)
    surface = PolygonSurface(vertices, vertex, offsets, pairs, normals)
    return surface, int(collapsed_mask.sum()), int(broken.sum()), non_simple


def _non_simple(corners, offsets) -> int:
    """Polygons that visit a vertex more than once."""
    count = len(offsets) - 1
    if count == 0:
        return 0
    polygon = np.repeat(np.arange(count), np.diff(offsets))
    key = polygon * (int(corners.max()) + 1) + corners
    distinct = np.bincount(polygon[np.unique(key, return_index=True)[1]], minlength=count)
    return int((distinct < np.diff(offsets)).sum())
