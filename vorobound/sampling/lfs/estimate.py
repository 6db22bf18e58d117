"""Local feature size L of the piecewise-smooth surface a triangle mesh describes (docs/lfs.md).

The mesh is split into smooth patches at its sharp features (:mod:`.patches`). L is the
largest λ-Lipschitz function (λ ≤ 1) below three terms, each evaluated at *sites*: the mesh
vertices, points spread inside the faces at a spacing adapted to L (:mod:`.face_sites`; so a
coarse and a fine triangulation of one part give the same L), and points on the feature edges.

* **Medial term** (estimator A): the distance to the Voronoi poles (:mod:`.medial`) of a
  sample of the curved patches (vertices, fitted edge midpoints, face sites), counting only
  medial balls that touch no two adjacent patches (those are created by a sharp feature).
* **Thickness and curvature** (estimator B, :mod:`.thickness`): half the distance along the
  normal to the surface inward (any face: the part's thickness) and outward (faces of the same
  or non-adjacent patches), and the radius of curvature of the patch from its vertex normals.
  Each bounds the medial-ball radius from above, so B is an upper bound on L at a face site.
* **Features**: a point of a feature curve gets L_F = min(the curve's radius of curvature,
  half the distance to non-adjacent curves), and every site x gets min over feature points p
  of max(|x − p|, L_F(p)): L may not exceed a feature's own size before the distance to it.

Then L(x) = min over sites y of raw(y) + λ|x − y| everywhere (:mod:`.lipschitz`): the same
λ-Lipschitz function in the vertex output, in ``LfsEstimate.at`` (the sampler's L) and in the
integrals of the advisor. Sites are refined until the spacing is at most SITE_SPACING·L.

On a closed smooth mesh without sharp features this is the distance to the poles of the
vertices and fitted edge midpoints, as before (the face sites of a fine mesh are not split and
do not enter the pole sample), capped by the thickness and curvature bound.

The estimate is split by concern: the sites and their spacing (:mod:`.sites`), the feature
terms (:mod:`.features`), the fitted midpoints and poles (:mod:`.poles`), the rounds
(:mod:`.rounds`) and the result with its warnings (:mod:`.result`). It is cached on the mesh
object (:meth:`vorobound.mesh.TriangleMesh.cached`) with the options it was made with: a
command given the same mesh object again reuses it.
"""

from __future__ import annotations

import numpy as np

from ...checks import LIPSCHITZ_RANGE, checked_number, checked_seed
from ...errors import InputError, warn_once
from ...mesh import TriangleMesh, fingerprint
from ...progress import Counter, Progress
from .face_sites import face_curvature_radius
from .mesh_quality import prepare_mesh, vertex_normals
from .patches import find_patches
from .poles import AUTO_SAMPLES, fitted_midpoints, labelled_poles, rounding_error
from .result import LfsEstimate, build_result
from .rounds import _last_balls, _tangent_balls, round_state, run_rounds
from .sites import Sites
from .thickness import RayCaster

__all__ = [
    "AUTO_SAMPLES",
    "SHARP_ANGLE",
    "LfsEstimate",
    "Sites",
    "checked_lfs_options",
    "estimate_lfs",
    "_last_balls",
    "_tangent_balls",
]

SHARP_ANGLE = 30.0
"""Default threshold (degrees) on the angle between the normals of two adjacent faces above
which their edge is sharp (VTK's and ParaView's default feature angle)."""

FLAT_RTOL = 1e-9
"""Vertices whose spread across their best plane is below FLAT_RTOL times their extent are
coplanar."""


def _refuse_non_manifold(prepared, name: str) -> None:
    """Refuse a surface whose parts touch at a vertex or meet along an edge of three or more
    faces: L there is 0 (any ball around such a point meets two sheets), which no positive
    estimate can stand for (issue 34: L at a pinch was the largest on the mesh, L along a fin's
    edge that of the sphere it stands on)."""

    def at(vertex) -> str:
        where = prepared.centre + prepared.scale * prepared.points[vertex]
        return "(" + ", ".join(f"{value:.6g}" for value in where) + ")"

    report = prepared.report
    if len(report.pinched_vertices):
        raise InputError(
            f"mesh {name}: {len(report.pinched_vertices)} vertices where parts of the surface "
            f"touch at a point (non-manifold; the first at {at(report.pinched_vertices[0])}): "
            "the local feature size there is 0; move the parts apart or join them along faces"
        )
    edges = report.nonmanifold_edge_vertices
    if len(edges):
        raise InputError(
            f"mesh {name}: {len(edges)} edges shared by more than two faces (non-manifold; the "
            f"first from {at(edges[0, 0])} to {at(edges[0, 1])}): the local feature size along "
            "them is 0; remove the extra faces or move the parts apart"
        )


