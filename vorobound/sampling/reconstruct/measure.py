"""M̂ measured: facet quality, and distance and normals against the surface that was sampled.

* **Quality** of each facet: shortest over longest edge, and smallest interior angle.
* **M̂ → surface**: the distance from points of M̂ (its vertices, and seven points of each fan
  triangle of each facet: the centroid, the edge midpoints and the points (4, 1, 1)/6) to the
  surface, over ε·L at the closest surface point. Per facet, the largest over its points.
* **surface → M̂**: the distance from random surface points (uniform by area) to M̂ (its fan
  triangles, through libigl's AABB tree), over ε·L at the surface point.
* **Hausdorff** (two-sided, in units of ε·L): the larger of the two maxima. Both are maxima
  over finitely many points, so a measured Hausdorff distance is a lower bound of the true one
  (numerical).
* **Normal deviation** of each facet: the angle between its normal (from its inside seed to its
  outside seed) and the surface's outward normal at the point closest to its centroid; above
  90° the facet faces the wrong way.

Where L is a λ-Lipschitz function of space that costs a search per point (a mesh with an
estimated L), it is evaluated only where it can change a result: L at the nearest surface
point q(p) of a point p of a facet is at least L(q(v)) − λ(d(p) + |p − v| + d(v)) for each
vertex v of its fan triangle (|q(p) − q(v)| ≤ d(p) + |p − v| + d(v)), so a point whose bound of
distance/(εL) is below its facet's largest value so far leaves every maximum, and where it is,
unchanged; a surface probe is bounded likewise from the vertices of the part of M̂ nearest to
it. The results are those of evaluating L everywhere (the tests compare the two).

References
----------
VoroCrust's approximation guarantees for M̂ (distance and normals), which these measure.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .facets import PolygonSurface

FAN_SAMPLES = np.array(
    [
        [1 / 3, 1 / 3, 1 / 3],
        [1 / 2, 1 / 2, 0.0],
        [0.0, 1 / 2, 1 / 2],
        [1 / 2, 0.0, 1 / 2],
        [4 / 6, 1 / 6, 1 / 6],
        [1 / 6, 4 / 6, 1 / 6],
        [1 / 6, 1 / 6, 4 / 6],
    ]
)
"""Barycentric points of each fan triangle at which M̂ → surface is measured (with the
vertices)."""
PROBES_PER_VERTEX = 4
"""Surface points per vertex of M̂ for surface → M̂ (at least ``MIN_PROBES``)."""
MIN_PROBES = 100_000
CHUNK = 1 << 20
"""Points measured at a time (bounds the memory of the closest-point queries)."""
PRUNE_RTOL = 1e-9
"""Bounds of distance/(εL) are widened by this fraction before a point is left out (L and
the distances are computed to a few units of the last place)."""


@dataclass(frozen=True)
class FacetQuality:
    """Shape of each facet."""

    edge_ratio: np.ndarray
    """(F,) shortest over longest edge."""
    min_angle: np.ndarray
    """(F,) smallest interior angle, degrees."""
    area: np.ndarray
    """(F,) area."""


@dataclass(frozen=True)
class Extreme:
    """A largest measured value and where it was found."""

    value: float
    where: np.ndarray | None
    """(3,) the point of M̂ or of the surface where it occurs."""


@dataclass(frozen=True)
class SurfaceMeasures:
    """M̂ against the surface, per facet and in total."""

    facet_distance: np.ndarray
    """(F,) largest distance/(εL) from the facet's points to the surface."""
    normal_deviation: np.ndarray
    """(F,) angle between the facet's normal and the surface normal, degrees."""
    to_surface: Extreme
    """M̂ → surface: largest distance/(εL) over M̂'s points."""
    from_surface: Extreme
    """surface → M̂: largest distance/(εL) over the surface probes."""
    points: int
    """Points of M̂ measured."""
    probes: int
    """Surface points measured."""

    @property
    def hausdorff(self) -> float:
        """Two-sided Hausdorff distance over ε·L (measured on finitely many points)."""
        return max(self.to_surface.value, self.from_surface.value)


