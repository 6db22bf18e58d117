"""Medial-axis points of a surface sample: the Voronoi poles of Amenta and Bern.

The Voronoi cell of a point of a dense surface sample is a thin needle along the surface
normal, and its two far ends (the poles, one on each side of the surface) lie near the medial
axis (Amenta & Bern, "Surface reconstruction by Voronoi filtering", 1999). Voronoi vertices are
the circumcentres of the Delaunay tetrahedra (CGAL's, through GUDHI: :mod:`.delaunay`).

Sampled smooth surfaces are full of cospherical point sets (every sample of a sphere is one),
whose Delaunay triangulation is not unique. The triangulation is therefore built on a copy of
the sample moved by a tiny pseudo-random jitter, which picks one, while every circumcentre is
computed from the unmoved points.

Ill-conditioned circumcentres are the second difficulty. Four (nearly) cocircular points have
a circumcentre that moves far along the axis of their circle under the smallest perturbation:
the rounding of coordinates to single precision, as in every STL file, or the jitter itself.
Such a centre is a wrong pole, and it can sit close to the surface (before these tests, a
grid torus stored in single precision had errors of tens of percent). Three tests drop
them:

* reliability: comparing each circumcentre with that of the jittered corners shows how far
  it moves per unit of perturbation; one that the rounding of the input coordinates moves by
  more than UNRELIABLE_RTOL of its radius is dropped (only for inputs coarser than double
  precision);
* emptiness, locally: no far vertex of the four neighbouring tetrahedra inside the ball;
* consistency of the poles: no sample inside the ball of its nearest pole. A pole that fails
  is dropped with every other circumcentre of its point whose ball holds the same sample, the
  next farthest one takes its place, and the test repeats.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from ...errors import InputError
from ...geometry.kernels import load_kernel, pure_numpy
from ...geometry.threads import chunk_bounds, run_in_threads, thread_count
from ...mesh.rows import unique_rows
from ...progress import Counter, Progress
from .delaunay import delaunay_tetrahedra

JITTER = 1e-6
"""Size of the jitter applied before the triangulation, relative to each point's distance to
its nearest neighbour (local, so that a far-away part of the model does not blur this one).
(Chosen when qhull built the triangulation, which smaller jitters slowed down on cospherical
samples: 10⁻⁸ made the 163 842-vertex icosphere take 108 s instead of 7 s.)"""
SPACING_FLOOR = 1e-6
"""Nearest-neighbour distances below SPACING_FLOOR (in diameters) count as SPACING_FLOOR, so
that the jitter stays above the rounding of the coordinates."""
FLAT_RTOL = 1e-12
"""A tetrahedron with |det| ≤ FLAT_RTOL·(longest edge)³ has no circumcentre (it is flat)."""
EMPTY_RTOL = 1e-4
"""A sample closer to a circumcentre than (1 − EMPTY_RTOL)·radius − EMPTY_ATOL (radius: the
largest distance to its four corners) shows that its ball is not empty. Chosen on icospheres
whose vertices carry relative noise 10⁻⁸: 10⁻⁵ keeps ill-conditioned circumcentres, 10⁻³
limits the accuracy to a few 10⁻⁴."""
EMPTY_ATOL = 20
"""Slack of the emptiness tests in units of the largest jitter of a tetrahedron's corners: the
triangulation is Delaunay for the jittered points."""
UNRELIABLE_RTOL = 1e-2
"""A circumcentre that the input's rounding can move by more than UNRELIABLE_RTOL·radius is
not used. Chosen on single-precision icospheres with and without edge midpoints: a third of
it drops so many good circumcentres that wrong ones become poles, three times it keeps wrong
ones."""
NOISE_FLOOR = 1e-3
"""Noise below NOISE_FLOOR times the median jitter (double-precision rounding) is not checked
for."""
EMPTY_ROUNDS = 8
"""Rounds of the pole consistency test; poles still failing after the last one are dropped."""
FAR = 1e3
"""Poles farther than FAR diameters from the sample's centre are dropped (they are the far
ends of nearly unbounded cells and cannot be the nearest medial point of the surface)."""
NEAREST_CLUSTERS = 4
"""Clusters of coinciding sites looked at first by :func:`nearest_site`."""
NEAREST_PAIRS = 1 << 22
"""(query, site) distances :func:`nearest_site` measures together (bounds its memory)."""
LARGEST_CLUSTER = 2048
"""Above this many coinciding sites :func:`nearest_site` leaves the search to the k-d tree."""
TET_CHUNK = 1 << 15
"""Tetrahedra a thread of the compiled pass takes at a time (bounds the chunk arrays)."""
POINT_CHUNK = 1 << 14
"""Points a thread of the compiled pass takes at a time."""
BACKUP_POLES = 4
"""Next nearest poles each sample keeps from its last search (:func:`_consistent_poles`)."""
MERGE_RTOL = 1e-10
"""Poles closer than MERGE_RTOL diameters are one point (symmetric shapes repeat them)."""


@dataclass(frozen=True)
class MedialSample:
    """Distinct pole positions of a sample, in the sample's coordinates."""

    points: np.ndarray
    tetrahedra: int
    """Delaunay tetrahedra of the (jittered) sample."""
    dropped: int
    """Tetrahedra left out: flat, or whose ball (unmoved points) is shown not to be empty."""
    owner_labels: np.ndarray | None = None
    """With labels: the label of the sample each pole belongs to (a pole serving samples of
    several labels appears once per label, poles closer than MERGE_RTOL once), aligned with
    ``labelled_points``."""
    labelled_points: np.ndarray | None = None
    labelled_reach: np.ndarray | None = None
    """With labels: the distance from each labelled pole to the nearest corner of its
    tetrahedron (a sample point): an upper bound on its distance to the sample."""


