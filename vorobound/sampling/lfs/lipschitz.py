"""The λ-Lipschitz repair of a sizing function: L(x) ← min_y L(y) + λ|x − y|.

The result is the largest λ-Lipschitz function that nowhere exceeds the given values. It is
computed exactly (up to rounding) by branch and bound on a k-d tree of the sites: a node
holding sites with smallest value m and bounding box B cannot beat the best value found for
a query x once m + λ·dist(x, B) is not smaller. All queries of a chunk descend the tree
together, one level per numpy step. Each query starts from the cones of its nearest sites
(scipy's k-d tree), an upper bound that is usually the answer or close to it, so that the
descent prunes almost everything off the query's own path; chunks run on both cores.

With numba (:mod:`.compiled_envelope`) each query walks the same tree alone, compiled, nearer
child first: the same cones with the same arithmetic, a value never above the numpy path's
(equal on every tested query), at several times less CPU per query. The numpy path above
stays the reference; ``VOROBOUND_PURE_NUMPY`` forces it. Neither path rounds a cone down:
a value may exceed the exact real envelope by the rounding of one cone (a few units in the
last place), in both paths alike.
"""

from __future__ import annotations

import functools
import math
import os
from typing import Any

import numpy as np

from ...errors import InputError
from ...geometry.threads import chunk_bounds, run_in_threads, thread_count
from ...progress import Counter, Progress

LEAF_SIZE = 8
"""Sites per leaf of the tree."""
QUERY_CHUNK = 4096
"""Queries that descend the tree together (bounds the number of live query-node pairs)."""
CHUNKS_PER_STEP = 16
"""Chunks run on the threads between two progress reports."""
START_NEIGHBOURS = 4
"""Nearest sites whose cones give each query its first upper bound."""
START_BLOCK = 1 << 17
"""Queries whose nearest sites are found together."""


