"""Seed pairs of ball triples and whether other balls cover them.

The three boundary spheres of balls i, j, k meet in the two seeds ẑ ± sqrt(−R̂²)·n, where ẑ
is the power center in the plane of the centers, R̂² the signed squared orthoradius and n the
unit normal; they exist when R̂² < 0. A triple is a guide triangle when both seeds lie outside
every other ball, half-covered when exactly one does (VoroCrust, Section 4.1 of the paper).

Coverage is a nearest-neighbour question after lifting: with W = max r², the ball (p, r)
becomes the 4-D point (p, sqrt(W − r²)), and the squared distance from (s, 0) to it is the
power |s − p|² − r² plus W. The four nearest lifted balls therefore contain the
smallest-power ball other than i, j, k.

References
----------
Eq. (2), (5) (orthoball and its center); the guide triangles of Section 4.1.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...geometry import WeightedTriangles, weighted_triangles
from ...geometry.threads import thread_count
from ...progress import Counter, Progress
from ..balls import Balls

SEED_RTOL = 1e-9
"""A seed pair exists when R̂² < −SEED_RTOL·r_min² (r_min the smallest radius of the triple):
two spheres meeting tangentially up to rounding have no seed pair."""
COVER_RTOL = 1e-9
"""A seed is uncovered when its power to every other ball is ≥ COVER_RTOL·r_min². A seed on a
fourth sphere up to rounding counts as covered, so a degenerate configuration (four spheres
through one point) yields no guide triangle whichever way a triangulation breaks the tie."""
SEARCH_POWER = 4 * COVER_RTOL
"""The coverage search looks for other balls up to this power over W (a few times the cover
tolerance, far above rounding)."""
LIFTED_LEAFSIZE = 32
"""Leaf size of the lifted balls' k-d tree, built by sliding midpoints (not balanced): the seeds'
bounded 4-nearest queries run a few per cent faster than on scipy's default tree. Any exact
tree gives the same answers: the nearest ball outside a triple is among the four nearest
whichever way ties are broken, and its distance is the same float."""
SEED_CHUNK = 1 << 18
"""Triples whose seeds are looked up at a time (bounds the memory of the coverage queries)."""


@dataclass(frozen=True)
class SeededTriangles:
    """Ball triples with their weighted-triangle geometry, seeds and seed coverage."""

    triples: np.ndarray
    """(m, 3) ball indices."""
    geometry: WeightedTriangles
    """Circumradius, signed orthoradius², Theorem 1's R − R̂, edges, ... (input order)."""
    seeds: np.ndarray
    """(m, 2, 3) the two seeds (NaN where no seed pair exists)."""
    uncovered: np.ndarray
    """(m, 2) True where the seed lies outside every other ball."""

    @property
    def has_seeds(self) -> np.ndarray:
        return np.isfinite(self.seeds).all(axis=(1, 2))

    @property
    def guide(self) -> np.ndarray:
        """Both seeds uncovered: a guide triangle."""
        return np.asarray(self.uncovered.all(axis=1))

    @property
    def half_covered(self) -> np.ndarray:
        """Exactly one seed uncovered."""
        return self.uncovered.sum(axis=1) == 1

    def take(self, index) -> SeededTriangles:
        """The rows ``index`` (a mask or indices)."""
        fields: dict[str, Any] = {
            name: (None if value is None else value[index])
            for name, value in vars(self.geometry).items()
        }
        geometry = WeightedTriangles(**fields)
        return SeededTriangles(
            self.triples[index], geometry, self.seeds[index], self.uncovered[index]
        )


def seed_pairs(balls: Balls, triples: np.ndarray) -> tuple[WeightedTriangles, np.ndarray]:
    """Weighted-triangle geometry and the two seeds of each triple (NaN where none exist).

    References
    ----------
    Eq. (2), (5).
    """
    centers = balls.centers[triples]
    weights = balls.weights[triples]
    geometry = weighted_triangles(centers, weights)
    normal = np.cross(centers[:, 1] - centers[:, 0], centers[:, 2] - centers[:, 0])
    with np.errstate(all="ignore"):
        normal /= _row_norm(normal)[:, None]
        r_min_sq = row_minima(weights)
        depth_sq = -geometry.orthoradius_sq
        exists = geometry.valid & (depth_sq > SEED_RTOL * r_min_sq)
        half = np.sqrt(np.where(exists, depth_sq, np.nan))[:, None] * normal
    center = np.asarray(geometry.orthocenter)
    seeds = np.empty((len(center), 2, 3))
    np.add(center, half, out=seeds[:, 0])
    np.subtract(center, half, out=seeds[:, 1])
    return geometry, seeds


