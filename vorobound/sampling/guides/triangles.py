"""Guide triangles of a set of balls: candidate triples from an engine, then seed coverage.

Engines propose triples that include every guide triangle;
:func:`vorobound.sampling.guides.seeds.classify` decides. A seed uncovered by every other ball
has power 0 to its three balls and ≥ 0 to all others, so it lies on the power-diagram edge dual
to the triple: the triple is a triangle of the regular (weighted Delaunay) triangulation, and
the smallest power on that dual edge, its weighted alpha filtration value, is ≤ 0.

* ``gudhi``: the triangles of GUDHI's regular triangulation (``DelaunayComplex`` with weights,
  CGAL's exact predicates; no filtration values are computed), read in bulk from its simplex
  tree (:mod:`vorobound.sampling.simplices`). Space is cut into slabs, each
  triangulated with the balls within a margin around it (a seed lies within r_max of its three
  centers, and dropping far balls uncovers nothing near the slab), and the slabs run in
  threads (GUDHI releases the GIL). Filler points of weight 0, kept more than r_max away from
  every center, fill the space around the balls: they cannot claim a seed (their power there
  is positive, the seed's power to its own balls is 0), but they cut up the long tetrahedra
  that points on a curved surface otherwise form across its inside (a sample of a cylinder has
  a Delaunay triangulation of size Θ(n^{3/2})), which makes CGAL several times faster on a
  torus. Against the weighted alpha complex pruned at alpha² ≈ 0 (the same triangulation plus
  an alpha value for every simplex) it proposes 1–5 % more triples on surface samples and
  takes about 30 % less time (``benchmarks/bench_check.py --tile-engines``).
* ``geogram``: the same triangles, slabs and filler points, from geogram's regular
  triangulation compiled with the package (:func:`vorobound.sampling.geogram_delaunay
  .regular_triangles`: exact for the weights given, the triangles read in C++ with no simplex
  tree). Where an input leaves its exact range, that triangulation is CGAL's (GUDHI's, when
  installed). The slabs share one lock (geogram's random engine is global), so they
  triangulate one at a time.
* ``hull``: equal radii on a sphere. The power diagram is the Voronoi diagram of cospherical
  points, a seed's dual edge is the ray through a hull facet's normal, and a triple that is not
  a facet has points of the sphere on both sides of its plane, so both its seeds are covered:
  the candidates are the convex-hull facets (CGAL is slow on cospherical input).
* ``brute``: every triple of pairwise-overlapping balls (kd-tree neighbours), for checks and
  when GUDHI is not installed.
"""

from __future__ import annotations

import importlib.util
import math
from dataclasses import dataclass

import numpy as np

from ...checks import brief
from ...errors import InputError
from ...geometry.threads import thread_count
from ...mesh.rows import unique_rows
from ...progress import Counter, Progress
from ..balls import Balls
from .engines import Engine
from .seeds import SeededTriangles, classify

SLAB_POINTS = 200_000
"""Balls per slab of the ``gudhi`` engine (bounds its memory; at least one slab per core)."""
SLAB_MARGIN = 2.0
"""Each slab also triangulates the balls within SLAB_MARGIN·r_max of it (1 suffices)."""
FILLER_SPACING = 6.0
"""Finest spacing of the filler points, in units of r_max; it doubles with each level."""
FILLER_CLEARANCE = 2.0
"""Filler points keep at least FILLER_CLEARANCE·r_max from every center (1 suffices)."""
FILLER_JITTER = 0.1
"""Filler points are moved by up to this fraction of their level's spacing (no cocircular
points for CGAL)."""
COSPHERICAL_RTOL = 1e-12
"""Relative tolerance of "equal radii" and "on the sphere" for the hull engine."""
BRUTE_MAX_BALLS = 200_000
"""The ``brute`` engine enumerates about a hundred triples per ball: refuse beyond this."""
FILLER_MAX_NODES_PER_CENTER = 64
"""A filler level with more grid nodes than this per center is not built (see
:func:`filler_points`)."""
BRUTE_MAX_TRIPLES = 5_000_000
"""Most triples the ``brute`` engine examines (balls that all overlap give n³/6)."""