def vertex_poles(
    points: np.ndarray,
    normals: np.ndarray,
    noise: float = 0.0,
    seed: int = 0,
    progress: Progress | None = None,
    labels: np.ndarray | None = None,
    adjacent: np.ndarray | None = None,
) -> MedialSample:
    """Poles of each sample point on both sides of its normal line.

    With ``labels`` (a patch per point) and ``adjacent`` (labels × labels, True for two
    different adjacent patches), a Delaunay ball is a candidate pole of a point only if none
    of its four corners lies on a patch adjacent to the point's: balls that touch two adjacent
    patches are the ones a sharp feature between them creates (docs/lfs.md).

    Parameters
    ----------
    points : ndarray (n, 3)
        The sample, n ≥ 5, centred and of diameter about 1 (the tolerances are absolute).
    normals : ndarray (n, 3)
        A normal direction per point; only the line matters (its sign is ignored).
    noise : float
        How far the coordinates may be off (their rounding), in the units of ``points``;
        circumcentres it can move by more than UNRELIABLE_RTOL of their radius are not used.
    seed : int
        Seed of the jitter.
    progress : Progress, optional
        Called with task "Delaunay" and "poles".

    Returns
    -------
    MedialSample
        The pole of each point on each side, except on the side where the point's Voronoi cell
        is unbounded (points on the convex hull), merged and without far ones.

    References
    ----------
    Amenta & Bern (1999), definition of poles; Amenta, Choi & Kolluri (2001), the power crust.
    """
    counter = Counter(progress, "Delaunay", 1)
    random = np.random.default_rng(seed)
    jitter = JITTER * nearest_spacing(points)
    moved = points + jitter[:, None] * random.standard_normal(points.shape)
    tets, neighbours = delaunay_tetrahedra(moved)
    if not len(tets):
        raise InputError(
            "the mesh vertices are (nearly) coplanar: a flat surface has no finite local "
            "feature size"
        )
    counter.step()
    counter = Counter(progress, "poles", 2)
    # The centres of the jittered corners show how much each centre moves per unit of
    # perturbation of its corners.
    check_noise = noise > NOISE_FLOOR * float(np.median(jitter))
    kernel = compiled_medial()
    if kernel is not None:
        centres, bound, usable = _compiled_tet_pass(
            kernel, points, moved, tets, neighbours, jitter, noise if check_noise else 0.0
        )
    else:
        centres, radii = _circumcentres(points[tets])
        moved_by = jitter[tets].max(axis=1)
        bound = (1 - EMPTY_RTOL) * radii - EMPTY_ATOL * moved_by
        if check_noise:
            shift = np.linalg.norm(_circumcentres(moved[tets])[0] - centres, axis=1)
            with np.errstate(invalid="ignore"):
                bound[shift * (noise / moved_by) > UNRELIABLE_RTOL * radii] = np.nan
        usable = np.isfinite(bound) & _locally_empty(points, tets, neighbours, centres, bound)
    counter.step()
    unbounded = _unbounded_side(points, normals, tets, neighbours)
    candidates: _IncidentCandidates | _SortedCandidates
    if kernel is not None:
        candidates = _IncidentCandidates(
            kernel, points, normals, tets, centres, usable, unbounded, labels, adjacent
        )
    else:
        candidates = _SortedCandidates(
            *_pole_candidates(points, normals, tets, centres, usable, unbounded, labels, adjacent)
        )
    chosen = _consistent_poles(points, centres, bound, candidates, usable)
    poles = centres[chosen]
    key = np.round(poles / MERGE_RTOL).astype(np.int64)
    _, first = unique_rows(key, return_index=True)
    labelled = labelled_points = labelled_reach = None
    if labels is not None and candidates.any:
        # The final pole of every (point, side) group, tagged with the point's label.
        group, tet = candidates.farthest(usable)
        keep = np.linalg.norm(centres[tet], axis=1) < FAR
        pairs = unique_rows(np.c_[tet[keep], labels[candidates.owner(group[keep])]])
        # Poles closer than MERGE_RTOL are one point per label, as above (on a sampled
        # torus, every tetrahedron of a ring of cospherical samples has its own copy).
        merged = np.round(centres[pairs[:, 0]] / MERGE_RTOL).astype(np.int64)
        _, once = unique_rows(np.c_[merged, pairs[:, 1]], return_index=True)
        pairs = pairs[np.sort(once)]
        labelled, labelled_points = pairs[:, 1], centres[pairs[:, 0]]
        corners = points[tets[pairs[:, 0]]]
        labelled_reach = np.linalg.norm(corners - labelled_points[:, None], axis=2).min(axis=1)
    counter.step()
    return MedialSample(
        poles[np.sort(first)],
        len(tets),
        int((~usable).sum()),
        labelled,
        labelled_points,
        labelled_reach,
    )


