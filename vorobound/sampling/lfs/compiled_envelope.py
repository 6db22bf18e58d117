"""Compiled evaluation of the cone envelopes of :mod:`.lipschitz` (needs the optional numba).

One query at a time walks the tree of :class:`.lipschitz._ConeTree` depth first, the child
with the smaller bound first, and keeps the smallest cone it has evaluated. Its first bound is
the cone of the site that gave the previous query its value (the sampler's queries come in
lattice order, so that site is usually the answer); no arrays of live query-node pairs.

Each cone is computed with the same operations in the same order as the numpy path
(:meth:`.lipschitz._ConeTree.cones`: the offset, the sum of squares left to right, its square
root, minus the radius; a gradient's dot product left to right), so the same site gives the
same value to the last bit. A node is dropped when its bound is not below the best value found:

* For plain cones and the distance cap the bound, computed as the numpy path computes it, is
  never above the computed cone of any site of the node: every step is monotone under
  round-to-nearest (|fl(x − y)| ≥ fl(low − x) for y ≥ low > x; squares, the sum in the same
  order, the square root, subtracting a radius ρ ≤ the node's largest, max(·, 0), the product
  with slope ≥ 0 and adding a smallest value ≤ the site's value all keep ≤). Dropping such a
  node loses nothing: the result is the minimum over every site's cone as computed.
* With tangent planes the bound rests on the floor value − c (c the plane's deepest dip)
  and is exact only up to rounding, so a node holding a site with a plane is dropped only
  when its bound exceeds the best value by :data:`PRUNE_MARGIN` times the magnitudes in the
  comparison, far more than their rounding (~1e-16 relative).

A site or node whose smallest value is not below the best value is skipped without its
distance (no planes: value + slope·beyond ≥ value and max(value, ·) ≥ value hold in floating
point too). Either way the walk returns the minimum over all sites' cones as computed, never
above what the numpy path returns (which computes the same cones and keeps the minimum of a
subset); on every tested query the two are equal.

Importing this module compiles nothing; the first call compiles (a few seconds) and caches
the machine code on disk. The kernel releases the GIL and runs on the library's threads. All
compiled helpers of the envelope stay in this one file (numba checks only the defining file's
timestamp before reusing cached machine code).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

PRUNE_MARGIN = 1e-12
"""A node is dropped when its bound exceeds the best value by more than this times the sum of
the magnitudes that enter the comparison (rounding moves them by ~1e-16 relative)."""

NO_CUTOFF = -math.inf
"""The cutoff of a query whose walk runs to the end (:meth:`FlatTree.evaluate`)."""

MODE_CONE, MODE_PLANE, MODE_CAP = 0, 1, 2
"""Plain cones value + slope·max(0, |x − y| − ρ); cones with a tangent plane; the distance
cap max(value, max(0, |x − y| − ρ)) (no slope)."""


class FlatTree:
    """The arrays of a :class:`.lipschitz._ConeTree` in heap order (node k at depth d is
    2^d − 1 + k), as the kernel reads them."""

    def __init__(self, tree):
        self.depth = int(tree.depth)
        self.low = np.ascontiguousarray(np.concatenate(tree.low), dtype=float)
        self.high = np.ascontiguousarray(np.concatenate(tree.high), dtype=float)
        self.best_value = np.ascontiguousarray(np.concatenate(tree.best_value), dtype=float)
        self.best_site = np.ascontiguousarray(np.concatenate(tree.best_site), dtype=np.int64)
        self.max_radius = np.ascontiguousarray(np.concatenate(tree.max_radius), dtype=float)
        self.leaf_sites = np.ascontiguousarray(tree.leaf_sites, dtype=np.int64)
        self.sites = np.ascontiguousarray(tree.sites, dtype=float)
        self.values = np.ascontiguousarray(tree.values, dtype=float)
        self.radii = np.ascontiguousarray(tree.radii, dtype=float)
        gradients = tree.gradients
        self.has_gradients = gradients is not None
        self.gradients = np.ascontiguousarray(
            np.zeros((1, 3)) if gradients is None else gradients, dtype=float
        )
        # Per node: does it hold a site with a (nonzero) plane? Then its drop test has a margin.
        leaves = len(tree.leaf_sites)
        planar = np.zeros(leaves, dtype=bool)
        if gradients is not None:
            sloped = np.abs(gradients).max(axis=1) > 0
            slot = self.leaf_sites >= 0
            planar = (sloped[np.where(slot, self.leaf_sites, 0)] & slot).any(axis=1)
        levels = [planar]
        while len(levels[-1]) > 1:
            levels.append(levels[-1][0::2] | levels[-1][1::2])
        self.planar = np.ascontiguousarray(np.concatenate(levels[::-1]), dtype=np.bool_)

    def evaluate(
        self,
        queries: np.ndarray,
        slope: float | None,
        best: np.ndarray,
        cutoff: np.ndarray | None = None,
    ) -> None:
        """min(best, every site's cone) at each query, in place (``best``: float64, C order,
        upper bounds or inf). With ``cutoff`` (one per query), the walk of a query stops at
        the first cone at most its cutoff: where the minimum is at most the cutoff, the
        value left is some value at most it, not the minimum (:data:`NO_CUTOFF`: none)."""
        if cutoff is None:
            cutoff = np.full(len(queries), NO_CUTOFF)
        if slope is None:
            mode, slope_value = MODE_CAP, 0.0
        else:
            mode = MODE_PLANE if self.has_gradients else MODE_CONE
            slope_value = float(slope)
        _envelope_kernel(
            np.ascontiguousarray(queries, dtype=float),
            best,
            self.depth,
            self.low,
            self.high,
            self.best_value,
            self.best_site,
            self.max_radius,
            self.planar,
            self.leaf_sites,
            self.sites,
            self.values,
            self.radii,
            self.gradients,
            mode,
            slope_value,
            np.ascontiguousarray(cutoff, dtype=float),
        )


@njit(inline="always", error_model="numpy")
def _cone(x0, x1, x2, site, sites, values, radii, gradients, mode, slope):
    """The cone of ``site`` at x: the arithmetic of :meth:`.lipschitz._ConeTree.cones`."""
    o0 = x0 - sites[site, 0]
    o1 = x1 - sites[site, 1]
    o2 = x2 - sites[site, 2]
    past = math.sqrt(o0 * o0 + o1 * o1 + o2 * o2) - radii[site]
    if mode == MODE_PLANE:
        along = o0 * gradients[site, 0] + o1 * gradients[site, 1] + o2 * gradients[site, 2]
        return values[site] + max(along, slope * past)
    beyond = max(past, 0.0)
    if mode == MODE_CAP:
        return max(values[site], beyond)
    return values[site] + slope * beyond


@njit(inline="always", error_model="numpy")
def _node_bound(x0, x1, x2, node, value, low, high, best_value, max_radius, planar, mode, slope):
    """(bound, margin) of a node: its smallest floor combined with the distance from x to its
    box beyond its largest radius (the numpy path's arithmetic), and the drop margin (0 but
    for nodes holding a site with a plane; module docstring). A node without planes whose
    floor is already not below ``value`` gets the floor (a bound too) without the distance."""
    floor = best_value[node]
    if floor >= value and not planar[node]:
        return floor, 0.0
    g0 = max(low[node, 0] - x0, 0.0) + max(x0 - high[node, 0], 0.0)
    g1 = max(low[node, 1] - x1, 0.0) + max(x1 - high[node, 1], 0.0)
    g2 = max(low[node, 2] - x2, 0.0) + max(x2 - high[node, 2], 0.0)
    squared = g0 * g0 + g1 * g1 + g2 * g2
    gap = math.sqrt(squared) if squared > 0.0 else 0.0
    reach = max(gap - max_radius[node], 0.0)
    if mode == MODE_CAP:
        return max(floor, reach), 0.0
    bound = floor + slope * reach
    if not planar[node]:
        return bound, 0.0
    return bound, PRUNE_MARGIN * (abs(floor) + abs(bound) + slope * (gap + max_radius[node]))


@njit(inline="always", error_model="numpy")
def _dropped(bound, margin, value):
    """A node is dropped when its bound is not below the best value (margin 0: every cone of
    the node is at least the bound) or above it by more than the margin."""
    if margin == 0.0:
        return bound >= value
    return bound - value > margin + PRUNE_MARGIN * abs(value)


@njit(cache=True, nogil=True, error_model="numpy")
def _envelope_kernel(
    queries,
    best,
    depth,
    low,
    high,
    best_value,
    best_site,
    max_radius,
    planar,
    leaf_sites,
    sites,
    values,
    radii,
    gradients,
    mode,
    slope,
    cutoff,
):
    first_leaf = (1 << depth) - 1
    width = leaf_sites.shape[1]
    stack_node = np.empty(2 * depth + 2, dtype=np.int64)
    stack_bound = np.empty(2 * depth + 2)
    stack_margin = np.empty(2 * depth + 2)
    previous = -1  # the site of the last query's smallest cone: a first bound near this one
    for i in range(queries.shape[0]):
        x0, x1, x2 = queries[i, 0], queries[i, 1], queries[i, 2]
        value = best[i]
        enough = cutoff[i]  # a value at most this ends the walk (FlatTree.evaluate)
        if previous >= 0:
            cone = _cone(x0, x1, x2, previous, sites, values, radii, gradients, mode, slope)
            if cone < value:
                value = cone
        if value <= enough:
            best[i] = value
            continue
        bound, margin = _node_bound(
            x0, x1, x2, 0, value, low, high, best_value, max_radius, planar, mode, slope
        )
        stack_node[0], stack_bound[0], stack_margin[0] = 0, bound, margin
        top = 1
        while top > 0 and value > enough:
            top -= 1
            node = stack_node[top]
            if _dropped(stack_bound[top], stack_margin[top], value):
                continue
            site = best_site[node]
            cone = _cone(x0, x1, x2, site, sites, values, radii, gradients, mode, slope)
            if cone < value:
                value, previous = cone, site
            if node >= first_leaf:
                leaf = node - first_leaf
                for j in range(width):
                    site = leaf_sites[leaf, j]
                    if site < 0:
                        break
                    if mode != MODE_PLANE and values[site] >= value:
                        continue  # its cone is at least its value
                    cone = _cone(x0, x1, x2, site, sites, values, radii, gradients, mode, slope)
                    if cone < value:
                        value, previous = cone, site
                continue
            # Both children, the one with the larger bound pushed first (walked second).
            left = 2 * node + 1
            b_left, m_left = _node_bound(
                x0, x1, x2, left, value, low, high, best_value, max_radius, planar, mode, slope
            )
            b_right, m_right = _node_bound(
                x0, x1, x2, left + 1, value, low, high, best_value, max_radius, planar, mode, slope
            )
            near, far = (left, left + 1) if b_left <= b_right else (left + 1, left)
            b_near, b_far = min(b_left, b_right), max(b_left, b_right)
            m_near, m_far = (m_left, m_right) if b_left <= b_right else (m_right, m_left)
            if not _dropped(b_far, m_far, value):
                stack_node[top], stack_bound[top], stack_margin[top] = far, b_far, m_far
                top += 1
            if not _dropped(b_near, m_near, value):
                stack_node[top], stack_bound[top], stack_margin[top] = near, b_near, m_near
                top += 1
        best[i] = value


SELECT_SMALL = 16
"""A range this short is put in order by insertion instead of being partitioned further."""

SELECT_ROUNDS = 64
"""Partitions one selection may take before it sorts what is left: median-of-three pivots
make that rare, and it bounds the worst case by a sort."""


@njit(cache=True, nogil=True, error_model="numpy")
def tree_order(sites, depth):
    """The order of the sites in :meth:`.lipschitz._ConeTree._shape`'s tree: level by level,
    each node (the slice [s·n/2^l, (s+1)·n/2^l) of the order, rounded down) is split at its
    children's boundary along its first widest axis (as np.argmax), every site of the first
    child at most every site of the second there. A selection, not a sort: O(n) per level
    and no order promised within a child (the branch and bound returns the minimum over all sites'
    cones, whichever way ties are shared out). The sites' coordinates travel with their
    indices, so that every pass reads them in memory order."""
    count = len(sites)
    order = np.arange(count)
    placed = sites.copy()
    for level in range(depth):
        nodes = 2**level
        for s in range(nodes):
            start, end = (s * count) // nodes, ((s + 1) * count) // nodes
            split = ((2 * s + 1) * count) // (2 * nodes)
            axis = _widest_axis(placed, start, end)
            _select(placed, order, axis, start, end, split)
    return order


@njit(cache=True, nogil=True, error_model="numpy")
def _widest_axis(placed, start, end):
    """The first axis (as np.argmax) of the largest extent of rows start..end of ``placed``."""
    low = np.full(3, np.inf)
    high = np.full(3, -np.inf)
    for j in range(start, end):
        for axis in range(3):
            low[axis] = min(low[axis], placed[j, axis])
            high[axis] = max(high[axis], placed[j, axis])
    widest = 0
    for axis in (1, 2):
        if high[axis] - low[axis] > high[widest] - low[widest]:
            widest = axis
    return widest


@njit(cache=True, nogil=True, error_model="numpy")
def _select(placed, order, axis, start, end, split):
    """Permute rows start..end of ``placed`` and ``order`` alike so that no row before
    ``split`` is above any row from it on along ``axis``: quickselect, deterministic
    (median-of-three pivots, Hoare's partition, which shares ties out evenly), a sort of what
    is left after :data:`SELECT_ROUNDS` partitions. Each partition shrinks the range."""
    lo, hi = start, end
    for _ in range(SELECT_ROUNDS):
        if split <= lo or split >= hi:
            return
        if hi - lo <= SELECT_SMALL:
            _insertion_sort(placed, order, axis, lo, hi)
            return
        first, middle, last = placed[lo, axis], placed[(lo + hi) // 2, axis], placed[hi - 1, axis]
        pivot = max(min(first, middle), min(max(first, middle), last))
        left, right = _partition(placed, order, axis, lo, hi, pivot)
        if left == right:  # the row there equals the pivot, none before is above it
            if split == left:
                return
            lo, hi = (left + 1, hi) if split > left else (lo, left)
        else:  # rows lo..left are at most the pivot, rows left..hi at least it
            lo, hi = (left, hi) if split >= left else (lo, left)
    if lo < split < hi:
        ranked = np.argsort(placed[lo:hi, axis], kind="mergesort")
        placed[lo:hi] = placed[lo:hi][ranked]
        order[lo:hi] = order[lo:hi][ranked]


@njit(cache=True, nogil=True, error_model="numpy")
def _partition(placed, order, axis, lo, hi, pivot):
    """Hoare's partition of rows lo..hi around ``pivot`` (a value among them), the two
    scans stopping at rows equal to it. Returns (left, right): rows before ``left`` are at
    most the pivot, rows after ``right`` at least it, and either left == right + 1 or
    left == right, a row equal to the pivot."""
    left, right = lo, hi - 1
    while True:
        while placed[left, axis] < pivot:
            left += 1
        while placed[right, axis] > pivot:
            right -= 1
        if left >= right:
            return left, right
        _swap(placed, order, left, right)
        left += 1
        right -= 1


@njit(inline="always", error_model="numpy")
def _swap(placed, order, i, j):
    for axis in range(3):
        placed[i, axis], placed[j, axis] = placed[j, axis], placed[i, axis]
    order[i], order[j] = order[j], order[i]


@njit(cache=True, nogil=True, error_model="numpy")
def _insertion_sort(placed, order, axis, lo, hi):
    """Sort rows lo..hi of ``placed`` (and ``order`` alike) along ``axis``."""
    for i in range(lo + 1, hi):
        j = i
        while j > lo and placed[j - 1, axis] > placed[j, axis]:
            _swap(placed, order, j - 1, j)
            j -= 1