def checked_lfs_options(samples, lipschitz, sharp_angle, seed) -> tuple[float, int]:
    """Refuse bad options of :func:`estimate_lfs` (before a mesh is read); the λ and seed as
    plain numbers."""
    if samples is not None and (
        isinstance(samples, bool) or not isinstance(samples, int | np.integer) or samples < 0
    ):
        raise InputError(f"--samples must be a whole number ≥ 0, got {samples!r}")
    lipschitz = checked_number(lipschitz, "lipschitz", *LIPSCHITZ_RANGE)
    angle = checked_number(sharp_angle, "sharp_angle", 0.0, 180.0, open_low=True)
    if angle == 180.0:
        raise InputError(f"sharp_angle must be between 0 and 180 degrees, got {sharp_angle}")
    return lipschitz, checked_seed(seed)


def estimate_lfs(
    mesh: TriangleMesh,
    *,
    samples: int | None = None,
    lipschitz: float = 1.0,
    sharp_angle: float = SHARP_ANGLE,
    seed: int = 0,
    progress: Progress | None = None,
) -> LfsEstimate:
    """Estimate the local feature size of the surface of a triangle mesh (module docstring).

    Parameters
    ----------
    mesh : TriangleMesh
        The surface; a closed mesh, vertices on the surface it describes.
    samples : int, optional
        Size N ≥ 0 of the vertex part of the pole sample: the vertices plus up to
        N − (vertices) edge midpoints on a quartic fit (smooth patches only). 0: no midpoints.
        None: every eligible edge if that makes at most AUTO_SAMPLES points, else none.
    lipschitz : float
        λ > 0; the result is min(λ, 1)-Lipschitz.
    sharp_angle : float
        Edges whose adjacent face normals differ by more than this (degrees) are sharp.
    seed : int
        Seed of the triangulation's jitter.
    progress : Progress, optional
        Progress callback.

    Raises
    ------
    InputError
        Empty or invalid mesh, NaN coordinates, coplanar vertices, bad parameters.

    References
    ----------
    Local feature size and ε-samples as in Section 4.1 of "Analytic formula for the difference
    of the circumradius and orthoradius of a weighted triangle"; poles from Amenta & Bern (1999).
    """
    lipschitz, seed = checked_lfs_options(samples, lipschitz, sharp_angle, seed)
    options = (None if samples is None else int(samples), lipschitz, float(sharp_angle), seed)

    def compute() -> LfsEstimate:
        return _estimate(mesh, *options, progress)

    cached = getattr(mesh, "cached", None)
    estimate = compute() if cached is None else cached(("lfs estimate", options), compute)
    subject = fingerprint(mesh.points, mesh.triangles)
    for note in estimate.warnings:  # once per mesh and process (as when it is computed again)
        warn_once(f"mesh {mesh.name}: {note}", subject)
    return estimate


def _estimate(
    mesh: TriangleMesh,
    samples: int | None,
    lipschitz: float,
    sharp_angle: float,
    seed: int,
    progress: Progress | None,
) -> LfsEstimate:
    """:func:`estimate_lfs` with checked options, not cached."""
    slope = float(min(lipschitz, 1.0))
    prepared = prepare_mesh(mesh)
    _refuse_non_manifold(prepared, mesh.name)
    points, faces = prepared.points, prepared.triangles
    surface_ids = np.unique(faces)
    if len(surface_ids) < 5:
        raise InputError(f"mesh {mesh.name}: need at least 5 vertices on faces with area")
    _refuse_flat(points[surface_ids], mesh.name)
    counter = Counter(progress, "surface structure", 1)
    patches = find_patches(prepared, sharp_angle)
    radius_face = face_curvature_radius(points, faces, patches.corner_normals)
    vertex_patch = prepared.mesh.vertex_labels(patches.face_patch)
    caster = RayCaster(points, faces)
    counter.step()
    vertex_sites = surface_ids[~patches.feature_vertex[surface_ids]]
    counter = Counter(progress, "fitted midpoints", 1)
    normals = vertex_normals(prepared)
    midpoints = fitted_midpoints(
        prepared, patches, samples, len(surface_ids), normals, vertex_patch
    )
    counter.step()
    # The pole sample (vertices and fitted midpoints of curved patches) is the same in every
    # round: its poles are found once.
    poles = labelled_poles(
        prepared,
        patches,
        midpoints,
        sites=(vertex_sites, vertex_patch, normals),
        seed=seed,
        noise=rounding_error(mesh.points) / prepared.scale,
        caster=caster,
        progress=progress,
    )
    state = round_state(
        prepared,
        patches,
        slope=slope,
        caster=caster,
        surface_ids=surface_ids,
        vertex_sites=vertex_sites,
        vertex_patch=vertex_patch,
        poles=poles,
        radius_face=radius_face,
        normals=normals,
    )
    rounds = run_rounds(state, progress)
    Counter(progress, "result", 1)
    return build_result(mesh, prepared, patches, midpoints, sharp_angle, slope, rounds)


def _refuse_flat(points: np.ndarray, name: str) -> None:
    """A surface in one plane has no medial axis (L is unbounded): refuse it."""
    spread = np.linalg.eigvalsh(np.cov(points.T))
    if spread[0] <= FLAT_RTOL**2 * spread[-1]:
        raise InputError(
            f"mesh {name}: the vertices are (nearly) coplanar: a flat surface has no finite "
            "local feature size"
        )