def facet_quality(surface: PolygonSurface) -> FacetQuality:
    """Edge ratio, smallest angle and area of every facet."""
    corners = surface.corners
    nxt = surface.next_corner()
    prv = np.empty_like(nxt)
    prv[nxt] = np.arange(len(nxt))
    points = surface.vertices[corners]
    ahead = surface.vertices[corners[nxt]] - points
    behind = surface.vertices[corners[prv]] - points
    length = np.linalg.norm(ahead, axis=1)
    cosine = np.einsum("ij,ij->i", ahead, behind) / (length * np.linalg.norm(behind, axis=1))
    angle = np.degrees(np.arccos(np.clip(cosine, -1, 1)))
    starts = surface.offsets[:-1]
    shortest = np.minimum.reduceat(length, starts) if len(starts) else length[:0]
    longest = np.maximum.reduceat(length, starts) if len(starts) else length[:0]
    smallest = np.minimum.reduceat(angle, starts) if len(starts) else angle[:0]
    triangles, facet = surface.fan_triangles()
    p = surface.vertices[triangles]
    part = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
    return FacetQuality(shortest / longest, smallest, np.bincount(facet, part, surface.n_facets))


def measure_against(
    surface: PolygonSurface,
    reference,
    eps: float,
    rng: np.random.Generator,
) -> SurfaceMeasures:
    """Distances (over ε·L) and normal deviations of M̂ against ``reference``, a shape of
    :mod:`vorobound.sampling.surfaces` (its ``closest`` and ``random_points``; module
    docstring)."""
    count = surface.n_facets
    triangles, facet = surface.fan_triangles()
    vertex_ratio, at_vertices = _to_surface(reference, surface.vertices, eps)
    known = at_vertices if _prunable(reference) else None
    facet_distance = np.zeros(count)
    np.maximum.at(facet_distance, surface.facet_of_corner(), vertex_ratio[surface.corners])
    best = _argmax(vertex_ratio)
    to_surface = Extreme(float(vertex_ratio[best]), surface.vertices[best]) if best >= 0 else None
    corners = surface.vertices[triangles]
    for weights in FAN_SAMPLES:
        points = np.einsum("k,ikj->ij", weights, corners)
        if known is None:
            ratio, _ = _to_surface(reference, points, eps)
        else:
            ratio = _to_surface_pruned(
                reference, points, eps, surface.vertices, triangles, known, facet_distance[facet]
            )
        np.maximum.at(facet_distance, facet, ratio)
        top = _argmax(ratio)
        if top >= 0 and (to_surface is None or ratio[top] > to_surface.value):
            to_surface = Extreme(float(ratio[top]), points[top])
    measured = len(surface.vertices) + len(FAN_SAMPLES) * len(triangles)
    if known is None:
        normal = reference.closest(surface.centroids()).normal
    else:  # the normal alone, without L
        normal = reference.normals[reference.nearest(surface.centroids())[2]]
    cosine = np.einsum("ij,ij->i", surface.normals, normal)
    deviation = np.degrees(np.arccos(np.clip(cosine, -1, 1)))
    probes = max(MIN_PROBES, PROBES_PER_VERTEX * len(surface.vertices))
    from_surface = _from_surface(reference, surface, triangles, eps, probes, rng, known)
    return SurfaceMeasures(
        facet_distance=facet_distance,
        normal_deviation=deviation,
        to_surface=to_surface or Extreme(float("nan"), None),
        from_surface=from_surface,
        points=measured,
        probes=probes,
    )


def _argmax(values: np.ndarray) -> int:
    """Index of the largest value (NaN counts as largest: a point the surface cannot place);
    -1 for no values."""
    if len(values) == 0:
        return -1
    bad = np.flatnonzero(np.isnan(values))
    return int(bad[0]) if len(bad) else int(np.argmax(values))


def _prunable(reference) -> bool:
    """True when L is a λ-Lipschitz function of space that costs a search per point (a mesh
    with an estimated L): L is then evaluated only where it can change a maximum."""
    return (
        bool(getattr(reference, "lipschitz_exact", False))
        and hasattr(reference, "nearest")
        and hasattr(reference, "random_points_on")
    )


@dataclass(frozen=True)
class _Known:
    """Distance d(v) of each vertex v of M̂ to the surface and L(q(v)) at its nearest surface
    point q(v): L elsewhere is bounded from them (λ-Lipschitz)."""

    distance: np.ndarray
    lfs: np.ndarray


def _to_surface(reference, points: np.ndarray, eps: float) -> tuple[np.ndarray, _Known]:
    """distance/(εL) from each point to the surface, chunked; and the distances and L."""
    ratio, distance, lfs = (np.empty(len(points)) for _ in range(3))
    for start in range(0, len(points), CHUNK):
        part = reference.closest(points[start : start + CHUNK])
        ratio[start : start + CHUNK] = part.distance / (eps * part.lfs)
        distance[start : start + CHUNK] = part.distance
        lfs[start : start + CHUNK] = part.lfs
    return ratio, _Known(distance, lfs)