def classify(
    balls: Balls,
    triples: np.ndarray,
    progress: Progress | None = None,
    top: float | None = None,
) -> SeededTriangles:
    """Seeds of every triple and which of them no other ball covers.

    Parameters
    ----------
    balls : Balls
        All balls (the coverage test uses every one).
    triples : numpy.ndarray, shape (m, 3)
        Ball indices.
    progress : Progress, optional
        Reports the triples classified.
    top : float, optional
        W of the lifting (default: the largest weight of ``balls``). A tile of a larger set
        passes the whole set's W, so its rounding, hence its answer, is the whole set's.

    References
    ----------
    The guide triangles and seeds of Section 4.1.
    """
    from scipy.spatial import cKDTree

    triples = np.asarray(triples, dtype=np.int64).reshape(-1, 3)
    top = float(balls.weights.max()) if top is None else float(top)
    tree = cKDTree(lifted_balls(balls, top), leafsize=LIFTED_LEAFSIZE, balanced_tree=False)
    counter = Counter(progress, "seeds", len(triples))
    geometry, seeds = seed_pairs(balls, triples)  # row by row: the same bits in one call
    uncovered = np.zeros((len(triples), 2), dtype=bool)
    has = np.isfinite(seeds).all(axis=(1, 2))
    for start in range(0, len(triples), SEED_CHUNK):
        at = start + np.flatnonzero(has[start : start + SEED_CHUNK])
        if len(at):
            rows = triples[at]
            floor = COVER_RTOL * row_minima(balls.weights[rows])
            for side in range(2):
                power = other_power(tree, top, seeds[at, side], rows)
                uncovered[at, side] = power >= floor
        counter.step(len(has[start : start + SEED_CHUNK]))
    return SeededTriangles(triples, geometry, seeds, uncovered)


def lifted_balls(balls: Balls, top: float | None = None) -> np.ndarray:
    """The balls as 4-D points whose squared distance to (s, 0) is the power of s plus W = top
    (default: the largest weight)."""
    weights = balls.weights
    top = float(weights.max()) if top is None else top
    height = np.sqrt(np.maximum(top - weights, 0.0))
    return np.column_stack([balls.centers, height])


def other_power(tree, top: float, points: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """Smallest power of each point to a ball outside its own triple, where it is below
    SEARCH_POWER·W (+inf where it is not: the point is uncovered either way).

    The search stops at that power (lifted distance √((1 + SEARCH_POWER)·W)), which a seed's own
    balls (power 0) are within and a covering ball (power < COVER_RTOL·r_min² ≤ COVER_RTOL·W)
    too, so the answer to "covered?" is that of the unbounded search, and so is the power
    wherever it is below the bound.
    """
    query = np.zeros((len(points), 4))
    query[:, :3] = points
    count = min(4, tree.n)
    bound = math.sqrt(top * (1 + SEARCH_POWER))
    dist, index = tree.query(query, k=count, distance_upper_bound=bound, workers=thread_count())
    dist = dist.reshape(len(points), count)  # (k = 1 drops the axis)
    index = index.reshape(len(points), count)
    power = dist * dist - top
    rows = np.asarray(rows)
    own = index == rows[:, :1]
    for column in range(1, rows.shape[1]):
        own |= index == rows[:, column : column + 1]
    power[own] = np.inf
    return row_minima(power)


def _row_norm(vectors: np.ndarray) -> np.ndarray:
    """Euclidean norms of the rows of an (n, 3) array: the squares summed in the order of
    ``numpy.linalg.norm(vectors, axis=1)`` (the same bits), without its per-row reduction."""
    square = vectors * vectors
    return np.sqrt(square[:, 0] + square[:, 1] + square[:, 2])


def row_minima(values: np.ndarray) -> np.ndarray:
    """Row minima of a 2-D array without NaN, column by column: the same values as
    ``values.min(axis=1)`` without its per-row overhead (a few columns, millions of rows)."""
    out = values[:, 0].copy()
    for column in range(1, values.shape[1]):
        np.minimum(out, values[:, column], out=out)
    return out