class _ConeTree:
    """Implicit balanced k-d tree: node k at depth d holds sites order[b_d[k]:b_d[k + 1]].

    A site may carry a radius ρ: its cone is then value + slope·max(0, |x − y| − ρ), flat on
    the ball of radius ρ (a site standing for a small piece of surface). It may also carry a
    gradient a (|a| ≤ slope): its cone is then value + max(a·(x − y), slope·(|x − y| − ρ)),
    the tangent plane of L inside the ball and the plain cone far away (a = 0: the flat cone).
    Such a cone is never below floor + slope·max(0, |x − y| − ρ), floor = value − c with
    c = |a|·slope·ρ/(slope + |a|) the deepest the plane dips before the cone takes over; the
    nodes are bounded with the floors.
    """

    depth: int
    order: np.ndarray
    low: list[np.ndarray]
    """Per depth, the lower corner of each node's box."""
    high: list[np.ndarray]
    leaf_sites: np.ndarray

    def __init__(
        self,
        sites: np.ndarray,
        values: np.ndarray,
        radii: np.ndarray | None = None,
        like: _ConeTree | None = None,
        gradients: np.ndarray | None = None,
        floors: np.ndarray | None = None,
    ):
        """The tree of ``sites``; ``like``, a tree of the same sites, lends its shape;
        ``floors`` (default ``values``) bound each site's cone from below (class docstring)."""
        radii = np.zeros(len(sites)) if radii is None else np.asarray(radii, dtype=float)
        self.sites, self.values, self.radii = sites, values, radii
        self.gradients = gradients
        if like is None:
            self._shape(sites)
        else:
            self.depth, self.order, self.low, self.high = (
                like.depth,
                like.order,
                like.low,
                like.high,
            )
            self.leaf_sites = like.leaf_sites
        # Per node, bottom-up: the smallest value, the first site of the node (in tree order)
        # that has it, and the largest radius.
        count, order = len(sites), self.order
        bounds = self._bounds(self.depth, count)
        value = (values if floors is None else floors)[order]
        best = np.minimum.reduceat(value, bounds[:-1])
        segment = np.repeat(np.arange(len(bounds) - 1), np.diff(bounds))
        smallest = np.where(value == best[segment], np.arange(count), count)
        best_site = order[np.minimum.reduceat(smallest, bounds[:-1])]
        max_radius = np.maximum.reduceat(radii[order], bounds[:-1])
        self.best_value, self.best_site, self.max_radius = [best], [best_site], [max_radius]
        for _ in range(self.depth):
            left, right = best[0::2], best[1::2]
            best_site = np.where(left <= right, best_site[0::2], best_site[1::2])
            best = np.minimum(left, right)
            max_radius = np.maximum(max_radius[0::2], max_radius[1::2])
            self.best_value.append(best)
            self.best_site.append(best_site)
            self.max_radius.append(max_radius)
        for per_depth in (self.best_value, self.best_site, self.max_radius):
            per_depth.reverse()

    def _shape(self, sites: np.ndarray) -> None:
        """The order of the sites (median splits along the widest axis), the nodes' boxes and
        the leaves."""
        count = len(sites)
        self.depth = max(0, math.ceil(math.log2(max(count / LEAF_SIZE, 1))))
        compiled = compiled_envelope()
        if compiled is not None:
            order = compiled.tree_order(np.ascontiguousarray(sites, dtype=float), self.depth)
        else:
            order = self._numpy_order(sites)
        self.order = order
        bounds = self._bounds(self.depth, count)
        placed = sites[order]
        low = np.minimum.reduceat(placed, bounds[:-1])
        high = np.maximum.reduceat(placed, bounds[:-1])
        self.low, self.high = [low], [high]
        for _ in range(self.depth):
            low = np.minimum(low[0::2], low[1::2])
            high = np.maximum(high[0::2], high[1::2])
            self.low.append(low)
            self.high.append(high)
        self.low.reverse()
        self.high.reverse()
        width = int(np.diff(bounds).max())
        slots = bounds[:-1, None] + np.arange(width)
        self.leaf_sites = np.where(
            slots < bounds[1:, None], order[np.minimum(slots, count - 1)], -1
        )

    def _numpy_order(self, sites: np.ndarray) -> np.ndarray:
        """The order of the sites: each node's sites sorted along its widest axis, level by
        level. :func:`.compiled_envelope.tree_order` only splits each node there, a selection;
        where sites tie along a split axis the two may share them out differently between
        the children, and either tree gives the same envelope."""
        count = len(sites)
        order = np.arange(count)
        for depth in range(self.depth):
            bounds = self._bounds(depth, count)
            segment = np.repeat(np.arange(len(bounds) - 1), np.diff(bounds))
            placed = sites[order]
            low = np.minimum.reduceat(placed, bounds[:-1])
            high = np.maximum.reduceat(placed, bounds[:-1])
            axis = np.argmax(high - low, axis=1)
            # Sort every node by its widest coordinate, all nodes in one sort: the key is the
            # node's index plus the coordinate mapped into [0, 1/2] (any split gives a valid
            # tree; the branch and bound is exact for every tree).
            rows = np.arange(len(axis))
            lowest, extent = low[rows, axis], (high - low)[rows, axis]
            offset = placed[np.arange(count), axis[segment]] - lowest[segment]
            key = segment + 0.5 * offset / np.where(extent > 0, extent, 1.0)[segment]
            order = order[np.argsort(key, kind="stable")]
        return order

    def cones(self, x: np.ndarray, site: np.ndarray, slope: float | None) -> np.ndarray:
        """The cones of sites ``site`` at points ``x`` (same leading shape; ``x`` (..., 3)):
        :meth:`combine` of value and the distance past the radius, or with gradients
        value + max(a·(x − y), slope·(|x − y| − ρ))."""
        offset = x - self.sites[site]
        past = np.linalg.norm(offset, axis=-1) - self.radii[site]
        if self.gradients is None or slope is None:
            return self.combine(self.values[site], np.maximum(past, 0), slope)
        along = (offset * self.gradients[site]).sum(axis=-1)
        return self.values[site] + np.maximum(along, slope * past)

    @staticmethod
    def _bounds(depth: int, count: int) -> np.ndarray:
        return (np.arange(2**depth + 1) * count) // 2**depth

    @staticmethod
    def combine(value, beyond, slope: float | None):
        """A site's cone at a query: value + slope·beyond, or max(value, beyond) without a
        slope (``beyond``: the distance past the site's radius)."""
        return np.maximum(value, beyond) if slope is None else value + slope * beyond

    def envelope(self, queries: np.ndarray, slope: float | None, best: np.ndarray) -> np.ndarray:
        """min over sites y of their cones (:meth:`combine`) at each query x, given upper
        bounds ``best`` (the value of some cone at each query; updated in place). A node's
        cones are at least its smallest value combined with its distance beyond the largest
        radius."""
        pair_query = np.arange(len(queries))
        node = np.zeros(len(queries), dtype=np.int64)
        for depth in range(self.depth + 1):
            x = queries[pair_query]
            gap = np.maximum(self.low[depth][node] - x, 0) + np.maximum(
                x - self.high[depth][node], 0
            )
            reach = np.maximum(np.linalg.norm(gap, axis=1) - self.max_radius[depth][node], 0)
            bound = self.combine(self.best_value[depth][node], reach, slope)
            live = bound < best[pair_query]
            pair_query, node, x = pair_query[live], node[live], x[live]
            site = self.best_site[depth][node]
            np.minimum.at(best, pair_query, self.cones(x, site, slope))
            if depth < self.depth:
                pair_query = np.repeat(pair_query, 2)
                node = (2 * np.repeat(node, 2)) + np.tile([0, 1], len(node))
        sites = self.leaf_sites[node]
        valid = sites >= 0
        safe = np.where(valid, sites, 0)
        candidate = self.cones(queries[pair_query][:, None, :], safe, slope)
        candidate = np.where(valid, candidate, np.inf).min(axis=1)
        np.minimum.at(best, pair_query, candidate)
        return best