@functools.cache
def _load_compiled_poles():
    return load_kernel(f"{__package__}.compiled_poles")


def compiled_poles():
    """:mod:`.compiled_poles`, or None without numba or with ``VOROBOUND_PURE_NUMPY`` set."""
    return None if pure_numpy() else _load_compiled_poles()


@functools.cache
def _load_compiled_medial():
    return load_kernel(f"{__package__}.compiled_medial")


def compiled_medial():
    """:mod:`.compiled_medial`, or None without numba or with ``VOROBOUND_PURE_NUMPY`` set."""
    return None if pure_numpy() else _load_compiled_medial()


def nearest_spacing(points: np.ndarray) -> np.ndarray:
    """Distance from each point to its nearest other point, at least SPACING_FLOOR."""
    from scipy.spatial import cKDTree

    distance = cKDTree(points).query(points, k=2, workers=thread_count())[0][:, 1]
    return np.maximum(distance, SPACING_FLOOR)


def nearest_site(sites: np.ndarray, queries: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Distance to the nearest of ``sites`` and its index, for each query.

    Many sites may coincide to rounding (the circumcentres of the tetrahedra of one
    cospherical set of samples, hundreds on a sampled torus), and a k-d tree cannot tell them
    apart without measuring every one. The tree therefore holds one site per cluster closer
    than MERGE_RTOL; the clusters near enough to hold the nearest site are then measured in
    full.

    With numba the search is instead the compiled walk of :mod:`.compiled_poles` (exact, the
    lowest index among equally near sites): the poles of a curved medial axis (a torus's core
    circle) put thousands of sites at nearly one distance from each query, which scipy's tree
    opens all of (issue 35: 3.5 CPU-s of a 65 536-vertex torus, growing faster than N).
    """
    from scipy.spatial import cKDTree

    compiled = compiled_poles()
    if compiled is not None:
        tree = compiled.PoleTree(sites, np.zeros(len(sites), dtype=np.int64))
        return tree.nearest_allowed(queries, np.zeros(len(queries)), np.ones((1, 1), bool))

    key = np.round(sites / MERGE_RTOL).astype(np.int64)
    _, first, cluster = np.unique(key, axis=0, return_index=True, return_inverse=True)
    cluster = cluster.reshape(-1)
    largest = int(np.bincount(cluster).max())
    if len(first) == len(sites) or largest > LARGEST_CLUSTER:
        # No clusters, or one so large (a sphere's poles are all its centre) that measuring
        # its members for every query would take more memory and time than the tree.
        return cKDTree(sites).query(queries, workers=thread_count())
    spread = float(np.linalg.norm(sites - sites[first][cluster], axis=1).max())
    order = np.argsort(cluster, kind="stable")
    start = np.searchsorted(cluster[order], np.arange(len(first) + 1))
    tree = cKDTree(sites[first])
    distance, index = np.empty(len(queries)), np.empty(len(queries), dtype=np.int64)
    chunk = max(1, NEAREST_PAIRS // (2 * largest))
    for lo in range(0, len(queries), chunk):
        todo = np.arange(lo, min(lo + chunk, len(queries)))
        k = min(NEAREST_CLUSTERS, len(first))
        while len(todo):
            reach, near = tree.query(queries[todo], k=k, workers=thread_count())
            reach, near = reach.reshape(len(todo), k), near.reshape(len(todo), k)
            # Every member lies within `spread` of its cluster's first site.
            slack = 2 * spread * (1 + 1e-9) + 1e-15 * reach[:, :1]
            within = reach <= reach[:, :1] + slack
            done = ~within[:, -1] | (k == len(first))
            rows = todo[done]
            found = _members_nearest(sites, order, start, queries[rows], near[done], within[done])
            distance[rows], index[rows] = found
            todo, k = todo[~done], min(4 * k, len(first))
    return distance, index


def _members_nearest(sites, order, start, queries, clusters, use):
    """Nearest member of the ``clusters`` (where ``use``) of each query: (distance, index)."""
    if not len(queries):
        return np.zeros(0), np.zeros(0, dtype=np.int64)
    row, column = np.nonzero(use)
    cluster = clusters[row, column]
    sizes = start[cluster + 1] - start[cluster]
    owner = np.repeat(row, sizes)
    member = order[
        np.repeat(start[cluster], sizes)
        + np.arange(sizes.sum())
        - np.repeat(np.cumsum(sizes) - sizes, sizes)
    ]
    gap = np.linalg.norm(sites[member] - queries[owner], axis=1)
    # The nearest member per query (entries are grouped by query), the lowest index among
    # equals.
    starts = np.flatnonzero(np.r_[True, owner[1:] != owner[:-1]])
    nearest = np.minimum.reduceat(gap, starts)
    best = np.where(gap == np.repeat(nearest, np.diff(np.r_[starts, len(gap)])), member, len(sites))
    return nearest, np.minimum.reduceat(best, starts)


def _consistent_poles(points, centres, bound, candidates, usable) -> np.ndarray:
    """The pole tetrahedra after the consistency test: no sample inside the ball of its nearest
    pole (closer to its centre than ``bound``). ``usable`` is updated in place; ``candidates``:
    a :class:`_SortedCandidates` or :class:`_IncidentCandidates`.

    Each round drops the failing poles and, in the groups (point, side) they served, every
    circumcentre whose ball holds the same sample; the nearest poles are then updated only
    for the samples that lost theirs or that a new pole is closer to. A sample that lost its
    pole looks first among the BACKUP_POLES next nearest of its last search (:class:`_Backups`)
    and the new poles, and searches all poles again only when none of those is left.
    """
    chosen = np.zeros(0, dtype=np.int64)
    nearest = np.full(len(points), -1)
    gap = np.full(len(points), np.inf)
    backups = _Backups(len(points))
    for round_ in range(EMPTY_ROUNDS):
        group, pole_tet = candidates.farthest(usable)
        near = np.linalg.norm(centres[pole_tet], axis=1) < FAR
        group, pole_tet = group[near], pole_tet[near]
        current = np.unique(pole_tet)
        if len(current) == 0:
            return current
        new = np.setdiff1d(current, chosen, assume_unique=True)
        chosen = current
        _renew_nearest(points, centres, chosen, new, gap, nearest, backups, round_)
        depth = bound[nearest] - gap
        inside = np.flatnonzero(depth > 0)
        if len(inside) == 0:
            break
        witness = np.full(len(centres), -1)
        deepest_last = inside[np.argsort(depth[inside])]
        witness[nearest[deepest_last]] = deepest_last
        usable[nearest[inside]] = False
        hit = witness[pole_tet] >= 0
        candidates.drop(points, centres, bound, group[hit], witness[pole_tet[hit]], usable)
    return chosen[usable[chosen]]


def _renew_nearest(points, centres, chosen, new, gap, nearest, backups, round_) -> None:
    """Update ``gap`` and ``nearest`` (each sample's nearest pole, a tetrahedron, −1 for none
    yet) in place for the poles ``chosen`` now, of which ``new`` were not chosen before: the
    samples whose pole is gone take their first backup still chosen or search again, and
    every sample compares its pole with the new ones."""
    lost = np.flatnonzero(~np.isin(nearest, chosen))
    kept = np.flatnonzero(np.isin(nearest, chosen))
    # Samples whose last search was over last round's poles: their nearest pole now is the
    # first of their backups still chosen, or a new pole.
    lost, backed = backups.take(lost, chosen, round_, gap, nearest)
    if len(lost):
        gap[lost], nearest[lost] = backups.search(centres, chosen, points[lost], lost, round_)
    if len(new) and len(backed):
        distance, index = nearest_site(centres[new], points[backed])
        tet = new[index]
        closer = (distance < gap[backed]) | ((distance == gap[backed]) & (tet < nearest[backed]))
        gap[backed[closer]], nearest[backed[closer]] = distance[closer], tet[closer]
    if len(new) and len(kept):
        distance, index = nearest_site(centres[new], points[kept])
        closer = distance < gap[kept]
        gap[kept[closer]], nearest[kept[closer]] = distance[closer], new[index[closer]]


class _Backups:
    """The BACKUP_POLES nearest poles (tetrahedra, by distance, then index) of each sample at
    its last search over all chosen poles, and the round of that search (compiled path only:
    without numba every search finds the nearest pole alone)."""

    def __init__(self, count: int):
        self.tets = np.full((count, BACKUP_POLES), -1, dtype=np.int64)
        self.gaps = np.full((count, BACKUP_POLES), np.inf)
        self.round = np.full(count, -2)

    def search(self, centres, chosen, queries, samples, round_):
        """(distance, tetrahedron) of the nearest chosen pole of each of ``samples``, whose
        backups are renewed."""
        compiled = compiled_poles()
        if compiled is None:
            distance, index = nearest_site(centres[chosen], queries)
            return distance, chosen[index]
        tree = compiled.PoleTree(centres[chosen], np.zeros(len(chosen), dtype=np.int64))
        distance, index = tree.k_nearest(queries, BACKUP_POLES)
        self.tets[samples] = np.where(index >= 0, chosen[np.maximum(index, 0)], -1)
        self.gaps[samples], self.round[samples] = distance, round_
        return distance[:, 0], self.tets[samples, 0]

    def take(self, lost, current, round_, gap, nearest):
        """Split ``lost`` into (samples that must search again, samples given their first
        backup still in ``current``, with ``gap`` and ``nearest`` set). Only backups from the
        last round qualify: every pole chosen since is then one of this round's new poles."""
        recent = lost[self.round[lost] == round_ - 1]
        if not len(recent):
            return lost, recent
        alive = np.isin(self.tets[recent], current)
        found = alive.any(axis=1)
        first = np.argmax(alive, axis=1)[found]
        backed = recent[found]
        gap[backed] = self.gaps[backed, first]
        nearest[backed] = self.tets[backed, first]
        return np.setdiff1d(lost, backed, assume_unique=True), backed


class _SortedCandidates:
    """The (point, side) groups of pole candidates as sorted arrays (:func:`_pole_candidates`):
    the numpy path."""

    def __init__(self, candidates, starts, owner):
        self.candidates, self.starts, self.owners = candidates, starts, owner
        self.ends = np.r_[starts[1:], len(candidates)].astype(np.int64)
        self.any = len(candidates) > 0

    def farthest(self, usable):
        """(groups with a usable candidate, the farthest usable candidate of each)."""
        position = _farthest(self.candidates, self.starts, usable)
        group = np.flatnonzero(position >= 0)
        return group, self.candidates[position[group]]

    def owner(self, group):
        """The point of each group."""
        return self.owners[self.starts[group]]

    def drop(self, points, centres, bound, group, witness, usable):
        """:func:`_drop_containing` in the groups ``group``."""
        first, last = self.starts[group], self.ends[group]
        _drop_containing(points, centres, bound, self.candidates, first, last, witness, usable)


class _IncidentCandidates:
    """The same groups read from each point's list of usable tetrahedra by the compiled
    kernels (:mod:`.compiled_medial`), never stored: a group is 2·point + side, and its
    farthest usable candidate is looked for again only once the last one found is dropped."""

    def __init__(self, kernel, points, normals, tets, centres, usable, unbounded, labels, adjacent):
        self.kernel = kernel
        use_labels = labels is not None and adjacent is not None and bool(adjacent.any())
        if not use_labels:
            labels, adjacent = np.zeros(len(points), np.int64), np.zeros((1, 1), bool)
        self.entry = (
            np.ascontiguousarray(points, dtype=float),
            np.ascontiguousarray(normals, dtype=float),
            centres,
            tets,
            np.ascontiguousarray(unbounded, dtype=np.int64),
            np.ascontiguousarray(labels, dtype=np.int64),
            np.ascontiguousarray(adjacent, dtype=np.bool_),
            use_labels,
        )
        self.start, self.members = kernel.incidence(tets, usable, len(points))
        self.best = np.full(2 * len(points), -1, dtype=np.int64)
        self._update(np.arange(len(points)), usable)
        self.any = bool((self.best >= 0).any())

    def _update(self, vertices, usable):
        def task(bounds):
            self.kernel.group_farthest(
                *self.entry, self.start, self.members, usable, vertices, *bounds, self.best
            )

        run_in_threads(task, chunk_bounds(len(vertices), POINT_CHUNK))

    def farthest(self, usable):
        """(groups with a usable candidate, the farthest usable candidate of each)."""
        dropped = (self.best >= 0) & ~usable[np.maximum(self.best, 0)]
        if dropped.any():
            self._update(np.unique(np.flatnonzero(dropped) // 2), usable)
        group = np.flatnonzero(self.best >= 0)
        return group, self.best[group]

    def owner(self, group):
        """The point of each group."""
        return group // 2

    def drop(self, points, centres, bound, group, witness, usable):
        """:func:`_drop_containing` in the groups ``group``."""
        points, normals, _, *rest = self.entry
        self.kernel.drop_containing(
            points,
            normals,
            centres,
            bound,
            *rest,
            self.start,
            self.members,
            np.ascontiguousarray(group, dtype=np.int64),
            np.ascontiguousarray(witness, dtype=np.int64),
            usable,
        )


def _compiled_tet_pass(kernel, points, moved, tets, neighbours, jitter, noise):
    """(centres, bound, usable) of every tetrahedron, as the numpy path of
    :func:`vertex_poles` computes them, in chunks of TET_CHUNK on the library's threads;
    ``noise`` 0 leaves out the reliability test."""
    count = len(tets)
    points = np.ascontiguousarray(points, dtype=float)
    centres = np.empty((count, 3))
    bound = np.empty(count)
    usable = np.empty(count, dtype=bool)

    def chunk_centres(corners_of, lo, hi):
        origin, edges = np.empty((hi - lo, 3)), np.empty((hi - lo, 3, 3))
        squared, longest = np.empty((hi - lo, 3)), np.empty(hi - lo)
        kernel.tet_edges(corners_of, tets, lo, hi, origin, edges, squared, longest)
        return _centres_from_edges(origin, edges, squared, longest)

    def task(bounds):
        lo, hi = bounds
        centres[lo:hi] = chunk_centres(points, lo, hi)
        shift = np.zeros(0)
        if noise > 0:
            shifted = chunk_centres(np.ascontiguousarray(moved, dtype=float), lo, hi)
            shift = np.linalg.norm(shifted - centres[lo:hi], axis=1)
        kernel.tet_bounds(
            points,
            tets,
            neighbours,
            centres,
            jitter,
            lo,
            hi,
            shift,
            float(noise),
            1 - EMPTY_RTOL,
            float(EMPTY_ATOL),
            UNRELIABLE_RTOL,
            bound,
            usable,
        )

    run_in_threads(task, chunk_bounds(count, TET_CHUNK))
    return centres, bound, usable


def _pole_candidates(points, normals, tets, centres, usable, unbounded, labels=None, adjacent=None):
    """Every (point, side of its normal line, usable tetrahedron of the point) except on the
    point's unbounded side and, with labels, except tetrahedra with a corner on a patch
    adjacent to the point's, sorted by point, side and distance to the circumcentre.

    Returns the tetrahedron of each entry, the index where each (point, side) group starts,
    and the point of each entry.
    """
    vertex = tets[usable].reshape(-1)
    tet = np.repeat(np.flatnonzero(usable), 4)
    offset = centres[tet] - points[vertex]
    side = (offset * normals[vertex]).sum(axis=1) > 0
    keep = unbounded[vertex] != np.where(side, 1, -1)
    if labels is not None and adjacent is not None and adjacent.any():
        corner_labels = labels[tets[tet]]  # (entries, 4)
        keep &= ~adjacent[labels[vertex][:, None], corner_labels].any(axis=1)
    vertex, tet, side, offset = vertex[keep], tet[keep], side[keep], offset[keep]
    # One key for (point, side): the same order as sorting by point, then side (a sort less).
    group = 2 * vertex + side
    order = np.lexsort((np.linalg.norm(offset, axis=1), group))
    group = group[order]
    starts = np.flatnonzero(np.r_[True, group[1:] != group[:-1]]) if len(group) else group
    return tet[order], starts, vertex[order]


def _farthest(candidates: np.ndarray, starts: np.ndarray, usable: np.ndarray) -> np.ndarray:
    """Per group, the position (in ``candidates``) of its farthest usable circumcentre; −1 where
    none is usable."""
    if len(candidates) == 0:
        return np.zeros(0, dtype=np.int64)
    position = np.where(usable[candidates], np.arange(len(candidates)), -1)
    return np.maximum.reduceat(position, starts)


def _drop_containing(points, centres, bound, candidates, first, last, witness, usable) -> None:
    """Mark unusable every candidate in ``candidates[first[k]:last[k]]`` whose ball contains the
    sample ``witness[k]``: a nearly degenerate point set yields many such circumcentres along
    one line, and dropping them one per round would take as many rounds."""
    sizes = last - first
    owner = np.repeat(np.arange(len(sizes)), sizes)
    tet = candidates[
        first[owner] + np.arange(sizes.sum()) - np.repeat(np.cumsum(sizes) - sizes, sizes)
    ]
    gap = np.linalg.norm(points[witness[owner]] - centres[tet], axis=1)
    usable[tet[gap < bound[tet]]] = False


def _circumcentres(corners: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Circumcentres of tetrahedra (t, 4, 3) and the largest distance from each to its corners;
    NaN for tetrahedra too flat to have a reliable circumcentre (:func:`_centres_from_edges`).
    """
    origin = corners[:, 0]
    edges = corners[:, 1:] - origin[:, None]
    squared = (edges * edges).sum(axis=2)
    longest = np.sqrt(squared.max(axis=1))
    centres = _centres_from_edges(origin, edges, squared, longest)
    radii = np.linalg.norm(centres[:, None] - corners, axis=2).max(axis=1)
    return centres, radii


def _centres_from_edges(origin, edges, squared, longest) -> np.ndarray:
    """Circumcentres of tetrahedra given by a corner (t, 3), the edges from it (t, 3, 3), their
    squared lengths (t, 3) and the longest (t); NaN for flat ones.

    Four points spread over a length l on a sphere of radius r span a tetrahedron of thickness
    about l²/r. One far flatter than that has four nearly cocircular corners, and its
    circumcentre moves along the axis of their circle under any rounding of the corners.
    """
    det = np.linalg.det(edges)
    solid = np.abs(det) > FLAT_RTOL * longest**3
    centres = np.full(origin.shape, np.nan)
    centres[solid] = (
        origin[solid] + np.linalg.solve(edges[solid], 0.5 * squared[solid][..., None])[..., 0]
    )
    return centres


def _locally_empty(points, tets, neighbours, centres, bound) -> np.ndarray:
    """False where a neighbouring tetrahedron's far vertex lies inside the circumscribed ball
    (unmoved points): closer to the centre than ``bound``."""
    ok = np.ones(len(tets), dtype=bool)
    for face in range(4):
        other = neighbours[:, face]
        has = other >= 0
        their = tets[np.where(has, other, 0)]
        outside_ours = ~(their[:, :, None] == tets[:, None, :]).any(axis=2)
        far_vertex = their[np.arange(len(tets)), outside_ours.argmax(axis=1)]
        gap = np.linalg.norm(points[far_vertex] - centres, axis=1)
        with np.errstate(invalid="ignore"):
            ok &= ~has | (gap >= bound)
    return ok


def _unbounded_side(points, normals, tets, neighbours) -> np.ndarray:
    """Per point: +1 or −1, the side of its normal where its Voronoi cell is unbounded (points
    on the convex hull), 0 for interior points."""
    tet, face = np.nonzero(neighbours < 0)
    corners = np.stack([tets[tet, (face + k) % 4] for k in (1, 2, 3)], axis=1)
    p = points[corners]
    outward = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    inward = points[tets[tet, face]] - p[:, 0]
    outward *= np.where((outward * inward).sum(axis=1) > 0, -1.0, 1.0)[:, None]
    total = np.zeros_like(points)
    for k in range(3):
        np.add.at(total, corners[:, k], outward)
    side = np.sign((total * normals).sum(axis=1)).astype(int)
    on_hull = np.zeros(len(points), dtype=bool)
    on_hull[corners.reshape(-1)] = True
    return np.where(on_hull, np.where(side == 0, 1, side), 0)
