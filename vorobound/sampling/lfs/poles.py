"""The medial term of the estimate of L (:mod:`.estimate`): fitted edge midpoints on the
curved patches, the Voronoi poles of them and the vertices (labelled by their patch, checked
empty of the mesh), and the distance from a site to the nearest pole that its patch allows.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...errors import InputError
from ...geometry.threads import thread_count
from ...mesh.nearest import nearest_allowed
from ...progress import Counter, Progress
from .curved import edge_midpoints
from .medial import compiled_poles, vertex_poles
from .mesh_quality import PreparedMesh
from .patches import Patches
from .thickness import RayCaster

AUTO_SAMPLES = 60_000
"""Without a sample size, every eligible edge of a smooth patch gets a fitted midpoint if the
vertices and midpoints then number at most AUTO_SAMPLES, and none otherwise."""

NEAREST_POLES = (8, 32, 128)
"""Numbers of nearest poles tried, in turn, for one of an allowed patch."""

POLE_EMPTY_RTOL = 0.05
"""A pole is dropped when the mesh comes closer to it than (1 − POLE_EMPTY_RTOL) times the
distance to the nearest sample point (on a patch the owner's contact is not ignored on)."""


@dataclass(frozen=True)
class Midpoints:
    points: np.ndarray
    normals: np.ndarray
    labels: np.ndarray
    eligible: int


def fitted_midpoints(
    prepared, patches: Patches, samples, vertices: int, normals, vertex_patch
) -> Midpoints:
    """Fitted edge midpoints on the smooth patches, as in the pole estimator of docs/lfs.md."""
    excluded = np.zeros(len(prepared.edges), dtype=bool)
    feature_keys = {tuple(e) for e in np.sort(patches.feature_edges, axis=1).tolist()}
    if feature_keys:
        excluded = np.array([tuple(e) in feature_keys for e in prepared.edges.tolist()])
    budget = (
        int(samples) - vertices
        if samples is not None
        else (len(prepared.edges) if vertices + len(prepared.edges) <= AUTO_SAMPLES else 0)
    )
    added = edge_midpoints(prepared, normals, excluded, budget)
    labels = vertex_patch[added.edges[:, 0]] if len(added.points) else np.zeros(0, np.int64)
    curved = ~patches.flat[labels] if len(labels) else np.zeros(0, dtype=bool)
    # Flat patches need no poles (their thickness bound is exact).
    return Midpoints(added.points[curved], added.normals[curved], labels[curved], added.eligible)


def labelled_poles(
    prepared: PreparedMesh,
    patches: Patches,
    midpoints: Midpoints,
    *,
    sites: tuple[np.ndarray, np.ndarray, np.ndarray],
    seed: int,
    noise: float,
    caster: RayCaster,
    progress: Progress | None,
) -> tuple[np.ndarray, np.ndarray] | None:
    """(pole positions, owner patch) from the vertices of curved patches and the fitted
    midpoints, or None when there are too few points.

    Points interpolated inside coarse faces are not used: PN patches meet with small creases,
    whose spurious poles would shrink L (docs/lfs.md). ``sites``: the vertex sites, a patch
    of each vertex and the vertex normals; ``noise``: the rounding error of the coordinates.
    """
    vertex_sites, vertex_patch, normals = sites
    curved_vertex = vertex_sites[~patches.flat[vertex_patch[vertex_sites]]]
    pole_points = np.vstack([prepared.points[curved_vertex], midpoints.points])
    if len(pole_points) < 5:
        return None
    pole_normals = np.vstack([normals[curved_vertex], midpoints.normals])
    labels = np.concatenate([vertex_patch[curved_vertex], midpoints.labels]).astype(np.int64)
    try:
        poles = vertex_poles(
            pole_points,
            pole_normals,
            noise=noise,
            seed=seed,
            progress=progress,
            labels=labels,
            adjacent=patches.adjacent,
        )
    except InputError:
        return None  # a nearly planar sample of curved patches: no medial points
    labelled, owners = poles.labelled_points, poles.owner_labels
    if labelled is None or owners is None or not len(owners):
        return None
    counter = Counter(progress, "pole check", 1)
    checked = _checked_poles(labelled, owners, pole_points, caster, patches, poles.labelled_reach)
    counter.step()
    return checked


def _checked_poles(centres, owners, sample, caster, patches, reach=None):
    """Keep the poles whose ball is empty of the mesh itself, not only of the sample: the
    surface may come no closer to the centre than POLE_EMPTY_RTOL short of the distance to
    the nearest sample point, unless it does so on a patch adjacent to the owner's (those
    contacts are left out by definition). A sample of some patches alone (the curved ones)
    leaves cells unbounded toward the others; their far Voronoi vertices are not medial.

    ``reach``, an upper bound on each pole's distance to the sample (the nearest corner of its
    tetrahedron), makes the check cheaper and changes no decision: the nearest face is searched
    within (1 − POLE_EMPTY_RTOL)·reach, at least the bound of the exact distance, so a pole
    with no face found there passes as it would with the exact one, and a found face is the
    mesh's nearest. The exact distance to the sample, a k-d tree query that on a torus's core
    circle measures every vertex of the tube's ring (issue 35: 7 of the 11 CPU-s of this
    check on a 65 536-vertex torus, and growing faster than the vertices), is then needed only
    for the poles with such a face."""
    from scipy.spatial import cKDTree

    if reach is None:
        reach = cKDTree(sample).query(centres, workers=thread_count())[0]
    # Only faces nearer than the bound matter (the nearest of them is the mesh's nearest), so
    # the search stays inside each pole's ball: a pole equally far from many faces (the centre
    # of a sphere, the core circle of a torus) costs nothing.
    distance, face = caster.nearer_than(centres, (1 - POLE_EMPTY_RTOL) * reach)
    near = np.flatnonzero(face >= 0)
    radius = np.array(reach, dtype=float)
    if len(near):
        radius[near] = cKDTree(sample).query(centres[near], workers=thread_count())[0]
    bound = (1 - POLE_EMPTY_RTOL) * radius
    inside = (face >= 0) & (distance < bound)
    across = np.zeros(len(centres), dtype=bool)
    across[inside] = patches.adjacent[owners[inside], patches.face_patch[face[inside]]]
    keep = ~inside | across
    if not keep.any():
        return None
    return centres[keep], owners[keep]


def nearest_allowed_pole(pole_points, pole_labels, queries, query_labels, allowed) -> np.ndarray:
    """Distance from each query to the nearest pole whose label is allowed for the query's.

    With numba, one walk of a box tree along the poles (:mod:`.compiled_poles`); without it,
    a k-d tree: among the NEAREST_POLES nearest, else the nearest of the poles its label
    allows. Both give the exact minimum, with the same arithmetic (tested equal): the compiled
    walk only visits fewer poles where thousands lie at nearly one distance (a medial axis
    that is a curve)."""
    from scipy.spatial import cKDTree

    compiled = compiled_poles()
    if compiled is not None:
        tree = compiled.PoleTree(pole_points, pole_labels)
        return tree.nearest_allowed(queries, query_labels, allowed)[0]

    def ok(rows, index):
        return allowed[query_labels[rows][:, None], pole_labels[index]]

    out, index = nearest_allowed(cKDTree(pole_points), queries, ok, NEAREST_POLES)
    todo = np.flatnonzero(index < 0)
    if len(todo):
        for label in np.unique(query_labels[todo]):
            mine = todo[query_labels[todo] == label]
            keep = allowed[label, pole_labels]
            if keep.any():
                tree = cKDTree(pole_points[keep])
                out[mine] = tree.query(queries[mine], workers=thread_count())[0]
    return out


def rounding_error(points: np.ndarray) -> float:
    """The rounding error of the coordinates: single precision if every coordinate is a float32
    (as in STL files), else double."""
    points = np.asarray(points, dtype=float)
    with np.errstate(over="ignore", invalid="ignore"):
        single = np.array_equal(points.astype(np.float32).astype(float), points)
    return float(np.abs(points).max()) * float(np.finfo(np.float32 if single else float).eps)