class Envelope:
    """x ↦ min over sites y of value(y) + slope·max(0, |x − y| − ρ(y)), the tree built once
    (ρ = 0 unless ``radii`` are given). With ``gradients`` a(y) (|a| ≤ slope) a site's cone
    is value(y) + max(a·(x − y), slope·(|x − y| − ρ(y))): L's tangent plane on the site's ball,
    the cone beyond. Each cone is slope-Lipschitz, so their minimum is too."""

    tree: _ConeTree
    slope: float | None
    """None for a :class:`DistanceCap` (no cones)."""
    _nearest: Any

    def __init__(
        self,
        sites: np.ndarray,
        values: np.ndarray,
        slope: float,
        radii: np.ndarray | None = None,
        like: Envelope | None = None,
        gradients: np.ndarray | None = None,
    ):
        """``like``: an envelope of the same sites, whose tree lends its shape."""
        sites, values = _checked(sites, values, slope)
        if radii is not None:
            radii = np.asarray(radii, dtype=float)
            if radii.shape != values.shape or not (np.isfinite(radii).all() and (radii >= 0).all()):
                raise InputError("site radii must be finite, ≥ 0, one per site")
        floors = None
        if gradients is not None:
            gradients = np.asarray(gradients, dtype=float)
            size = np.linalg.norm(gradients, axis=1) if gradients.ndim == 2 else np.zeros(0)
            if (
                gradients.shape != sites.shape
                or not np.isfinite(gradients).all()
                or (size > slope * (1 + 1e-12)).any()
            ):
                raise InputError("site gradients must be finite, (n, 3), at most the slope long")
            reach = np.zeros(len(sites)) if radii is None else radii
            with np.errstate(invalid="ignore", divide="ignore"):
                dip = np.where(size > 0, size * slope * reach / (slope + size), 0.0)
            floors = values - dip
            if not gradients.any():  # plain cones: skip the planes' arithmetic
                gradients = floors = None
        shape = None
        if like is not None and np.array_equal(like.tree.sites, sites):
            shape = like.tree
        self.tree = _ConeTree(sites, values, radii, shape, gradients, floors)
        self.slope = float(slope)
        self._nearest = None if shape is None or like is None else like._nearest
        self._flat: Any = None

    def __call__(
        self,
        queries: np.ndarray,
        progress: Progress | None = None,
        upper: np.ndarray | None = None,
        cutoff: np.ndarray | None = None,
    ) -> np.ndarray:
        """The envelope at ``queries`` (m, 3), or its minimum with ``upper`` if given.

        ``cutoff`` (m,), optional: where the envelope is at most the query's cutoff, the
        result may be any value from it up to the cutoff (the compiled search stops at the
        first cone that low); elsewhere it is the envelope, bit for bit. For a caller that
        needs only max(envelope, cutoff) (:func:`.sites.spacings`).
        """
        queries = np.asarray(queries, dtype=float)
        counter = Counter(progress, "Lipschitz repair", len(queries))
        compiled = compiled_envelope()
        if compiled is not None:
            if self._flat is None:
                self._flat = compiled.FlatTree(self.tree)
            queries = np.ascontiguousarray(queries)
            result = np.full(len(queries), np.inf)
            if upper is not None:
                np.minimum(result, upper, out=result)
            cuts = None if cutoff is None else np.ascontiguousarray(cutoff, dtype=float)

            def descend(chunk):
                start, stop = chunk
                self._flat.evaluate(
                    queries[start:stop],
                    self.slope,
                    result[start:stop],
                    None if cuts is None else cuts[start:stop],
                )

        else:
            result = self._start(queries)
            if upper is not None:
                np.minimum(result, upper, out=result)

            def descend(chunk):
                start, stop = chunk
                self.tree.envelope(queries[start:stop], self.slope, result[start:stop])

        chunks = chunk_bounds(len(queries), QUERY_CHUNK)
        for first in range(0, len(chunks), CHUNKS_PER_STEP):
            batch = chunks[first : first + CHUNKS_PER_STEP]
            run_in_threads(descend, batch)
            counter.step(batch[-1][1] - batch[0][0])
        return result

    def _start(self, queries: np.ndarray) -> np.ndarray:
        """The smallest cone value at each query among its nearest sites."""
        from scipy.spatial import cKDTree

        tree = self.tree
        if self._nearest is None:
            self._nearest = cKDTree(tree.sites)
        k = min(START_NEIGHBOURS, len(tree.sites))
        out = np.empty(len(queries))
        for start in range(0, len(queries), START_BLOCK):
            block = queries[start : start + START_BLOCK]
            index = self._nearest.query(block, k=k, workers=thread_count())[1].reshape(
                len(block), k
            )
            # The cones as the tree's own search computes them (the same rounding).
            cones = tree.cones(block[:, None], index, self.slope)
            out[start : start + len(block)] = cones.min(axis=1)
        return out


