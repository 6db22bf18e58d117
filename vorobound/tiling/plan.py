"""Tiles with halos: a guide-triangle search split over space, with the answer of the whole.

Space is cut into boxes by a k-d tree of quantile splits (from a subsample of the centers) until
each box holds about ``tile_balls`` centers, so tiles follow the density of the sample, which
for a VoroCrust sample follows its radii (r = δL, spacing ≈ εL). Each ball belongs to one tile,
the leaf whose half-open box holds its center (the *core*); a tile is computed on its core
plus a *halo*: every ball b with

    dist(c_b, box_T) ≤ (r_b + β_T)·(1 + HALO_RTOL),     β_T ≥ R_T = max radius of T's core.

What each part of a check needs of the halo (docs/scale.md has the derivation):

* **Guide triangles.** A triangle is counted by the tile that owns its vertex of smallest
  index v. Its seeds s lie on all three spheres, so |s − c_v| = r_v ≤ R_T; a ball that covers
  s has |c_b − s| < r_b (up to the seeds' tolerance), hence dist(c_b, box_T) < r_b + R_T; and
  the other two vertices u overlap v (|c_u − c_v| ≤ r_u + r_v). With β_T ≥ R_T every ball that
  could decide the triangle is in the tile, and since a seed uncovered by all balls has
  power 0 to its own and ≥ 0 to the tile's, the triangle is in the tile's regular
  triangulation too. Seeds are classified with the whole set's lifting W, so the rounding is
  the whole set's: the same guide set, bit for bit. The tile checks the seeds it computed
  (``seed_reach``) and asks for a larger β if one lies farther out.
* **Sparsity.** A pair closer than σε·min(L) = (σ/(δ/ε))·min(r) is within (σ/(δ/ε))·R_T of the
  tile: β_T ≥ (σ/(δ/ε))·R_T. It is counted by the owner of its smaller index.
* **Neighbour pairs** (Lipschitz of L): each owned point's ``NEIGHBOURS`` nearest are exact
  when they lie within β_T, and deciding whether a neighbour j also has i among its own needs
  the points within |c_i − c_j| of c_j: β_T > 2·(distance to the last neighbour).

A tile reports the β it needed; a driver recomputes the few tiles whose halo was too thin
(:func:`needed_halo`), so the result never depends on the guess ``HALO_FACTOR``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError

HALO_FACTOR = 3.0
"""First guess of β_T in units of R_T (surface samples need about 2.5–2.7: twice the distance to
the 16th neighbour, which is a little more than one radius r = 2εL)."""
HALO_RTOL = 1e-9
"""Relative slack of the halo test (rounding of the distances to the box)."""
REACH_RTOL = 1e-6
"""β_T must exceed each requirement by this relative margin."""
MAX_SUBSAMPLE = 1 << 18
"""Centers kept for planning the tiles (a systematic subsample)."""


@dataclass(frozen=True)
class TilePlan:
    """A k-d tree of half-open boxes: internal nodes split an axis at a value (x < value goes
    left), leaves are tiles. Node 0 is the root; a child index c < 0 is the tile −c − 1."""

    axis: np.ndarray
    split: np.ndarray
    left: np.ndarray
    right: np.ndarray
    lo: np.ndarray
    """(tiles, 3) lower corners of the tiles' boxes, clipped to the centers' bounding box."""
    hi: np.ndarray
    """(tiles, 3) upper corners."""

    @property
    def count(self) -> int:
        return len(self.lo)

    def owner(self, centers: np.ndarray) -> np.ndarray:
        """The tile whose half-open box holds each center."""
        if len(self.axis) == 0:
            return np.zeros(len(centers), dtype=np.int64)
        node = np.zeros(len(centers), dtype=np.int64)
        rows = np.arange(len(centers))
        while True:
            inner = node >= 0
            if not inner.any():
                return -node - 1
            at = node[inner]
            below = centers[rows[inner], self.axis[at]] < self.split[at]
            node[inner] = np.where(below, self.left[at], self.right[at])

    def members(
        self, centers: np.ndarray, radii: np.ndarray, beta: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(row, tile, core) for every ball in a tile's core or halo (module docstring), with
        the tiles' β in ``beta`` (−inf: leave the tile out), rows increasing; ``core`` is True
        where the tile is the ball's own."""
        slack = 1 + HALO_RTOL
        own = self.owner(centers)
        mine = np.flatnonzero(0 <= (radii + beta[own]) * slack)
        if len(self.axis) == 0:
            return mine, own[mine], np.ones(len(mine), dtype=bool)
        # A ball deeper inside its own box than it reaches belongs to no other tile (the other
        # boxes lie outside its own): only the others are looked for in the tree.
        depth = np.minimum(centers - self.lo[own], self.hi[own] - centers).min(axis=1)
        reach = (radii + float(beta[np.isfinite(beta)].max(initial=0.0))) * slack
        near = np.flatnonzero(depth <= reach)
        found_rows, found_tiles = [mine], [own[mine]]
        reach_below = _subtree_max(self, beta)
        rows, node = near, np.zeros(len(near), dtype=np.int64)
        while len(rows):
            leaf = node < 0
            found_rows.append(rows[leaf])
            found_tiles.append(-node[leaf] - 1)
            rows, node = rows[~leaf], node[~leaf]
            if not len(rows):
                break
            coord = centers[rows, self.axis[node]]
            value = self.split[node]
            left, right = self.left[node], self.right[node]
            to_left = (coord - value) <= (radii[rows] + _reach(reach_below, left)) * slack
            to_right = (value - coord) <= (radii[rows] + _reach(reach_below, right)) * slack
            rows = np.concatenate([rows[to_left], rows[to_right]])
            node = np.concatenate([left[to_left], right[to_right]])
        rows = np.concatenate(found_rows[1:]) if len(found_rows) > 1 else near[:0]
        tiles = np.concatenate(found_tiles[1:]) if len(found_tiles) > 1 else near[:0]
        other = tiles != own[rows]
        rows, tiles = rows[other], tiles[other]
        gap = box_distance(centers[rows], self.lo[tiles], self.hi[tiles])
        keep = gap <= (radii[rows] + beta[tiles]) * slack
        core = np.concatenate([np.ones(len(mine), dtype=bool), np.zeros(keep.sum(), dtype=bool)])
        rows = np.concatenate([mine, rows[keep]])
        tiles = np.concatenate([own[mine], tiles[keep]])
        order = np.argsort(rows, kind="stable")
        return rows[order], tiles[order], core[order]