def _lfs_bounds(lipschitz, points, vertices, corners, known, gap):
    """Lower and upper bounds of L at the surface point nearest to ``points`` (m, 3), each
    ``gap`` (m,) from it, from the three vertices ``corners`` (m, 3) of M̂: with q the
    nearest-point map, |q(p) − q(v)| ≤ d(p) + |p − v| + d(v) (module docstring)."""
    lower, upper = np.full(len(points), -np.inf), np.full(len(points), np.inf)
    for k in range(3):
        v = corners[:, k]
        reach = gap + np.linalg.norm(points - vertices[v], axis=1) + known.distance[v]
        lower = np.maximum(lower, known.lfs[v] - lipschitz * reach)
        upper = np.minimum(upper, known.lfs[v] + lipschitz * reach)
    return lower, upper


def _upper_ratio(distance, eps, lower):
    """distance/(ε·lower), widened by PRUNE_RTOL; inf where the bound of L is not positive."""
    with np.errstate(all="ignore"):
        bound = distance / (eps * lower) * (1 + PRUNE_RTOL)
    return np.where(lower > 0, bound, np.inf)


def _to_surface_pruned(reference, points, eps, vertices, triangles, known, facet_max):
    """:func:`_to_surface` at points of M̂'s fan ``triangles``, L evaluated only where the
    point can raise its facet's maximum so far ``facet_max``; −inf where it cannot (its
    ratio is below that maximum, so no maximum, and no place of one, changes)."""
    ratio = np.full(len(points), -np.inf)
    for start in range(0, len(points), CHUNK):
        part = slice(start, start + CHUNK)
        nearest, distance, triangle = reference.nearest(points[part])
        lower, _ = _lfs_bounds(
            reference.lipschitz, points[part], vertices, triangles[part], known, distance
        )
        bound = _upper_ratio(distance, eps, lower)
        need = ~(bound < facet_max[part])
        lfs = reference.lfs_on(triangle[need], nearest[need])
        ratio[start + np.flatnonzero(need)] = distance[need] / (eps * lfs)
    return ratio


def _from_surface(reference, surface, triangles, eps, count, rng, known=None) -> Extreme:
    """Largest distance/(εL) from random surface points to M̂ (with ``known``, L only at the
    probes that can be the largest)."""
    import igl

    vertices = np.ascontiguousarray(surface.vertices, dtype=float)
    faces = np.ascontiguousarray(triangles, dtype=np.int64)
    if hasattr(igl, "AABB"):  # the tree of M̂ built once for all chunks of probes
        tree = igl.AABB()
        tree.init(vertices, faces)
        distances = tree.squared_distance
    else:  # a libigl without the class: a tree per chunk
        distances = lambda v, f, p: igl.point_mesh_squared_distance(p, v, f)  # noqa: E731
    best = Extreme(0.0, None)
    for start in range(0, count, CHUNK):
        if known is None:
            probes, lfs = reference.random_points(min(CHUNK, count - start), rng)
            squared, _, _ = distances(vertices, faces, np.ascontiguousarray(probes, dtype=float))
            ratio = np.sqrt(squared) / (eps * lfs)
        else:
            probes, triangle = reference.random_points_on(min(CHUNK, count - start), rng)
            squared, face, closest = distances(
                vertices, faces, np.ascontiguousarray(probes, dtype=float)
            )
            nearby = (closest, surface.vertices, triangles[face])
            distance = np.sqrt(squared)
            ratio = _probe_ratio(
                reference, probes, triangle, distance, nearby, known, eps, best.value
            )
        top = _argmax(ratio)
        if ratio[top] > best.value or np.isnan(ratio[top]):
            best = Extreme(float(ratio[top]), probes[top])
    return best


def _probe_ratio(reference, probes, triangle, distance, nearby, known, eps, best):
    """distance/(εL) at the probes that can hold the chunk's largest value above ``best``
    (−inf elsewhere): L is bounded from the vertices of the fan triangle of M̂ nearest to each
    probe (``nearby``: the nearest point of M̂, M̂'s vertices, the triangle's corners), and a
    probe whose upper bound is below the largest lower bound of the chunk, or below ``best``,
    is neither the chunk's largest nor a new largest."""
    closest, vertices, corners = nearby
    lower, upper = _lfs_bounds(reference.lipschitz, closest, vertices, corners, known, distance)
    high = _upper_ratio(distance, eps, lower)
    with np.errstate(all="ignore"):
        low = np.where(upper > 0, distance / (eps * upper) * (1 - PRUNE_RTOL), 0.0)
    floor = max(best, float(np.nanmax(low))) if len(low) else best
    need = ~(high < floor)
    ratio = np.full(len(probes), -np.inf)
    ratio[need] = distance[need] / (eps * reference.lfs_on(triangle[need], probes[need]))
    return ratio
