"""Compiled nearest-allowed-pole search of the estimate of L (needs the optional numba).

:func:`.poles.nearest_allowed_pole` measures, from every site, the distance to the nearest
pole whose patch the site's patch allows. A k-d tree answers that exactly, but on a surface
whose medial axis is a curve (the core circle of a torus, the axis of every surface of
revolution) thousands of poles lie within a few 10⁻³ of the same distance from a site, and
scipy's tree, whose boxes are cut along the coordinate axes, opens all of them: issue 35
measured 44 µs a site on the 65 536-vertex torus, growing about as N^0.75 a site with the
vertex count N (the poles along the circle get denser, their spread stays).

Here the poles are sorted along a Morton curve and split into the ranges of an octree's cells,
each with its bounding box (the tree of :class:`.compiled_search.PieceTree`, built by the same
Python calls, with points as the pieces): the boxes follow the curve the poles lie on, so a query
walks, nearest box first, only the few boxes that can hold a pole nearer than its best so far.
Each pole's distance is ``sqrt(dx² + dy² + dz²)``, summed in that order, as scipy's k-d tree
computes it, and a pole replaces the best only when strictly nearer: the distance is the exact
minimum over the allowed poles, equal to the k-d tree's (tested), whatever the tree visits.

The kernels release the GIL and run on the library's threads. All compiled helpers stay in
this one file: numba checks only the defining file's timestamp before reusing cached machine
code.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ...geometry.threads import chunk_bounds, run_in_threads
from .compiled_search import _box_gap, _push_children

QUERY_CHUNK = 4096
"""Queries handed to a worker thread at a time."""
POLE_LEAF_SIZE = 16
"""Poles per leaf of the tree (at most). The answer does not depend on it (module docstring);
where thousands of poles are nearly equally far from a query, larger leaves open fewer boxes
per pole measured."""


class PoleTree:
    """Poles (p, 3) with a label each, in a bounding-box tree along a Morton curve."""

    def __init__(self, points: np.ndarray, labels: np.ndarray):
        from .compiled_search import build_tree, morton_order

        points = np.asarray(points, dtype=float)
        order, codes = morton_order(points)
        self.order = order
        self.points = np.ascontiguousarray(points[order])
        self.labels = np.ascontiguousarray(np.asarray(labels)[order], dtype=np.int64)
        _, nodes = build_tree(codes, self.points, self.points, POLE_LEAF_SIZE)
        self.tree = (self.points, *nodes)

    def nearest_allowed(self, queries, query_labels, allowed) -> tuple[np.ndarray, np.ndarray]:
        """(distance, pole index in the caller's order) of the nearest pole whose label
        ``allowed[query label, pole label]`` accepts, per query (inf and −1 where none); of
        equally near poles the one of lowest index (boxes as near as the best are walked)."""
        queries = np.ascontiguousarray(queries, dtype=float)
        query_labels = np.ascontiguousarray(query_labels, dtype=np.int64)
        allowed = np.ascontiguousarray(allowed, dtype=np.bool_)
        distance = np.full(len(queries), np.inf)
        found = np.full(len(queries), -1, dtype=np.int64)
        if not len(queries) or not len(self.points):
            return distance, found

        def task(bounds):
            lo, hi = bounds
            _nearest_allowed_kernel(
                lo,
                hi,
                queries,
                query_labels,
                allowed,
                self.labels,
                self.order,
                distance,
                found,
                self.tree,
            )

        run_in_threads(task, chunk_bounds(len(queries), QUERY_CHUNK))
        hit = found >= 0
        found[hit] = self.order[found[hit]]
        return distance, found

    def k_nearest(self, queries, k: int) -> tuple[np.ndarray, np.ndarray]:
        """(distance, pole index in the caller's order), each (n, k): the k nearest poles of
        each query by distance, then by index (inf and −1 past the last pole), whatever the
        labels."""
        queries = np.ascontiguousarray(queries, dtype=float)
        distance = np.full((len(queries), k), np.inf)
        found = np.full((len(queries), k), -1, dtype=np.int64)
        if not len(queries) or not len(self.points) or k < 1:
            return distance, found

        def task(bounds):
            lo, hi = bounds
            _k_nearest_kernel(lo, hi, queries, self.order, distance, found, self.tree)

        run_in_threads(task, chunk_bounds(len(queries), QUERY_CHUNK))
        hit = found >= 0
        found[hit] = self.order[found[hit]]
        np.sqrt(distance, out=distance)
        return distance, found


@njit(cache=True, nogil=True, error_model="numpy")
def _k_nearest_kernel(lo, hi, queries, order, squared, found, tree):
    """Per query, the k nearest poles by (squared distance, caller's index), kept sorted in
    its rows of ``squared`` and ``found`` (tree positions; inf and −1 where none)."""
    points, node_low, node_high, node_range, node_child = tree
    k = squared.shape[1]
    stack = np.zeros(256, dtype=np.int64)
    for i in range(lo, hi):
        x0, x1, x2 = queries[i, 0], queries[i, 1], queries[i, 2]
        top = 0
        stack[0] = 0
        while top >= 0:
            node = stack[top]
            top -= 1
            # A box farther than the k-th best holds none of the k nearest.
            if _box_gap(node_low, node_high, node, x0, x1, x2) > squared[i, k - 1]:
                continue
            if node_child[node, 0] >= 0:
                top = _push_children(stack, top, node_low, node_high, node_child, node, x0, x1, x2)
                continue
            for p in range(node_range[node, 0], node_range[node, 1]):
                d0, d1, d2 = points[p, 0] - x0, points[p, 1] - x1, points[p, 2] - x2
                value = d0 * d0 + d1 * d1 + d2 * d2
                slot = k
                while slot > 0 and (
                    value < squared[i, slot - 1]
                    or (
                        value == squared[i, slot - 1]
                        and (found[i, slot - 1] < 0 or order[p] < order[found[i, slot - 1]])
                    )
                ):
                    slot -= 1
                if slot == k:
                    continue
                for j in range(k - 1, slot, -1):
                    squared[i, j], found[i, j] = squared[i, j - 1], found[i, j - 1]
                squared[i, slot], found[i, slot] = value, p


@njit(cache=True, nogil=True, error_model="numpy")
def _nearest_allowed_kernel(
    lo, hi, queries, query_labels, allowed, labels, order, distance, found, tree
):
    points, node_low, node_high, node_range, node_child = tree
    stack = np.zeros(256, dtype=np.int64)
    for i in range(lo, hi):
        x0, x1, x2 = queries[i, 0], queries[i, 1], queries[i, 2]
        g = query_labels[i]
        best, squared, which = np.inf, np.inf, -1
        top = 0
        stack[0] = 0
        while top >= 0:
            node = stack[top]
            top -= 1
            # A box no nearer than the best can hold no strictly nearer pole.
            if _box_gap(node_low, node_high, node, x0, x1, x2) > squared:
                continue
            left = node_child[node, 0]
            if left < 0:  # a leaf
                for p in range(node_range[node, 0], node_range[node, 1]):
                    if not allowed[g, labels[p]]:
                        continue
                    d0, d1, d2 = points[p, 0] - x0, points[p, 1] - x1, points[p, 2] - x2
                    value = d0 * d0 + d1 * d1 + d2 * d2
                    if value < squared or (value == squared and order[p] < order[which]):
                        squared, which = value, p
                continue
            top = _push_children(stack, top, node_low, node_high, node_child, node, x0, x1, x2)
        if which >= 0:
            best = math.sqrt(squared)
        distance[i] = best
        found[i] = which