def _reach(reach_below: tuple[np.ndarray, np.ndarray], child: np.ndarray) -> np.ndarray:
    nodes, leaves = reach_below
    return np.where(child >= 0, nodes[np.maximum(child, 0)], leaves[np.maximum(-child - 1, 0)])


def _subtree_max(plan: TilePlan, beta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Largest β of the tiles below each internal node (and of each tile itself)."""
    best = np.zeros(len(plan.axis))

    def value(child: int) -> float:
        return best[child] if child >= 0 else beta[-child - 1]

    for node in reversed(range(len(plan.axis))):  # children come after their parent
        best[node] = max(value(plan.left[node]), value(plan.right[node]))
    return best, beta


def box_distance(points: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Euclidean distance from each point to its box [lo, hi] (0 inside)."""
    outside = lo - points
    np.maximum(outside, points - hi, out=outside)
    np.maximum(outside, 0.0, out=outside)
    outside *= outside
    total = outside[:, 0].copy()  # summed column by column, in the order sum(axis=1) takes
    for column in range(1, outside.shape[1]):
        total += outside[:, column]
    return np.sqrt(total)


def plan_tiles(
    sample: np.ndarray,
    total: int,
    tile_balls: int,
    low: np.ndarray,
    high: np.ndarray,
    count: int | None = None,
) -> TilePlan:
    """Splits of the subsample ``sample`` of ``total`` centers until each box holds at most
    about ``tile_balls`` of them, cutting the longest side first: a box that needs k tiles is
    cut at the quantile ⌊k/2⌋/k, so the tiles come out close to ``tile_balls`` each. With
    ``count``, exactly that many tiles (as far as the subsample allows) of about equal size:
    the root needs ``count`` and each side of a cut the tiles it was cut for.

    ``low`` and ``high`` bound every center; the tiles' boxes are clipped to them.
    """
    if tile_balls < 1:
        raise InputError(f"tile_balls must be at least 1, got {tile_balls}")
    scale = total / max(len(sample), 1)
    axis: list[int] = []
    split: list[float] = []
    left: list[int] = []
    right: list[int] = []
    lows: list[np.ndarray] = []
    highs: list[np.ndarray] = []

    def build(points: np.ndarray, lo: np.ndarray, hi: np.ndarray, parts: int | None) -> int:
        if parts is None:
            parts = math.ceil(len(points) * scale / tile_balls)
        if parts > 1 and len(points) >= 2:
            rank = max(1, len(points) * (parts // 2) // parts)
            for dim in np.argsort(hi - lo)[::-1]:
                value = float(np.partition(points[:, dim], rank)[rank])
                below = points[:, dim] < value
                if below.any() and not below.all():
                    node = len(axis)
                    axis.append(int(dim))
                    split.append(value)
                    left.append(0)
                    right.append(0)
                    upper, lower = hi.copy(), lo.copy()
                    upper[dim], lower[dim] = value, value
                    below_parts = parts // 2 if count is not None else None
                    above_parts = parts - parts // 2 if count is not None else None
                    left[node] = build(points[below], lo, upper, below_parts)
                    right[node] = build(points[~below], lower, hi, above_parts)
                    return node
        lows.append(lo)
        highs.append(hi)
        return -len(lows)

    low, high = np.asarray(low, dtype=float), np.asarray(high, dtype=float)
    build(np.asarray(sample, dtype=float), low, high, count)
    return TilePlan(
        np.array(axis, dtype=np.int64),
        np.array(split, dtype=float),
        np.array(left, dtype=np.int64),
        np.array(right, dtype=np.int64),
        np.array(lows, dtype=float).reshape(-1, 3),
        np.array(highs, dtype=float).reshape(-1, 3),
    )


def first_halo(core_radius: np.ndarray, sparsity_reach: float) -> np.ndarray:
    """The first guess of β per tile: HALO_FACTOR·R_T, at least what sparsity needs
    (``sparsity_reach`` = σ/(δ/ε), in units of R_T)."""
    return max(HALO_FACTOR, sparsity_reach) * core_radius * (1 + REACH_RTOL)


def needed_halo(
    core_radius: float,
    sparsity_reach: float,
    seed_reach: float,
    neighbour_reach: float,
) -> float:
    """The β a tile needed (module docstring): R_T, (σ/(δ/ε))·R_T, the farthest seed of an
    owned triple from the box (plus the seeds' cover tolerance), and twice the farthest
    owned point's last neighbour."""
    return (1 + REACH_RTOL) * max(
        core_radius, sparsity_reach * core_radius, seed_reach, 2 * neighbour_reach
    )


class Subsample:
    """A systematic subsample of a stream of centers: every ``stride``-th row, the stride
    doubling whenever more than ``MAX_SUBSAMPLE`` rows are kept."""

    def __init__(self, limit: int | None = None):
        self.limit = MAX_SUBSAMPLE if limit is None else limit
        self.stride, self.kept = 1, 0
        self.parts: list[tuple[np.ndarray, np.ndarray]] = []  # (rows, centers) kept per call

    def add(self, first_row: int, centers: np.ndarray) -> None:
        """Offer the rows ``first_row, first_row + 1, ...`` of the stream."""
        rows = np.arange(first_row, first_row + len(centers))
        chosen = rows % self.stride == 0
        self.parts.append((rows[chosen], centers[chosen]))
        self.kept += int(chosen.sum())
        while self.kept > self.limit:
            self.stride *= 2
            self.parts = [(r[r % self.stride == 0], c[r % self.stride == 0]) for r, c in self.parts]
            self.kept = sum(len(r) for r, _ in self.parts)

    def points(self) -> np.ndarray:
        return np.concatenate([c for _, c in self.parts]) if self.parts else np.empty((0, 3))