@dataclass(frozen=True)
class GuideSearch:
    """Classified candidate triples of one engine."""

    engine: str
    candidates: int
    """Triples the engine proposed."""
    with_seeds: int
    """Candidates whose seed pair exists."""
    seeded: SeededTriangles
    """Candidates with at least one uncovered seed (guide or half-covered)."""

    @property
    def guide(self) -> SeededTriangles:
        return self.seeded.take(self.seeded.guide)

    @property
    def half_covered(self) -> int:
        return int(self.seeded.half_covered.sum())


def equal_radii_on_sphere(balls: Balls, radius: float) -> bool:
    """True when every radius is the same and every center lies on the sphere of ``radius``
    about the origin, up to COSPHERICAL_RTOL (the hull engine's premise)."""
    radii, norms = balls.radii, np.linalg.norm(balls.centers, axis=1)
    return bool(
        np.ptp(radii) <= COSPHERICAL_RTOL * radii.max()
        and np.abs(norms - radius).max() <= COSPHERICAL_RTOL * radius
    )


def gudhi_available() -> bool:
    """True when GUDHI can be imported."""
    return importlib.util.find_spec("gudhi") is not None


def geogram_available() -> bool:
    """True when geogram's compiled module was built with the package."""
    from .. import geogram_delaunay

    return geogram_delaunay.available()


def resolve_engine(engine: Engine | str, cospherical_equal: bool) -> Engine:
    """The engine ``auto`` stands for: hull on a sphere with equal radii, else geogram if its
    module was built, else gudhi if installed, else brute."""
    try:
        engine = Engine(engine)
    except (ValueError, TypeError):
        raise InputError(
            f"engine must be auto, geogram, gudhi, hull or brute, got {brief(engine)}"
        ) from None
    if engine is Engine.auto:
        if cospherical_equal:
            return Engine.hull
        if geogram_available():
            return Engine.geogram
        return Engine.gudhi if gudhi_available() else Engine.brute
    if engine is Engine.gudhi and not gudhi_available():
        raise InputError("engine gudhi needs the gudhi package (pip install gudhi)")
    if engine is Engine.geogram and not geogram_available():
        raise InputError(
            "engine geogram needs vorobound's compiled module (built when the package is "
            "installed from source with a C++ compiler)"
        )
    return engine


def whole_engine(engine: Engine | str, cospherical_equal: bool) -> Engine:
    """:func:`resolve_engine` for every ball at once: ``hull`` only on equal radii on a
    sphere."""
    engine = resolve_engine(engine, cospherical_equal)
    if engine is Engine.hull and not cospherical_equal:
        raise InputError("engine hull needs equal radii on a sphere")
    return engine


def find_guide_triangles(
    balls: Balls,
    engine: Engine | str = Engine.auto,
    cospherical_equal: bool = False,
    progress: Progress | None = None,
) -> GuideSearch:
    """Guide and half-covered triangles of ``balls``.

    Parameters
    ----------
    balls : Balls
        Centers and radii.
    engine : Engine
        Source of candidate triples (module docstring).
    cospherical_equal : bool
        The caller knows the centers lie on one sphere and the radii are equal (``auto`` then
        uses the hull engine; ``hull`` requires it).
    progress : Progress, optional
        Reports each stage.

    References
    ----------
    The guide triangles of Section 4.1.
    """
    engine = whole_engine(engine, cospherical_equal)
    triples = candidate_triples(balls, engine, progress=progress)
    seeded = classify(balls, triples, progress)
    keep = seeded.uncovered.any(axis=1)
    return GuideSearch(engine.value, len(triples), int(seeded.has_seeds.sum()), seeded.take(keep))


def candidate_triples(
    balls: Balls, engine: Engine, slabs: bool = True, progress: Progress | None = None
) -> np.ndarray:
    """The triples a resolved ``engine`` proposes (each row's indices increasing; module
    docstring). ``slabs``: the ``gudhi`` engine cuts space into slabs run in threads and
    returns distinct rows in lexicographic order (a whole check); without, one regular
    triangulation in lexicographic order (a tile of a tiled check, on one thread); ``geogram``
    the same. ``hull`` assumes equal radii on a sphere."""
    if engine is Engine.hull:
        Counter(progress, "convex hull", None)
        return hull_triples(balls)
    if engine in (Engine.gudhi, Engine.geogram):
        if slabs:
            return slab_triples(balls, progress, engine)
        return np.sort(regular_triangles(balls.centers, balls.weights, engine), axis=1)
    return overlap_triples(balls, progress)


