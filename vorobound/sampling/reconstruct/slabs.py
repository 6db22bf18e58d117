"""The fans of M̂'s Delaunay edges from overlapping slabs of the seeds: memory bounded by a slab.

CGAL's triangulation of all the seeds and GUDHI's simplex tree of it, alive together, were the
memory peak of ``reconstruct`` (issue 32: 3.4 GB for the 1.08·10⁶ seeds of the cube at
ε = 0.0094977). Here the seeds are cut along the longest axis of their box into slabs of about
``SLAB_SEEDS`` seeds (the *cores*, which partition the axis), each widened by a margin on both
sides (its *window* W); one window is triangulated at a time, and only what M̂ needs of it is
kept: the tetrahedra around the in/out edges the slab *owns* (the midpoint of the edge in its
core), with their circumcentres, in the order they turn.

Why a window gives the whole set's fans (the empty-ball property). Let P be all the seeds and Q = P
∩ W. A tetrahedron of the Delaunay triangulation DT(Q) whose circumscribed ball lies in W (closed
slab) is a tetrahedron of DT(P): the seeds of P left out of Q lie outside W, so outside the ball,
which stays empty (with the engine's symbolic perturbation, geogram's lexicographic one or CGAL's,
the same holds of the perturbed balls: seeds strictly outside a ball are not affected by it). Such a
tetrahedron is *certified* (its ball, widened by its rounding error, inside W). The tetrahedra
around an owned edge ab in DT(Q) form a closed cycle; when every one is certified they are
tetrahedra of DT(P) that close around ab, hence all the tetrahedra around ab in DT(P) (the link of
an interior edge is one cycle). The engine gives tetrahedra in the lexicographic order of
their vertices, and a slab's vertices keep the order of the seeds, so the walk around ab starts at
the same tetrahedron and the circumcentres are computed from the same coordinates in the same order:
the cycle, its orientation and its circumcentres are the whole set's, bit for bit, and so is M̂
after welding (the tetrahedra are numbered in the same lexicographic order). A flat tetrahedron
borrows its circumcentre from a face neighbour
(:func:`.facets.flat_circumcentres`: faces 0 … 3 tried in turn, each reading the centres
borrowed before it, for up to ``FLAT_ROUNDS`` rounds); its value depends only on the
neighbours across the faces it tried (up to the one it borrowed from in the first round; all
four otherwise) and, for the flat ones among them, on theirs. Its own circumscribed ball can be
huge and reach past the window, so the borrowed ball certifies nothing about it: a flat
tetrahedron is certified only when all four of its face neighbours exist and are certified,
repeated until nothing changes (an independent review found a flat tetrahedron certified
through the one face it borrowed from, in the slab's triangulation but not the whole set's,
all four checks below passing and a facet of M̂ lost:
``test_a_flat_tetrahedron_is_certified_through_all_four_faces``). Why that suffices: a
certified non-flat tetrahedron is one of DT(P) (its empty ball lies in the window); every face
of a certified flat tetrahedron is then shared with a certified tetrahedron, so the certified
set is a union of tetrahedra whose every interior face passes the local Delaunay test with
seeds of the window and the same symbolic perturbation; a locally Delaunay triangulation of a
region bounded by faces of DT(P) is DT(P) there (the Delaunay lemma; the perturbation makes it
unique), so each certified flat tetrahedron is the whole set's too, and its circumcentre,
computed from the same neighbours in the same order, is the whole set's bit for bit.

Completeness: every in/out facet of DT(P) is built, by exactly one slab. Edges are *owned* by
the slab whose core holds their midpoint (the cores partition space), or, for the edges left
out, by the box about them that holds it (the boxes of a round are disjoint along the axis, and
skip the edges already built): at most one slab builds an edge. That every one is built is
certified by four checks, and the caller triangulates the whole set when one fails:

1. Every tetrahedron kept is certified (above): the facets built are facets of M̂ = M̂(P).
2. Every in/out edge of every tetrahedron kept is built (edges left out, or not seen by their
   owner, are built in boxes about their midpoints with the margin doubled, up to
   ``MARGIN_ROUNDS`` times). Then the built facets M̂' form a 2-cycle: a Voronoi edge of M̂ is
   the dual of a mixed Delaunay triangle, in exactly two in/out facets, and both are built
   when one is (its tetrahedra are kept with the one built).
3. The seeds on the hull of P carry one label, so no in/out edge lies on it and every facet of
   M̂ is bounded: M̂ is a 2-cycle too (the boundary of the union of the inside cells). A seed on
   the hull of P lies on the hull of every window holding it, so the seeds in a core on their
   window's hull include every seed on P's hull; when they carry both labels, those on their
   own hull (qhull's vertices and coplanar points: P's hull) must carry one.
4. The seeds are connected through edges of G: the same-label edges of certified tetrahedra
   (a union–find over the seeds), the in/out edges built, and, for seeds left apart, the
   same-label edges to their nearest neighbours whose diametral ball (widened by
   ``GABRIEL_RTOL``) holds no other seed (Gabriel edges: the midpoint lies inside their
   Voronoi facet).

Proof. The facets missed, C = M̂ − M̂', form a 2-cycle of bounded polygons (2 and 3), so their
winding number w_C is an integer, constant off C. For an edge st of G, the path from s
straight to a point inside the Voronoi facet of st and on straight to t stays inside the
cells of s and t, and crosses only that facet, which is not in C (it separates two seeds of
one label, or it was built): w_C(s) = w_C(t), and by 4 w_C is the same at every seed. For a
missed edge ab the same path crosses its facet, which is in C, once and nothing else of C:
w_C(a) − w_C(b) = ±1. So no edge is missed. (In degenerate position the argument is made for
the seeds under the engine's symbolic perturbation, whose triangulation it computes; the checks are
combinatorial and hold for it.) The old rule (before issue 32's follow-up) had only check 2,
which leaves out whole components of M̂ whose seed pairs lie more than twice the margin apart
along the axis: no slab's window holds both seeds of any of them (the tests build such a
component).

The margin. A ball around an edge whose midpoint lies in the core reaches past the core at
most as far as it reaches from that midpoint along the axis (at most its diameter, as it holds
the midpoint). A probe (a small box about the median seed, its window the box widened by a
margin on every side, certified the same way) measures the farthest reach of the balls
around its in/out edges; the margin is ``MARGIN_GROWTH`` times it. The boxes start from the
farthest reach of the balls the slabs certified (bounded by their diameters; a wide core
certifies balls wider than its margin) and double it each round. An edge left out after the
last round (an unbounded facet: on the hull of all the seeds), a failed check, or two slabs
that computed different circumcentres for one tetrahedron make :func:`slab_fans` return None,
and the caller triangulates the whole set.

References
----------
The surface M̂ of VoroCrust (:mod:`.facets`); the empty-ball property of Delaunay
triangulations.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...progress import Counter, Progress
from .engine import delaunay_tetrahedra

WHOLE_SEEDS = 1_500_000
"""Up to this many seeds the whole set is triangulated at once (faster: the slabs trade CPU
time for memory, docs/reconstruct.md; the whole set's peak grows about linearly). On geogram,
M̂ of the cube's 1.08·10⁶ seeds takes 23.9 CPU-s and 1.37 GB at once against 30.1 CPU-s and
1.29 GB in 3 slabs (``bench_reconstruct.py --slabs cube-0.0095``); on CGAL's route, with its
simplex tree, it was 3.16 GB against 1.88, and the threshold 750,000."""
SLAB_SEEDS = 400_000
"""Seeds per slab core above ``WHOLE_SEEDS``."""
PROBE_SIZE = 0.005
"""Half the side of the probe's box (:func:`_probe_reach`), as a fraction of the seeds' extent
along the slabs' axis (doubled while it certifies nothing)."""
PROBE_MARGIN = 2.0
"""The probe's first margin, in sides of its box (doubled until the balls it measures reach
less than half of it)."""
FALLBACK_MARGIN = 0.125
"""The first margin, as a fraction of the mean slab width, when the probe certifies nothing."""
MARGIN_ROUNDS = 4
"""Rounds of boxes about the edges left out, the margin doubled each time, before the whole
set is triangulated (and tries of the probe)."""
MARGIN_GROWTH = 1.25
"""The slabs' margin is this multiple of the farthest reach of the certified balls around the
probe's in/out edges from their midpoints."""
BALL_RTOL = 1e-6
"""A ball is widened by this fraction of its radius (and its rounding error) before it is
compared with the window (a flat tetrahedron's borrowed centre is equidistant from its
vertices only to ``facets.WELD_RTOL``)."""
EXACT_REACH_SEEDS = 50_000
"""Windows of up to this many seeds (the probe, the boxes) measure how far their balls reach
from their edges' midpoints; larger ones (the slabs) bound it by the balls' diameters."""
GABRIEL_NEIGHBOURS = 8
"""Nearest neighbours tried for each seed the certified tetrahedra leave apart."""
GABRIEL_RTOL = 1e-9
"""A nearest neighbour's edge joins when no other seed lies within its diametral ball widened
by this fraction (its midpoint is then inside their Voronoi facet, whatever the rounding)."""
_VALUES = ("centres", "radius", "error", "flat")
"""The values per tetrahedron that every slab holding it must agree on."""


@dataclass(frozen=True)
class SlabFans:
    """The fans of the in/out edges, gathered from the slabs."""

    centres: np.ndarray
    """(T, 3) circumcentre of every tetrahedron around an in/out edge (lexicographic order of
    their vertices)."""
    radius: np.ndarray
    error: np.ndarray
    flat: np.ndarray
    """(T,) the tetrahedron's circumcentre is borrowed from a neighbour."""
    pairs: np.ndarray
    """(E, 2) inside and outside seed of each in/out edge, in the order of their keys."""
    tets: np.ndarray
    """Tetrahedra (rows of ``centres``) around each edge, edge after edge, in turning order."""
    offsets: np.ndarray
    present: np.ndarray
    """(n,) the seed is a vertex of a slab's triangulation."""
    tetrahedra: int
    """Tetrahedra of the slabs whose circumcentre lies in the slab's core (the whole set's
    count when every ball lies in its window; an estimate otherwise)."""
    slabs: int


@dataclass
class _SlabPart:
    quads: np.ndarray
    centres: np.ndarray
    radius: np.ndarray
    error: np.ndarray
    flat: np.ndarray
    inner: np.ndarray
    outer: np.ndarray
    lengths: np.ndarray
    corners: np.ndarray
    """Rows of ``quads`` around each owned edge, edge after edge."""
    required: np.ndarray
    """Keys of the in/out edges of the certified tetrahedra that another part must build."""
    tetrahedra: int


@dataclass
class _Evidence:
    """What the slabs saw, for the completeness certificate (:func:`_complete`)."""

    present: np.ndarray
    """(n,) the seed is a vertex of a slab's triangulation."""
    on_hull: np.ndarray
    """(n,) the seed lies in a slab's core and on the hull of its window's seeds."""
    parent: np.ndarray | None
    """(n,) union–find over the seeds (None: nothing joined, as in the probe)."""

    @classmethod
    def empty(cls, seeds_n: int, joined: bool = True) -> _Evidence:
        parent = np.arange(seeds_n, dtype=np.int64) if joined else None
        return cls(np.zeros(seeds_n, dtype=bool), np.zeros(seeds_n, dtype=bool), parent)


def slab_count(seeds: int) -> int:
    """Slabs for this many seeds (1: the whole set at once, up to ``WHOLE_SEEDS``)."""
    return 1 if seeds <= WHOLE_SEEDS else math.ceil(seeds / SLAB_SEEDS)


def slab_fans(
    points: np.ndarray,
    inside: np.ndarray,
    kernel,
    centres,
    slabs: int,
    progress: Progress | None = None,
    engine: str | None = None,
) -> SlabFans | None:
    """The fans of every in/out Delaunay edge of ``points`` (in the frame of
    :func:`.facets.seed_frame`), triangulated in ``slabs`` overlapping slabs; None when a slab
    cannot certify its edges (the caller then triangulates the whole set).

    ``kernel`` is :mod:`.facets_kernel` (the slabs need the compiled steps), ``centres`` the
    circumcentres of :func:`.facets.flat_circumcentres` (passed in: :mod:`.facets` calls this
    module), ``engine`` that of :func:`.engine.delaunay_tetrahedra`.
    """
    steps = (kernel, centres, engine)
    axis = int(np.argmax(np.ptp(points, axis=0)))
    x = np.ascontiguousarray(points[:, axis])
    bounds = np.concatenate([[-np.inf], _cuts(x, slabs), [np.inf]])
    seeds_n = len(points)
    seen = _Evidence.empty(seeds_n)
    margin = MARGIN_GROWTH * _probe_reach(points, inside, steps, x, slabs)
    parts, left, reach = [], [], margin
    counter = Counter(progress, "Delaunay", slabs)
    for k in range(slabs):
        low, high = np.full(3, -np.inf), np.full(3, np.inf)
        low[axis], high[axis] = bounds[k], bounds[k + 1]
        part, needed, rest = _slab(points, inside, steps, (low, high), margin, seen)
        if part is None:
            return None
        parts.append(part)
        left.append(rest)
        reach = max(reach, MARGIN_GROWTH * needed)
        counter.step()
    # A box is about the midpoints of its edges: its margin must reach as far as the balls
    # certified in the slabs reach from theirs (a wide core certifies balls wider than the
    # margin), and doubles from there each round.
    margin = 0.5 * reach
    # Edges whose balls left their slab's window, and in/out edges of kept tetrahedra that
    # their owner did not see: boxes about them, with wider margins.
    keys = np.concatenate(left)
    for round_ in range(MARGIN_ROUNDS + 1):
        built = np.sort(np.concatenate([_keys(part, seeds_n) for part in parts]))
        required = np.unique(np.concatenate([part.required for part in parts]))
        keys = np.union1d(keys, required[~_isin_sorted(required, built)])
        if not len(keys) or round_ == MARGIN_ROUNDS:
            break
        margin *= 2
        left = []
        for box in _patches(points, keys, axis, margin):
            part, _, rest = _slab(points, inside, steps, box, margin, seen, built)
            if part is None:
                return None
            part.tetrahedra = 0  # counted by the slabs
            parts.append(part)
            left.append(rest)
        keys = np.concatenate(left)
    if len(keys) or not _complete(points, inside, kernel, seen, parts):
        return None
    return _merged(parts, seen.present, seeds_n, slabs)


def _complete(points, inside, kernel, seen, parts) -> bool:
    """The completeness certificate (module docstring, steps 3 and 4): the seeds on the hull
    of a slab's window inside its core carry one label, and the seeds that are vertices,
    joined through the same-label edges of the certified tetrahedra (already in
    ``seen.parent``), the in/out edges built and, for the seeds left apart, the same-label
    edges to their nearest neighbours whose diametral ball holds no other seed, form one
    set."""
    if not _one_hull_label(points, inside, np.flatnonzero(seen.on_hull)):
        return False
    parent, present = seen.parent, seen.present
    for part in parts:
        kernel.join_pairs(parent, part.inner, part.outer)
    root = kernel.roots(parent)
    seeds = np.flatnonzero(present)
    if not len(seeds):
        return False
    apart = seeds[root[seeds] != np.argmax(np.bincount(root[seeds]))]
    if len(apart):
        from scipy.spatial import cKDTree

        tree = cKDTree(points[seeds])
        _, near = tree.query(points[apart], k=min(GABRIEL_NEIGHBOURS + 1, len(seeds)))
        first = np.repeat(apart, near.shape[1] - 1)
        second = seeds[near[:, 1:].reshape(-1)]
        keep = (inside[first] == inside[second]) & (first != second)
        first, second = first[keep], second[keep]
        middle = 0.5 * (points[first] + points[second])
        radius = 0.5 * np.linalg.norm(points[first] - points[second], axis=1)
        # Widened by the midpoint's rounding too, so both ends are always counted: a count of
        # 2 then means no third seed (near-duplicate ends could otherwise drop out of their
        # own ball and let a third seed in unseen).
        slack = 8 * np.finfo(float).eps * np.abs(middle).max(axis=1)
        inner = tree.query_ball_point(
            middle, radius * (1 + GABRIEL_RTOL) + slack, return_length=True
        )
        empty = inner <= 2
        kernel.join_pairs(parent, first[empty], second[empty])
        root = kernel.roots(parent)
    return bool((root[seeds] == root[seeds[0]]).all())


def _cuts(x, slabs) -> np.ndarray:
    """The borders of the slabs' cores along the axis: quantiles of the seeds' coordinates."""
    return np.quantile(x, np.arange(1, slabs) / slabs) if slabs > 1 else np.empty(0)


def _isin_sorted(values, sorted_keys) -> np.ndarray:
    """``np.isin`` against keys already sorted (a binary search)."""
    if not len(sorted_keys):
        return np.zeros(len(values), dtype=bool)
    spot = np.minimum(np.searchsorted(sorted_keys, values), len(sorted_keys) - 1)
    return sorted_keys[spot] == values


def _keys(part, seeds_n) -> np.ndarray:
    """The keys (min·n + max) of the edges a part built."""
    return np.minimum(part.inner, part.outer) * seeds_n + np.maximum(part.inner, part.outer)


def _patches(points, keys, axis, margin):
    """Boxes about the midpoints of the edges ``keys`` (min·n + max), one per group of
    midpoints along ``axis`` (groups split where they lie more than two margins apart, so the
    boxes do not overlap)."""
    seeds_n = len(points)
    midpoint = 0.5 * (points[keys // seeds_n] + points[keys % seeds_n])
    order = np.argsort(midpoint[:, axis])
    along = midpoint[order, axis]
    split = np.flatnonzero(np.diff(along) > 2 * margin) + 1
    for group in np.split(order, split):
        low, high = midpoint[group].min(axis=0), midpoint[group].max(axis=0)
        yield low, np.nextafter(high, np.inf)


def _probe_reach(points, inside, steps, x, slabs) -> float:
    """How far the balls around the in/out edges reach from their edges' midpoints, measured
    in a small box (the probe) about the median seed along ``x``: its window is widened until
    the balls it certifies reach less than half its margin (they are not cut short by it)."""
    centre = points[np.argpartition(x, len(x) // 2)[len(x) // 2]]
    half = PROBE_SIZE * float(np.ptp(x))
    margin = PROBE_MARGIN * 2 * half
    reach = None
    for _ in range(MARGIN_ROUNDS):
        box = (centre - half, centre + half)
        _, reach, _ = _slab(points, inside, steps, box, margin, _Evidence.empty(len(points), False))
        if reach and reach < 0.5 * margin:
            return reach
        if not reach:  # no in/out edge in the box, or too few seeds
            half *= 2
        margin *= 2
    return reach or FALLBACK_MARGIN * float(np.ptp(x)) / slabs


def _one_hull_label(points, inside, candidates) -> bool:
    """True when the seeds on the hull of all the seeds carry one label (then no in/out
    Delaunay edge is on the hull: no facet of M̂ is unbounded). ``candidates`` hold every seed
    on that hull (each lies on the hull of its own slab's window, inside its core), so their
    hull is the seeds' hull; where they carry both labels, those on it (qhull's vertices and
    coplanar points) must carry one."""
    labels = inside[candidates]
    if not len(labels) or labels.min() == labels.max():
        return True
    from scipy.spatial import ConvexHull, QhullError

    try:
        hull = ConvexHull(points[candidates], qhull_options="Qc")
    except (QhullError, ValueError):
        return False
    on = np.union1d(hull.vertices, hull.coplanar[:, 0] if len(hull.coplanar) else [])
    labels = labels[on.astype(np.int64)]
    return bool(labels.min() == labels.max())


def _slab(points, inside, steps, core, margin, seen, built=None):
    """One slab's part: the seeds in the box ``core`` widened by ``margin``, the in/out edges
    whose midpoint is in the core (and whose key is not among the sorted keys ``built``) and
    whose balls stay in the window; the margin its certified balls need (how far the farthest
    reaches from the midpoint of its edge along an axis: measured in a window of at most
    ``EXACT_REACH_SEEDS`` seeds, else bounded by twice its widened radius); and the keys of
    the owned edges left out (a ball leaves the window, or the edge is on the window's hull).
    The part is None when the triangulation fails (too few seeds, or inconsistent). ``seen``
    gathers the evidence of :func:`_complete`: the seeds triangulated, the seeds of the core
    on the window's hull, and (a union–find over the seeds) the vertices of one label of each
    certified tetrahedron joined."""
    kernel, circumcentres, engine = steps
    low, high = core[0] - margin, core[1] + margin
    window = np.flatnonzero(((points >= low) & (points <= high)).all(axis=1))
    if len(window) < 5:
        return None, None, None
    local = delaunay_tetrahedra(points[window], engine)
    if not len(local):
        return None, None, None
    neighbours, ok = kernel.face_neighbours(local, len(window))
    if not ok:
        return None, None, None
    tets = window[local]  # ascending rows stay ascending: the window keeps the seeds' order
    del local
    seen.present[tets.reshape(-1)] = True
    open_face = neighbours < 0
    if open_face.any():
        # The vertices of the faces on the window's hull (the face opposite corner k).
        rows, corner = np.nonzero(open_face)
        face = tets[rows][np.arange(4) != corner[:, None]]
        hull = points[face]
        in_core = ((hull >= core[0]) & (hull < core[1])).all(axis=1)
        seen.on_hull[face[in_core]] = True
    centres, radius, error, flat, last = circumcentres(points, tets, neighbours, kernel)
    reach = ((radius + error) * (1 + BALL_RTOL))[:, None]
    finite = np.isfinite(centres).all(axis=1)
    certified = finite & np.isfinite(reach[:, 0])
    for axis in np.flatnonzero(np.isfinite(low) | np.isfinite(high)):  # a slab: one axis
        with np.errstate(invalid="ignore"):
            certified &= (centres[:, axis] - reach[:, 0] >= low[axis]) & (
                centres[:, axis] + reach[:, 0] <= high[axis]
            )
    # A flat tetrahedron's own ball says nothing (its borrowed centre is a neighbour's): it is
    # certified only when all four face neighbours exist and are certified, until nothing
    # changes (the loop only removes, so it ends). Then each certified flat tetrahedron's four
    # faces are faces of DT(P) and, with the certified set locally Delaunay under the same
    # perturbation, it is a tetrahedron of DT(P) (module docstring).
    flat_rows = np.flatnonzero(flat)
    flat_neighbours = neighbours[flat_rows]
    while True:
        around = certified[np.maximum(flat_neighbours, 0)] & (flat_neighbours >= 0)
        settled = certified[flat_rows] & around.all(axis=1)
        if np.array_equal(settled, certified[flat_rows]):
            break
        certified[flat_rows] = settled
    del flat_rows, flat_neighbours, last
    if seen.parent is not None:
        kernel.join_same_label(seen.parent, tets, certified, inside)
    middle = centres.copy()
    middle[~finite] = points[tets[~finite]].mean(axis=1)
    tetrahedra = int(((middle >= core[0]) & (middle < core[1])).all(axis=1).sum())
    first, inner, outer, length, turn, found, ok = kernel.find_edges(
        points, tets, neighbours, inside
    )
    if not ok:
        return None, None, None
    first, inner, outer, length, turn = (v[:found] for v in (first, inner, outer, length, turn))
    midpoint = 0.5 * (points[inner] + points[outer])
    owned = ((midpoint >= core[0]) & (midpoint < core[1])).all(axis=1)
    key = np.minimum(inner, outer) * len(points) + np.maximum(inner, outer)
    if built is not None:
        owned &= ~_isin_sorted(key, built)
    # An owned edge open in the window (on its hull) is left out like one whose balls leave
    # it: a wider window closes it, unless it is on the hull of all the seeds.
    closed = length >= 0
    rest = key[owned & ~closed]
    owned &= closed
    key = key[owned]
    first, inner, outer, length, turn = (v[owned] for v in (first, inner, outer, length, turn))
    offsets = np.concatenate([[0], np.cumsum(length)])
    cycle = np.empty(int(offsets[-1]), dtype=np.int64)
    kernel.write_cycles(tets, neighbours, first, inner, outer, turn < 0, offsets, cycle)
    sure = certified[cycle]
    edge = np.repeat(np.arange(len(length)), length)
    good = np.bincount(edge, ~sure, minlength=len(length)) == 0
    rest = np.concatenate([rest, key[~good]])
    if not good.all():
        first, inner, outer, length, turn = (v[good] for v in (first, inner, outer, length, turn))
        cycle = cycle[np.repeat(good, offsets[1:] - offsets[:-1])]

    used, corners = dense_unique(cycle, len(tets))
    # How far a certified ball around a kept edge reaches from the edge's midpoint along an
    # axis: measured in a small window (the probe, a box), else bounded by its radius (the
    # ball holds the midpoint) plus its widened radius (no (corner, 3) arrays for a slab).
    if len(window) <= EXACT_REACH_SEEDS:
        edge_midpoint = np.repeat(midpoint[owned][good], length, axis=0)
        extent = (np.abs(centres[cycle] - edge_midpoint) + reach[cycle]).max(axis=1)
        needed = float(extent.max()) if len(extent) else 0.0
    else:
        needed = float((radius[used] + reach[used, 0]).max()) if len(used) else 0.0
    quads = tets[used]
    label = inside[quads]
    required = []
    for p, q in ((0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)):
        mixed = label[:, p] != label[:, q]
        a, b = quads[mixed, p], quads[mixed, q]
        if built is None:
            # An in/out edge of the slab's triangulation with its midpoint in the core is
            # owned here: built, or left out and built in a box (or the whole set is
            # triangulated). Only the others are checked when the parts are merged.
            middle = 0.5 * (points[a] + points[b])
            away = ~((middle >= core[0]) & (middle < core[1])).all(axis=1)
            a, b = a[away], b[away]
        required.append(np.minimum(a, b) * len(points) + np.maximum(a, b))
    part = _SlabPart(
        quads=quads,
        centres=centres[used],
        radius=radius[used],
        error=error[used],
        flat=flat[used],
        inner=inner,
        outer=outer,
        lengths=length,
        corners=corners,
        required=np.unique(np.concatenate(required)),
        tetrahedra=tetrahedra,
    )
    return part, needed, rest


def dense_unique(values: np.ndarray, bound: int) -> tuple[np.ndarray, np.ndarray]:
    """``np.unique(values, return_inverse=True)`` for integers in [0, bound), by a table of
    ``bound`` entries instead of a sort."""
    present = np.zeros(bound, dtype=bool)
    present[values] = True
    unique = np.flatnonzero(present)
    rank = np.empty(bound, dtype=np.int64)
    rank[unique] = np.arange(len(unique))
    return unique, rank[values]


def _merged(parts, present, seeds_n, slabs) -> SlabFans | None:
    """The slabs' parts as one set of numbered tetrahedra and edges in key order; None when
    two slabs disagree on a tetrahedron or an in/out edge of a certified tetrahedron was built
    by no slab. The parts' arrays are released as they are gathered (the merge was the memory
    peak of the slabs)."""
    sizes = [len(p.quads) for p in parts]
    quads = _taken(parts, "quads")
    high = (quads[:, 0] << 32) | quads[:, 1]
    low = (quads[:, 2] << 32) | quads[:, 3]
    del quads
    order = np.lexsort((low, high))
    high, low = high[order], low[order]
    new = np.ones(len(order), dtype=bool)
    new[1:] = (high[1:] != high[:-1]) | (low[1:] != low[:-1])
    del high, low
    number = np.empty(len(order), dtype=np.int64)
    number[order] = np.cumsum(new) - 1
    pick = order[new]
    del order, new
    merged = {}
    for name in _VALUES:
        value = _taken(parts, name)
        merged[name] = value[pick]
        if not np.array_equal(value, merged[name][number], equal_nan=True):
            return None
        del value
    start = np.cumsum([0] + sizes)
    tets = number[np.concatenate([p.corners + s for p, s in zip(parts, start, strict=False)])]
    del number
    inner, outer, lengths = (_taken(parts, name) for name in ("inner", "outer", "lengths"))
    key = np.minimum(inner, outer) * seeds_n + np.maximum(inner, outer)
    required = np.unique(np.concatenate([p.required for p in parts]))
    order = np.argsort(key, kind="stable")
    if not _isin_sorted(required, key[order]).all():
        return None
    del key
    offsets = np.concatenate([[0], np.cumsum(lengths)])
    new_offsets = np.concatenate([[0], np.cumsum(lengths[order])])
    index = np.arange(int(new_offsets[-1])) - np.repeat(new_offsets[:-1], lengths[order])
    tets = tets[np.repeat(offsets[:-1][order], lengths[order]) + index]
    return SlabFans(
        centres=merged["centres"],
        radius=merged["radius"],
        error=merged["error"],
        flat=merged["flat"],
        pairs=np.column_stack([inner[order], outer[order]]),
        tets=tets,
        offsets=new_offsets,
        present=present,
        tetrahedra=sum(p.tetrahedra for p in parts),
        slabs=slabs,
    )


def _taken(parts, name) -> np.ndarray:
    """The parts' arrays ``name``, concatenated; each part's array released."""
    value = np.concatenate([getattr(p, name) for p in parts])
    for part in parts:
        setattr(part, name, np.empty((0,) + value.shape[1:], value.dtype))
    return value