class DistanceCap(Envelope):
    """x ↦ min over sites y of max(value(y), max(0, |x − y| − ρ(y))): the smallest v such
    that a site of value at most v lies within v of x (beyond its radius)."""

    def __init__(self, sites: np.ndarray, values: np.ndarray, radii: np.ndarray):
        super().__init__(sites, values, 0.0, radii)
        self.slope = None


@functools.cache
def _load_compiled_envelope():
    try:
        from . import compiled_envelope as module
    except (ImportError, RuntimeError, OSError):  # no numba, or one that cannot cache
        return None
    return module


def compiled_envelope():
    """The compiled evaluation (:mod:`.compiled_envelope`), or None: numba is missing, or the
    environment variable ``VOROBOUND_PURE_NUMPY`` is set (then the numpy descent runs)."""
    if os.environ.get("VOROBOUND_PURE_NUMPY"):
        return None
    return _load_compiled_envelope()


def _checked(sites, values, slope):
    sites = np.asarray(sites, dtype=float)
    values = np.asarray(values, dtype=float)
    if (
        sites.ndim != 2
        or sites.shape[1] != 3
        or len(sites) == 0
        or values.shape != sites[:, 0].shape
    ):
        raise InputError("the Lipschitz repair needs sites (n, 3) with one value each, n ≥ 1")
    if not (math.isfinite(slope) and slope >= 0):
        raise InputError(f"the Lipschitz constant must be finite and ≥ 0, got {slope}")
    if not (np.isfinite(sites).all() and np.isfinite(values).all()):
        raise InputError("the Lipschitz repair needs finite sites and values")
    return sites, values


def lipschitz_envelope(
    sites: np.ndarray,
    values: np.ndarray,
    slope: float,
    queries: np.ndarray | None = None,
    progress: Progress | None = None,
) -> np.ndarray:
    """The λ-Lipschitz lower envelope of point values, evaluated at queries.

    Parameters
    ----------
    sites : ndarray (n, 3)
        Points where the values are given.
    values : ndarray (n,)
        Finite values at the sites.
    slope : float
        λ ≥ 0.
    queries : ndarray (m, 3), optional
        Where to evaluate (default: the sites themselves).
    progress : Progress, optional
        Called with task "Lipschitz repair".

    Returns
    -------
    ndarray (m,)
        min over sites y of values(y) + λ·|x − y|: λ-Lipschitz, and at a site never above its
        value (equal to it when the values already are λ-Lipschitz).
    """
    envelope = Envelope(sites, values, slope)
    return envelope(envelope.tree.sites if queries is None else queries, progress)