def hull_triples(balls: Balls) -> np.ndarray:
    """Facets of the convex hull of the centers (sorted vertex indices)."""
    from scipy.spatial import ConvexHull

    return np.sort(ConvexHull(balls.centers).simplices, axis=1)


def slab_triples(
    balls: Balls, progress: Progress | None = None, engine: Engine = Engine.gudhi
) -> np.ndarray:
    """Triangles of the regular triangulation of ``balls`` by ``engine`` (gudhi or geogram),
    by slab (module docstring)."""
    from concurrent.futures import ThreadPoolExecutor

    slabs = _slabs(balls)
    counter = Counter(progress, "regular triangulation", len(slabs))

    def run(members: np.ndarray) -> np.ndarray:
        centers, weights = balls.centers[members], balls.weights[members]
        triples = members[regular_triangles(centers, weights, engine)]
        counter.step()
        return triples

    with ThreadPoolExecutor(min(len(slabs), thread_count())) as pool:
        found = list(pool.map(run, slabs))
    return unique_rows(np.sort(np.concatenate(found), axis=1))


def _slabs(balls: Balls) -> list[np.ndarray]:
    """Ball indices of each slab (cut along the widest axis at count quantiles), with margin."""
    count = len(balls)
    pieces = max(math.ceil(count / SLAB_POINTS), min(thread_count(), count // 10_000), 1)
    centers = balls.centers
    axis = int(np.argmax(np.ptp(centers, axis=0)))
    coord = centers[:, axis]
    cuts = np.quantile(coord, np.linspace(0, 1, pieces + 1))
    cuts[0], cuts[-1] = -np.inf, np.inf
    margin = SLAB_MARGIN * float(balls.radii.max())
    return [
        np.flatnonzero((coord >= lo - margin) & (coord <= hi + margin))
        for lo, hi in zip(cuts[:-1], cuts[1:], strict=True)
    ]


def regular_triangles(
    centers: np.ndarray, weights: np.ndarray, engine: Engine = Engine.gudhi
) -> np.ndarray:
    """Local indices (m, 3) of the triangles of the regular triangulation of the weighted
    points, computed with filler points (module docstring) that the result leaves out, each row
    ascending and the rows in lexicographic order. ``engine`` gudhi: CGAL's triangulation, read
    in bulk (:func:`vorobound.sampling.simplices.delaunay_simplices`, no Python loop over
    simplices); geogram: geogram's exact regular triangulation, the triangles read in C++
    (:func:`vorobound.sampling.geogram_delaunay.regular_triangles`), CGAL's where the input
    leaves its exact range or spans no volume."""
    filler = filler_points(centers, math.sqrt(float(weights.max())))
    points = np.vstack([centers, filler])
    lifted = np.concatenate([weights, np.zeros(len(filler))])
    if engine is Engine.geogram:
        from .. import geogram_delaunay

        found = geogram_delaunay.regular_triangles(points, lifted, len(centers))
        if found is not None:
            return found
        if not gudhi_available():
            raise InputError(
                "geogram's regular triangulation does not take these balls (extreme spreads of "
                "coordinates or weights, all in one plane, or fewer than five points with the "
                "filler): install gudhi"
            )
    from ..simplices import delaunay_simplices

    triangles, _, _ = delaunay_simplices(points, lifted, tetrahedra=False)
    return triangles[(triangles < len(centers)).all(axis=1)]


def filler_points(centers: np.ndarray, radius: float) -> np.ndarray:
    """Points around ``centers``, coarser with distance, all farther than FILLER_CLEARANCE·radius.

    Level ℓ is a jittered grid of spacing g = FILLER_SPACING·radius·2^ℓ restricted to distances
    [g, 2g) from the nearest center (level 0 from the clearance), up to the size of the set.
    """
    from scipy.spatial import cKDTree

    rng = np.random.default_rng(0)
    low, high = centers.min(axis=0), centers.max(axis=0)
    extent = float((high - low).max())
    # Never more grid nodes on the finest level than there are centers.
    spacing = max(
        FILLER_SPACING * radius, (float(np.prod(high - low + 2 * radius)) / len(centers)) ** (1 / 3)
    )
    # Sliding-midpoint splits (not the median's): the grid nodes lie mostly away from the
    # centers, where this tree answers about four times faster (0.035 against 0.14 CPU-s to
    # build and query a tile of 1.6·10⁵ torus balls); the distances, so the points, are the same.
    tree = cKDTree(centers, balanced_tree=False, compact_nodes=False)
    levels: list[np.ndarray] = []
    while True:
        near = max(spacing, FILLER_CLEARANCE * radius) if not levels else spacing
        far = 2 * spacing
        with np.errstate(all="ignore"):
            nodes = np.prod((high - low + 2 * far) / spacing + 2)
        if not np.isfinite(nodes) or nodes > FILLER_MAX_NODES_PER_CENTER * len(centers) + 1e5:
            # Degenerate extents (all centers in a plane or a line, extreme scales): the
            # filler is an optimization only, so stop refining rather than build a huge grid.
            return np.vstack(levels) if levels else np.empty((0, 3))
        axes = [
            np.arange(lo - far, hi + far + spacing, spacing)
            for lo, hi in zip(low, high, strict=True)
        ]
        grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
        grid += rng.uniform(-FILLER_JITTER, FILLER_JITTER, grid.shape) * spacing
        dist, _ = tree.query(grid, distance_upper_bound=far, workers=thread_count())
        levels.append(grid[(dist >= near) & (dist < far)])
        if spacing > extent:
            return np.vstack(levels)
        spacing *= 2


def overlap_triples(balls: Balls, progress: Progress | None = None) -> np.ndarray:
    """Every triple (i < j < k) of pairwise-overlapping balls, found with a kd-tree.

    Three spheres meet in two points only if each pair of balls overlaps, so this is a superset
    of the triples with a seed pair.
    """
    from scipy.spatial import cKDTree

    if len(balls) > BRUTE_MAX_BALLS:
        raise InputError(
            f"the brute engine handles at most {BRUTE_MAX_BALLS} balls, got {len(balls)}: "
            "install gudhi"
        )
    centers, radii = balls.centers, balls.radii
    pairs = cKDTree(centers).query_pairs(2 * float(radii.max()), output_type="ndarray")
    i, j = pairs[:, 0], pairs[:, 1]
    pairs = pairs[np.linalg.norm(centers[i] - centers[j], axis=1) < radii[i] + radii[j]]
    pairs = np.sort(pairs, axis=1)
    pairs = pairs[np.lexsort((pairs[:, 1], pairs[:, 0]))]
    # CSR adjacency towards larger indices; a triple is an edge (i, j) plus k > j adjacent to both.
    n = len(balls)
    starts = np.searchsorted(pairs[:, 0], np.arange(n + 1))
    keys = pairs[:, 0] * n + pairs[:, 1]
    tried = int((starts[pairs[:, 1] + 1] - starts[pairs[:, 1]]).sum())
    if tried > BRUTE_MAX_TRIPLES:
        raise InputError(
            f"the brute engine would examine {tried:.3g} triples of overlapping balls (limit "
            f"{BRUTE_MAX_TRIPLES:.0e}): the balls overlap too much, or use the gudhi engine"
        )
    counter = Counter(progress, "overlapping triples", len(pairs))
    found = []
    for block in np.array_split(np.arange(len(pairs)), max(1, len(pairs) // 50_000)):
        second = pairs[block, 1]
        reach = starts[second + 1] - starts[second]
        edge = np.repeat(block, reach)
        offset = np.arange(len(edge)) - np.repeat(np.cumsum(reach) - reach, reach)
        third = pairs[starts[pairs[edge, 1]] + offset, 1]
        first = pairs[edge, 0]
        key = first * n + third
        spot = np.minimum(np.searchsorted(keys, key), max(len(keys) - 1, 0))
        hit = keys[spot] == key
        found.append(np.column_stack([first[hit], pairs[edge[hit], 1], third[hit]]))
        counter.step(len(block))
    return np.concatenate(found) if found else np.empty((0, 3), dtype=np.int64)
