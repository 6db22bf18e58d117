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
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from ...checks import LIPSCHITZ_RANGE, checked_number, checked_seed
from ...errors import InputError, VoroboundError, warn_once
from ...geometry.threads import thread_count
from ...mesh import TriangleMesh, fingerprint
from ...progress import Counter, Progress
from ..surfaces.base import SurfaceCounts
from .curved import edge_midpoints, tangent_basis
from .face_sites import edge_sites, face_curvature_radius, face_sites, pn_points
from .lipschitz import DistanceCap, Envelope
from .medial import vertex_poles
from .memo import RoundMemo, site_keys
from .mesh_quality import MeshReport, prepare_mesh, vertex_normals
from .patches import Patches, find_patches
from .tangent_ball import TangentBalls
from .thickness import RayCaster, Thickness, thickness

SHARP_ANGLE = 30.0
"""Default threshold (degrees) on the angle between the normals of two adjacent faces above
which their edge is sharp (VTK's and ParaView's default feature angle)."""
COARSE_EDGE_RATIO = 0.5
"""An edge of a curved patch longer than COARSE_EDGE_RATIO·L is reported as coarse: the
curvature and poles there rest on interpolated normals (docs/lfs.md)."""
FLAT_RTOL = 1e-9
"""Vertices whose spread across their best plane is below FLAT_RTOL times their extent are
coplanar."""
AUTO_SAMPLES = 60_000
"""Without a sample size, every eligible edge of a smooth patch gets a fitted midpoint if the
vertices and midpoints then number at most AUTO_SAMPLES, and none otherwise."""
SITE_SPACING = {"curved": 0.5, "flat": 1.0}
"""Face sites are refined until no piece is longer than this times L at its centroid: on
curved patches the poles and the curvature need the denser sample, on flat ones the thickness
bound is exact at any spacing."""
FIRST_SPACING = 1 / 25
"""Spacing of the first round of face sites, relative to the part's diagonal."""
SLOPE_NEIGHBOURS = 12
"""Nearest sites over which a site's local rate of change of L is taken."""
FIT_NEIGHBOURS = 24
"""Nearest sites among which a face site's gradient is fitted (those of its own patch)."""
PLANE_MIN_RATE = 1e-3
"""Face sites where L changes at less than this times λ keep a flat value (no fitted plane)."""
FIT_SPREAD = 1e-4
"""The fitted neighbours must spread in two directions: det/trace² of their second moments in
the tangent plane above this (0.25 for an even spread, 0 on a line)."""
GRADIENT_BLOCK = 1 << 16
"""Sites whose gradients are fitted together (bounds the temporaries to about 0.1 GB)."""
ROUNDS = 4
"""Most refinement rounds of the face sites."""
STABLE_RTOL = 0.02
"""Refinement stops when L at every vertex changed by less than this in the last round."""
DISAGREE_RATIO = 2.0
"""The medial estimate above DISAGREE_RATIO times the thickness and curvature bound at more
than DISAGREE_SHARE of the face sites is reported (L uses the bound there)."""
DISAGREE_SHARE = 0.01
NEAREST_POLES = (8, 32, 128)
RAY_NEAR = 0.25
"""Ray hits closer than this times the local mesh spacing are the next faces of a bumpy mesh."""
MIN_PIECES = 32
"""No piece is made shorter than its face's longest edge over MIN_PIECES: where L from the
vertex normals is far below the mesh spacing (an edge just below the sharp angle), the mesh
does not resolve it anyway."""
COARSE_POLE_RATIO = 0.8
"""Where the local mesh edge exceeds this times the medial estimate, the poles along the
medial axis are as sparse as the vertices and overestimate L (an L-bracket's bore with rings
0.9·L apart: 0.93 for 0.6); the curvature radius then caps it too. Below it the vertex-normal
curvature is left out: on irregular meshes it is noisy (a jittered torus: 0.25 for 0.5)."""
BOUND_TOLERANCE = 0.0
"""Where the poles give L, half the thickness lowers it only when it is smaller by more than
this share (ray hits on curved patches are lifted to the smooth PN surface, good to about this
on the test meshes); the curvature from vertex normals is left to the poles there."""
POLE_EMPTY_RTOL = 0.05
"""A pole is dropped when the mesh comes closer to it than (1 − POLE_EMPTY_RTOL) times the
distance to the nearest sample point (on a patch the owner's contact is not ignored on)."""
"""Numbers of nearest poles tried, in turn, for one of an allowed patch."""


@dataclass(frozen=True)
class Sites:
    """The points where the terms of L are evaluated (docs/lfs.md), in the mesh's units."""

    points: np.ndarray
    raw: np.ndarray
    """min of the terms at each site, before the Lipschitz envelope."""
    lfs: np.ndarray
    """L at each site (the envelope)."""
    kind: np.ndarray
    """0 vertex, 1 face site, 2 feature site."""
    areas: np.ndarray
    """Area each face site stands for (0 for the others); the face sites tile the surface."""
    medial: np.ndarray
    """Estimator A at each site (inf where no allowed pole)."""
    bound: np.ndarray
    """Estimator B at each face site (inf elsewhere)."""
    thickness: np.ndarray
    """T_in at each face site: distance across the part along the inward normal."""
    radii: np.ndarray
    """Radius of the piece of surface each site stands for (0 for vertices)."""
    values: np.ndarray
    """The value :meth:`LfsEstimate.at` spreads flat over the site's ball (its L)."""
    vertex: np.ndarray
    """The mesh vertex a site is (index into the prepared mesh), −1 for the other sites."""
    gradient: np.ndarray
    """Local rate of change of L at each site (largest over its nearest sites, at most λ)."""
    planes: np.ndarray
    """(n, 3) gradient of L fitted at each face site to the nearest sites of its patch (at
    most λ long; zero at the other sites and where no fit was possible)."""


@dataclass(frozen=True)
class LfsEstimate:
    """Estimated local feature size of a mesh's surface: at its vertices, and anywhere via
    :meth:`at` (the same λ-Lipschitz function)."""

    mesh: TriangleMesh
    lfs: np.ndarray
    """L at each vertex of ``mesh`` (in its order)."""
    lipschitz: float
    """λ: |L(x) − L(y)| ≤ λ|x − y| for all points (at most 1)."""
    medial_points: np.ndarray
    """The estimated medial axis: distinct Voronoi poles (k, 3)."""
    sample_count: int
    """Size of the pole sample: vertices of curved patches, fitted midpoints and face sites."""
    added_samples: int
    """Edge midpoints on the fitted surface in the pole sample."""
    eligible_edges: int
    """Edges that could get a fitted midpoint; 0 when the sample size asked for none."""
    sharp_edges: np.ndarray
    """Vertex index pairs (e, 2) of the edges sharper than ``sharp_angle``."""
    sharp_angle: float
    max_dihedral: float
    """Largest angle (degrees) between the normals of adjacent faces."""
    mesh_report: MeshReport
    warnings: tuple[str, ...]
    method: str
    patches: int = 0
    """Smooth patches the sharp features split the surface into."""
    feature_edges: int = 0
    """Edges on feature curves (sharp, boundary or non-manifold)."""
    feature_segments: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), np.int64))
    """(e, 2) input vertex pairs of the feature edges."""
    feature_corners: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    """Input vertex indices of the corners (where feature curves end or meet)."""
    feature_length: float = 0.0
    """Total length of the feature curves."""
    feature_inv_lfs: float = 0.0
    """∫ ds / L along the feature curves (sets the number of feature balls)."""
    rounds: int = 0
    disagreement: dict = field(default_factory=dict)
    """Where the medial estimate exceeds the thickness bound (share of face sites, worst ratio
    and its position)."""
    sites: Sites | None = field(default=None, repr=False)

    def at(self, points) -> np.ndarray:
        """L at arbitrary points (m, 3): min over sites y of v(y) + λ·max(0, |x − y| − ρ(y)),
        v the site's value and ρ its piece's radius (docs/lfs.md)."""
        points = np.asarray(points, dtype=float)
        if points.ndim != 2 or points.shape[1] != 3 or not np.isfinite(points).all():
            raise InputError(f"need finite points of shape (m, 3), got shape {points.shape}")
        return self._field(points)

    @cached_property
    def _field(self) -> Envelope:
        s = self.sites
        return Envelope(s.points, s.values, self.lipschitz, s.radii, gradients=s.planes)

    def surface(self) -> SurfaceCounts:
        """Area and ∫ dA/L² from the face sites (:class:`SurfaceCounts`, what the advice
        needs)."""
        face = self.sites.kind == 1
        areas, lfs = self.sites.areas[face], self.sites.lfs[face]
        with np.errstate(all="ignore"):
            area = float(areas.sum())
            integral = float((areas / lfs**2).sum())
        if not (math.isfinite(area) and area > 0 and math.isfinite(integral)):
            raise InputError(f"mesh {self.mesh.name}: its faces have no (finite) area")
        return SurfaceCounts(
            f"mesh {self.mesh.name}",
            area,
            integral,
            float(lfs.min()),
            False,
            feature_inv_lfs=self.feature_inv_lfs,
            mesh_lattice=True,
        )

    @cached_property
    def vertex_sharp(self) -> np.ndarray:
        sharp = np.zeros(len(self.mesh.points), dtype=bool)
        sharp[self.sharp_edges.reshape(-1)] = True
        return sharp


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
    curved_face = ~patches.flat[patches.face_patch]
    radius_face = face_curvature_radius(points, faces, patches.corner_normals)
    vertex_patch = np.full(len(points), -1)
    vertex_patch[faces.reshape(-1)] = np.repeat(patches.face_patch, 3)
    caster = RayCaster(points, faces)
    allowed = ~patches.adjacent
    counter.step()
    vertex_sites = surface_ids[~patches.feature_vertex[surface_ids]]
    counter = Counter(progress, "fitted midpoints", 1)
    normals = vertex_normals(prepared)
    midpoints = _midpoints(prepared, patches, samples, len(surface_ids), normals)
    counter.step()
    factor = np.where(curved_face, SITE_SPACING["curved"], SITE_SPACING["flat"])
    corners = points[faces]
    face_floor = np.linalg.norm(corners - np.roll(corners, -1, axis=1), axis=2).max(axis=1)
    face_floor = face_floor / MIN_PIECES
    ends = points[patches.feature_edges]
    edge_floor = np.linalg.norm(ends[:, 1] - ends[:, 0], axis=1) / MIN_PIECES
    # The pole sample (vertices and fitted midpoints of curved patches) is the same in every
    # round: its poles are found once.
    labelled = _labelled_poles(
        prepared,
        patches,
        vertex_sites,
        vertex_patch,
        midpoints,
        normals,
        seed,
        mesh.points,
        progress,
        caster,
    )
    fixed = _fixed(prepared, patches, vertex_sites, radius_face, allowed, normals)
    sites = poles = field = None
    previous = None
    rounds = 0
    for done in range(1, ROUNDS + 1):
        rounds = done
        if sites is None:

            def face_spacing(x, face):
                return np.full(len(x), FIRST_SPACING)

            def edge_spacing(x, edge):
                return np.full(len(x), FIRST_SPACING)

        else:
            face_spacing, edge_spacing = _spacings(field, factor, face_floor, edge_floor)
        counter = Counter(progress, "face sites", 1)
        on_faces = face_sites(points, faces, patches.corner_normals, curved_face, face_spacing)
        feature = edge_sites(points, patches.feature_edges, edge_spacing)
        counter.step()
        sites, poles, envelope = _evaluate(
            prepared,
            patches,
            caster,
            allowed,
            vertex_sites,
            vertex_patch,
            labelled,
            on_faces,
            feature,
            radius_face,
            curved_face,
            slope,
            progress,
            fixed,
        )
        counter = Counter(progress, "L at the vertices", 1)
        field = Envelope(
            sites.points, sites.values, slope, sites.radii, like=envelope, gradients=sites.planes
        )
        at_vertices = field(points)
        counter.step()
        current = at_vertices[surface_ids]
        if previous is not None and np.all(np.abs(current - previous) <= STABLE_RTOL * previous):
            break
        previous = current
    Counter(progress, "result", 1)
    return _result(
        mesh,
        prepared,
        patches,
        sites,
        poles,
        midpoints,
        slope,
        sharp_angle,
        rounds,
        field,
        at_vertices,
    )


def _spacings(field: Envelope, factor: np.ndarray, face_floor, edge_floor):
    """The next round's spacing: SITE_SPACING (per face) times L of the last round, at least
    the floors (:data:`MIN_PIECES`)."""

    def face_spacing(x, face):
        return np.maximum(factor[face] * field(x), face_floor[face])

    def edge_spacing(x, edge):
        return np.maximum(SITE_SPACING["curved"] * field(x), edge_floor[edge])

    return face_spacing, edge_spacing


@dataclass(frozen=True)
class _Midpoints:
    points: np.ndarray
    normals: np.ndarray
    labels: np.ndarray
    eligible: int


def _midpoints(prepared, patches: Patches, samples, vertices: int, normals) -> _Midpoints:
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
    vertex_patch = np.full(len(prepared.points), -1)
    vertex_patch[prepared.triangles.reshape(-1)] = np.repeat(patches.face_patch, 3)
    labels = vertex_patch[added.edges[:, 0]] if len(added.points) else np.zeros(0, np.int64)
    curved = ~patches.flat[labels] if len(labels) else np.zeros(0, dtype=bool)
    # Flat patches need no poles (their thickness bound is exact).
    return _Midpoints(added.points[curved], added.normals[curved], labels[curved], added.eligible)


def _evaluate(
    prepared,
    patches,
    caster,
    allowed,
    vertex_sites,
    vertex_patch,
    labelled,
    on_faces,
    feature,
    radius_face,
    curved_face,
    slope,
    progress,
    fixed: _Fixed,
):
    """One round: estimators A and B, the feature terms and the envelope at every site; the
    sites, the pole positions and the envelope of the raw values (whose tree lends its shape to
    the round's field).

    Sites, in this order: the vertices inside smooth patches, the face sites, the feature
    vertices, the points on feature edges. Values that depend on a site alone are taken over
    from the last round where the site is the same (:mod:`.memo`).
    """
    points, faces = prepared.points, prepared.triangles
    face_patch = patches.face_patch
    normals = fixed.normals
    poles = labelled
    feature_vertices = fixed.feature_vertices
    groups = [
        (points[vertex_sites], 0, vertex_patch[vertex_sites][:, None]),
        (on_faces.points, 1, face_patch[on_faces.face][:, None]),
        (points[feature_vertices], 2, fixed.vertex_faces[feature_vertices]),
        (feature.points, 2, fixed.edge_patches[feature.edge]),
    ]
    keys = np.concatenate(
        [
            site_keys(0, vertex_sites, points[vertex_sites]),
            site_keys(1, on_faces.face, on_faces.points),
            site_keys(2, feature_vertices, points[feature_vertices]),
            site_keys(3, feature.edge, feature.points),
        ]
    )
    counter = Counter(progress, "pole distances", 1)
    last = fixed.memo.match(keys)
    seen = last >= 0
    site_points = np.vstack([g[0] for g in groups])
    kind = np.concatenate([np.full(len(g[0]), g[1]) for g in groups]).astype(np.int8)
    width = max(g[2].shape[1] for g in groups)
    site_patches = np.concatenate(
        [np.pad(g[2], ((0, 0), (0, width - g[2].shape[1])), constant_values=-1) for g in groups]
    )
    count = len(site_points)
    medial = np.full(count, np.inf)
    medial[seen] = fixed.memo.get("medial", last[seen])
    if poles is not None:
        for column in range(width):
            lab = site_patches[:, column]
            ok = np.flatnonzero((lab >= 0) & ~seen)
            if len(ok):
                values = _nearest_allowed(*poles, site_points[ok], lab[ok], allowed)
                medial[ok] = np.minimum(medial[ok], values)
    counter.step()
    # --- B: thickness and curvature at the vertices inside patches and the face sites -------
    counter = Counter(progress, "rays", 1)
    ray_sites = np.flatnonzero(kind < 2)
    n_vertex = len(vertex_sites)
    origin_face = np.concatenate([fixed.vertex_face, on_faces.face])
    ray_normals = np.vstack([normals[vertex_sites], on_faces.normals])

    def lift(hit_faces, bary):
        """Hit points on the smooth surface (PN) for faces of curved patches."""
        points_out = np.einsum("nc,ncd->nd", bary, points[faces[hit_faces]])
        moved = curved_face[hit_faces]
        if moved.any():
            chosen = hit_faces[moved]
            points_out[moved] = pn_points(
                points[faces[chosen]], patches.corner_normals[chosen], bary[moved]
            )
        return points_out, moved

    # Rays only from the sites the last round did not have.
    fresh = np.flatnonzero(~seen[ray_sites])
    new = thickness(
        caster,
        site_points[ray_sites[fresh]],
        ray_normals[fresh],
        origin_face[fresh],
        allowed | np.eye(patches.count, dtype=bool),
        face_patch,
        site_patches[ray_sites[fresh], 0],
        lift,
        RAY_NEAR * np.concatenate([fixed.vertex_size, on_faces.sizes])[fresh],
    )
    ray = _rays_with_last(fixed.memo, last[ray_sites], fresh, new)
    curvature = np.concatenate([fixed.vertex_radius, radius_face[on_faces.face]])
    across = np.full(count, np.inf)  # half the thickness, inward or across a gap
    across[ray_sites] = np.minimum(ray.inward, ray.outward) / 2
    bend = np.full(count, np.inf)  # radius of curvature from the vertex normals
    bend[ray_sites] = curvature
    thick = np.full(count, np.inf)
    thick[ray_sites] = ray.inward
    counter.step()
    # --- features ---------------------------------------------------------------------------
    counter = Counter(progress, "feature sizes", 1)
    feature_site = kind == 2
    vertex_curves = fixed.vertex_curves
    edge_curves = patches.edge_curve[feature.edge][:, None]
    columns = max(vertex_curves.shape[1], 1)
    curves = np.concatenate(
        [
            vertex_curves.reshape(len(feature_vertices), columns),
            np.pad(edge_curves, ((0, 0), (0, columns - 1)), constant_values=-1),
        ]
    )
    radius = np.concatenate(
        [patches.vertex_curvature_radius[feature_vertices], _edge_radius(patches, feature.edge)]
    )
    feature_lfs = _feature_lfs(site_points[feature_site], curves, radius, patches, feature)
    # B is itself estimated: the distances from facets, the curvature from differences of
    # vertex normals, which are noisy on irregular meshes. Where the poles give L on a fine
    # mesh, only the distances cap it; where the mesh is coarse against the poles' L, the poles
    # along the medial axis are as far apart as the vertices (their distance overestimates L)
    # and the curvature caps it too; elsewhere B is the estimate.
    size = np.full(count, np.inf)
    size[ray_sites] = np.concatenate([fixed.vertex_size, fixed.longest[on_faces.face]])
    coarse = size > COARSE_POLE_RATIO * medial
    raw = np.where(
        np.isfinite(medial),
        np.minimum(
            np.minimum(medial, (1 + BOUND_TOLERANCE) * across), np.where(coarse, bend, np.inf)
        ),
        np.minimum(across, bend),
    )
    raw[feature_site] = np.minimum(raw[feature_site], feature_lfs)
    half = np.concatenate([np.zeros(len(feature_vertices)), feature.lengths / 2])
    raw = _feature_cap(site_points, raw, site_points[feature_site], feature_lfs, half)
    counter.step()
    counter = Counter(progress, "tangent balls", 1)
    # The largest ball tangent at the site that no other non-adjacent patch enters: medial
    # balls across the part that no normal ray finds (an L-bracket's corner). Inward always;
    # outward only where a ray found a gap (a convex outside has no medial ball to find).
    tangent, balls = _tangent_balls(
        fixed.balls,
        site_points[ray_sites],
        ray_normals,
        ray,
        site_patches[ray_sites, 0],
        raw[ray_sites],
        _last_balls(fixed.memo, last[ray_sites]),
    )
    across[ray_sites] = np.minimum(across[ray_sites], tangent)
    raw[ray_sites] = np.minimum(raw[ray_sites], tangent)
    bound = np.minimum(across, bend)
    # A feature site takes the values of its patches next to it (their limit at the feature).
    raw[feature_site] = np.minimum(
        raw[feature_site],
        _patch_limit(site_points, site_patches, raw, kind, np.flatnonzero(feature_site)),
    )
    if not np.isfinite(raw).any():
        raise VoroboundError("no finite local feature size anywhere: is the mesh closed?")
    raw = np.where(np.isfinite(raw), raw, np.nanmax(raw[np.isfinite(raw)]))
    counter.step()
    counter = Counter(progress, "Lipschitz repair", 1)
    envelope = Envelope(site_points, raw, slope)
    lfs = envelope(site_points, progress)
    counter = Counter(progress, "site radii", 1)
    areas = np.zeros(count)
    areas[n_vertex : n_vertex + len(on_faces.points)] = on_faces.areas
    radii = np.zeros(count)
    face_rows = slice(n_vertex, n_vertex + len(on_faces.points))
    radii[face_rows] = np.linalg.norm(on_faces.corners - on_faces.points[:, None], axis=2).max(
        axis=1
    )
    radii[len(site_points) - len(feature.points) :] = feature.lengths / 2
    # A site's value is spread over a ball of radius ρ(1 − g/λ), g the local rate of change of
    # L, beyond which its cone rises at λ; at a face site it follows L's tangent plane there
    # (the gradient fitted to the nearest sites of its patch) rather than staying flat, so L
    # between the sites is right to first order where it changes (docs/lfs.md).
    if slope > 0:
        site_normals = np.zeros((count, 3))
        site_normals[ray_sites] = ray_normals
        gradient, planes = _site_gradients(
            site_points, lfs, site_patches[:, 0], kind, site_normals, slope
        )
        radii = radii * (1 - gradient / slope)
    else:
        gradient, planes, radii = np.zeros(count), np.zeros((count, 3)), radii * 0
    vertex = np.concatenate(
        [
            vertex_sites,
            np.full(len(on_faces.points), -1),
            feature_vertices,
            np.full(len(feature.points), -1),
        ]
    )
    sites = Sites(
        site_points,
        raw,
        lfs,
        kind,
        areas,
        medial,
        bound,
        thick,
        radii,
        lfs,
        vertex,
        gradient,
        planes,
    )
    per_ray = balls | {
        "inward": ray.inward,
        "outward": ray.outward,
        "inward_known": ray.inward_known,
        "inward_sign": ray.inward_sign,
    }
    remembered = {name: np.full(count, np.nan) for name in per_ray}
    for name, values in per_ray.items():
        remembered[name][ray_sites] = values
    fixed.memo.remember(keys, medial=medial, **remembered)
    counter.step()
    medial_points = None if poles is None else poles[0]
    return sites, medial_points, envelope


@dataclass(frozen=True)
class _Fixed:
    """What every round of :func:`_evaluate` needs and no round changes."""

    normals: np.ndarray
    feature_vertices: np.ndarray
    vertex_faces: np.ndarray
    """(m, k) the patches of each vertex's faces."""
    edge_patches: np.ndarray
    """(e, 2) the patches on either side of each feature edge."""
    vertex_curves: np.ndarray
    """The curves of each feature vertex."""
    vertex_face: np.ndarray
    """A face of each vertex site."""
    vertex_size: np.ndarray
    """Longest edge at each vertex site."""
    vertex_radius: np.ndarray
    """Smallest radius of curvature of the faces around each vertex site."""
    longest: np.ndarray
    """Longest edge of each face."""
    balls: TangentBalls
    """The faces, for the tangent balls against other non-adjacent patches."""
    memo: RoundMemo


def _fixed(prepared, patches: Patches, vertex_sites, radius_face, allowed, normals) -> _Fixed:
    points, faces = prepared.points, prepared.triangles
    feature_vertices = np.flatnonzero(patches.feature_vertex)
    corners = points[faces]
    other = allowed & ~np.eye(patches.count, dtype=bool)
    return _Fixed(
        normals=normals,
        feature_vertices=feature_vertices,
        vertex_faces=_vertex_patch_table(faces, patches.face_patch, len(points)),
        edge_patches=_edge_patches(prepared, patches),
        vertex_curves=_vertex_curves(patches, feature_vertices),
        vertex_face=_a_face(faces, vertex_sites),
        vertex_size=_vertex_size(faces, points, vertex_sites),
        vertex_radius=_vertex_radius(faces, radius_face, vertex_sites, len(points)),
        longest=np.linalg.norm(corners - np.roll(corners, -1, axis=1), axis=2).max(axis=1),
        balls=TangentBalls(corners, patches.face_patch, other),
        memo=RoundMemo(),
    )


def _labelled_poles(
    prepared,
    patches,
    vertex_sites,
    vertex_patch,
    midpoints,
    normals,
    seed,
    input_points,
    progress,
    caster,
):
    """(pole positions, owner patch) from the vertices of curved patches and the fitted
    midpoints, or None when there are too few points.

    Points interpolated inside coarse faces are not used: PN patches meet with small creases,
    whose spurious poles would shrink L (docs/lfs.md).
    """
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
            noise=_rounding(input_points) / prepared.scale,
            seed=seed,
            progress=progress,
            labels=labels,
            adjacent=patches.adjacent,
        )
    except InputError:
        return None  # a nearly planar sample of curved patches: no medial points
    if poles.labelled_points is None or not len(poles.owner_labels):
        return None
    return _checked_poles(poles.labelled_points, poles.owner_labels, pole_points, caster, patches)


def _checked_poles(centres, owners, sample, caster, patches):
    """Keep the poles whose ball is empty of the mesh itself, not only of the sample: the
    surface may come no closer to the centre than POLE_EMPTY_RTOL short of the distance to
    the nearest sample point, unless it does so on a patch adjacent to the owner's (those
    contacts are left out by definition). A sample of some patches alone (the curved ones)
    leaves cells unbounded toward the others; their far Voronoi vertices are not medial."""
    from scipy.spatial import cKDTree

    radius = cKDTree(sample).query(centres, workers=thread_count())[0]
    # Only faces nearer than the bound matter (the nearest of them is the mesh's nearest), so
    # the search stays inside each pole's ball: a pole equally far from many faces (the centre
    # of a sphere, the core circle of a torus) costs nothing.
    bound = (1 - POLE_EMPTY_RTOL) * radius
    distance, face = caster.nearer_than(centres, bound)
    inside = face >= 0
    across = np.zeros(len(centres), dtype=bool)
    across[inside] = patches.adjacent[owners[inside], patches.face_patch[face[inside]]]
    keep = (distance >= bound) | across
    if not keep.any():
        return None
    return centres[keep], owners[keep]


def _vertex_patch_table(faces, face_patch, vertices: int) -> np.ndarray:
    """(m, k) the distinct patches of each vertex's faces, −1 padded."""
    pairs = np.unique(np.c_[faces.reshape(-1), np.repeat(face_patch, 3)], axis=0)
    counts = np.bincount(pairs[:, 0], minlength=vertices)
    width = max(1, int(counts.max()))
    table = np.full((vertices, width), -1)
    starts = np.r_[0, np.cumsum(counts)[:-1]]
    slot = np.arange(len(pairs)) - starts[pairs[:, 0]]
    table[pairs[:, 0], slot] = pairs[:, 1]
    return table


def _a_face(faces, vertices) -> np.ndarray:
    """One face of each vertex (the ray of a vertex skips it; its other faces lie at t ≈ 0)."""
    owner = np.full(int(faces.max()) + 1, -1)
    owner[faces.reshape(-1)] = np.repeat(np.arange(len(faces)), 3)
    return owner[vertices]


def _tangent_balls(balls: TangentBalls, sites, normals, ray, groups, cap, last):
    """Largest empty tangent ball against the faces of other non-adjacent patches, on the
    inward side (and the outward side where the ray there met an allowed patch), at most
    ``cap``; with what to remember of each side (its cap, ball and direction), from which
    ``last`` (the same, of the last round, NaN for new sites) gives a ball again where it can
    (:mod:`.memo`)."""
    out = np.asarray(cap, dtype=float).copy()
    side = np.where(ray.inward_sign < 0, -1.0, 1.0)
    remember = {"side": side}
    inward = side[:, None] * normals
    for name, direction, use in (
        ("inward", inward, ray.inward_sign != 0),
        ("outward", -inward, np.isfinite(ray.outward)),
    ):
        rows = np.flatnonzero(use & np.isfinite(out))
        limit, ball = out[rows], np.full(len(rows), np.nan)
        old_cap, old_ball = last[name + "_cap"][rows], last[name + "_ball"][rows]
        same = (last["side"][rows] == side[rows]) & np.isfinite(old_cap)
        again = same & ((old_ball < old_cap) | (limit <= old_cap))
        ball[again] = np.minimum(limit[again], old_ball[again])
        todo = np.flatnonzero(~again)
        if len(todo) and balls.allowed.any():
            chosen = rows[todo]
            ball[todo] = balls(sites[chosen], direction[chosen], groups[chosen], limit[todo])
        else:
            ball[todo] = limit[todo]
        out[rows] = ball
        remember[name + "_cap"] = np.full(len(out), np.nan)
        remember[name + "_ball"] = np.full(len(out), np.nan)
        remember[name + "_cap"][rows], remember[name + "_ball"][rows] = limit, ball
    return out, remember


def _rays_with_last(memo: RoundMemo, rows: np.ndarray, fresh: np.ndarray, new: Thickness):
    """The ray results of every ray site: ``new`` at ``fresh``, the rest remembered."""
    seen = np.flatnonzero(rows >= 0)
    fields = {}
    for name, kind in (
        ("inward", float),
        ("outward", float),
        ("inward_known", bool),
        ("inward_sign", np.int8),
    ):
        values = np.zeros(len(rows), dtype=kind)
        values[fresh] = getattr(new, name)
        values[seen] = memo.get(name, rows[seen]).astype(kind)
        fields[name] = values
    return Thickness(**fields)


def _last_balls(memo: RoundMemo, rows: np.ndarray) -> dict:
    """The remembered tangent balls at ``rows`` of the last round (NaN where −1)."""
    names = ("side", "inward_cap", "inward_ball", "outward_cap", "outward_ball")
    out = {name: np.full(len(rows), np.nan) for name in names}
    seen = rows >= 0
    if seen.any():
        for name in names:
            out[name][seen] = memo.get(name, rows[seen])
    return out


def _site_gradients(points, lfs, labels, kind, normals, slope: float):
    """Per site: the largest |L(y) − L(x)|/|y − x| over its SLOPE_NEIGHBOURS nearest sites
    (at most ``slope``); at face sites the tangential gradient of L (``normals``: unit normals
    there) fitted by least squares to the sites of the same patch among its FIT_NEIGHBOURS
    nearest (scaled to at most ``slope``; zero where fewer than three such sites or all on one
    line)."""
    from scipy.spatial import cKDTree

    count = len(points)
    slopes, planes = np.zeros(count), np.zeros((count, 3))
    k = min(FIT_NEIGHBOURS + 1, count)
    if k < 2:
        return slopes, planes
    tree = cKDTree(points)
    for start in range(0, count, GRADIENT_BLOCK):
        rows = np.arange(start, min(start + GRADIENT_BLOCK, count))
        few = min(SLOPE_NEIGHBOURS + 1, count)
        dist, near = tree.query(points[rows], k=few, workers=thread_count())
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.abs(lfs[near[:, 1:]] - lfs[rows, None]) / dist[:, 1:]
        slopes[rows] = np.minimum(np.where(np.isfinite(ratio), ratio, 0.0).max(axis=1), slope)
        # A plane only where L changes: elsewhere it would move the value by less than
        # PLANE_MIN_RATE times the piece radius.
        rows = rows[(kind[rows] == 1) & (slopes[rows] > PLANE_MIN_RATE * slope)]
        if not len(rows):
            continue
        near = tree.query(points[rows], k=k, workers=thread_count())[1][:, 1:]
        change = lfs[near] - lfs[rows, None]
        same = (labels[near] == labels[rows, None]) & (labels[rows, None] >= 0)
        # Least squares in the tangent plane: the offsets in an orthonormal basis of it.
        first, second = tangent_basis(normals[rows])
        offset = points[near] - points[rows, None]
        u = np.einsum("nki,ni->nk", offset, first) * same
        v = np.einsum("nki,ni->nk", offset, second) * same
        change = change * same
        uu, uv, vv = (u * u).sum(axis=1), (u * v).sum(axis=1), (v * v).sum(axis=1)
        cu, cv = (u * change).sum(axis=1), (v * change).sum(axis=1)
        det = uu * vv - uv * uv
        # At least three sites of the patch, not all on one line.
        good = (same.sum(axis=1) >= 3) & (det > FIT_SPREAD * (uu + vv) ** 2)
        with np.errstate(divide="ignore", invalid="ignore"):
            gu = (vv * cu - uv * cv) / det
            gv = (uu * cv - uv * cu) / det
            gradient = gu[:, None] * first + gv[:, None] * second
            size = np.linalg.norm(gradient, axis=1)
            gradient *= np.minimum(1.0, slope / np.where(size > 0, size, 1.0))[:, None]
        good &= np.isfinite(gradient).all(axis=1)
        planes[rows[good]] = gradient[good]
    return slopes, planes


def _vertex_size(faces, points, vertices) -> np.ndarray:
    """Longest edge at each vertex (the first search radius of its tangent ball)."""
    longest = np.zeros(len(points))
    for k in range(3):
        a, b = faces[:, k], faces[:, (k + 1) % 3]
        length = np.linalg.norm(points[a] - points[b], axis=1)
        np.maximum.at(longest, a, length)
        np.maximum.at(longest, b, length)
    return longest[vertices]


def _vertex_radius(faces, radius_face, vertices, count: int) -> np.ndarray:
    """Smallest radius of curvature of the faces around each vertex."""
    per_vertex = np.full(count, np.inf)
    np.minimum.at(per_vertex, faces.reshape(-1), np.repeat(radius_face, 3))
    return per_vertex[vertices]


def _edge_patches(prepared, patches: Patches) -> np.ndarray:
    """(e, 2) the patches on either side of each feature edge (−1 where none)."""
    edges = np.sort(patches.feature_edges, axis=1)
    out = np.full((len(edges), 2), -1)
    if not len(edges):
        return out
    faces = prepared.triangles
    pairs = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), 1)
    face = np.tile(np.arange(len(faces)), 3)
    order = np.lexsort((pairs[:, 1], pairs[:, 0]))
    pairs, face = pairs[order], face[order]
    key = edges[:, 0] * (len(prepared.points) + 1) + edges[:, 1]
    all_keys = pairs[:, 0] * (len(prepared.points) + 1) + pairs[:, 1]
    first = np.searchsorted(all_keys, key)
    for column in range(2):
        at = np.minimum(first + column, len(all_keys) - 1)
        hit = all_keys[at] == key
        out[hit, column] = patches.face_patch[face[at[hit]]]
    return out


def _vertex_curves(patches: Patches, vertices: np.ndarray) -> np.ndarray:
    """(n, k) the curves of each feature vertex's edges, −1 padded."""
    edges = patches.feature_edges
    if not len(edges) or not len(vertices):
        return np.full((len(vertices), 1), -1)
    ends = np.concatenate([edges[:, 0], edges[:, 1]])
    curve = np.concatenate([patches.edge_curve, patches.edge_curve])
    pairs = np.unique(np.c_[ends, curve], axis=0)
    index = {v: k for k, v in enumerate(vertices.tolist())}
    width = max(1, int(np.bincount(pairs[:, 0]).max()))
    table = np.full((len(vertices), width), -1)
    fill = np.zeros(len(vertices), dtype=np.int64)
    for v, c in pairs.tolist():
        row = index.get(v)
        if row is not None:
            table[row, fill[row]] = c
            fill[row] += 1
    return table


def _edge_radius(patches: Patches, edge: np.ndarray) -> np.ndarray:
    """Radius of curvature of the curve at a point of a feature edge: the smaller one of the
    edge's two end vertices."""
    ends = patches.feature_edges[edge]
    radius = patches.vertex_curvature_radius
    return np.minimum(radius[ends[:, 0]], radius[ends[:, 1]])


def _patch_limit(site_points, site_patches, raw, kind, queries) -> np.ndarray:
    """For each query (feature) site, min over its patches of raw at that patch's nearest site
    inside the patch (a vertex or a face site among the 16 nearest)."""
    from scipy.spatial import cKDTree

    inner = np.flatnonzero(kind < 2)
    out = np.full(len(queries), np.inf)
    if not len(inner) or not len(queries):
        return out
    tree = cKDTree(site_points[inner])
    k = min(16, len(inner))
    _, index = tree.query(site_points[queries], k=k, workers=thread_count())
    candidates = inner[index.reshape(len(queries), -1)]
    candidate_patch = site_patches[candidates, 0]
    for column in range(site_patches.shape[1]):
        wanted = site_patches[queries, column]
        match = (candidate_patch == wanted[:, None]) & (wanted[:, None] >= 0)
        found = match.any(axis=1)
        first = candidates[np.arange(len(queries)), match.argmax(axis=1)]
        out[found] = np.minimum(out[found], raw[first[found]])
    return out


def _nearest_allowed(pole_points, pole_labels, queries, query_labels, allowed) -> np.ndarray:
    """Distance from each query to the nearest pole whose label is allowed for the query's."""
    from scipy.spatial import cKDTree

    tree = cKDTree(pole_points)
    out = np.full(len(queries), np.inf)
    todo = np.arange(len(queries))
    for k in NEAREST_POLES:
        if not len(todo):
            break
        k_eff = min(k, len(pole_points))
        dist, index = tree.query(queries[todo], k=k_eff, workers=thread_count())
        dist, index = dist.reshape(len(todo), -1), index.reshape(len(todo), -1)
        ok = allowed[query_labels[todo][:, None], pole_labels[index]]
        found = ok.any(axis=1)
        first = ok.argmax(axis=1)
        out[todo[found]] = dist[found, first[found]]
        todo = todo[~found]
        if k_eff == len(pole_points):
            break
    if len(todo):
        for label in np.unique(query_labels[todo]):
            mine = todo[query_labels[todo] == label]
            keep = allowed[label, pole_labels]
            if keep.any():
                out[mine] = cKDTree(pole_points[keep]).query(queries[mine], workers=thread_count())[
                    0
                ]
    return out


def _feature_lfs(query_points, query_curves, radius, patches: Patches, feature) -> np.ndarray:
    """L_F at feature sites: min(the curve's radius of curvature, half the distance to the
    nearest point of a non-adjacent curve: neither one of the site's curves nor sharing a
    corner with one)."""
    from scipy.spatial import cKDTree

    n = len(query_points)
    if n == 0 or len(feature.points) == 0:
        return np.minimum(radius, np.inf)
    target_curve = patches.edge_curve[feature.edge]
    related = patches.curve_adjacent | np.eye(patches.curves, dtype=bool)
    tree = cKDTree(feature.points)
    gap = np.full(n, np.inf)
    todo = np.arange(n)
    for k in (16, 64, 256, len(feature.points)):
        if not len(todo):
            break
        k_eff = min(k, len(feature.points))
        dist, index = tree.query(query_points[todo], k=k_eff, workers=thread_count())
        dist, index = dist.reshape(len(todo), -1), index.reshape(len(todo), -1)
        near = np.zeros(index.shape, dtype=bool)
        for column in range(query_curves.shape[1]):
            mine = query_curves[todo, column]
            valid = mine >= 0
            hit = related[np.maximum(mine, 0)[:, None], target_curve[index]]
            near |= hit & valid[:, None]
        far = ~near
        found = far.any(axis=1)
        gap[todo[found]] = dist[found, far[found].argmax(axis=1)]
        todo = todo[~found]
        if k_eff == len(feature.points):
            break
    return np.minimum(radius, gap / 2)


def _feature_cap(site_points, raw, feature_points, feature_lfs, half) -> np.ndarray:
    """min(raw, min over feature pieces P of max(dist(x, P), L_F(P))), with dist(x, P) taken
    as |x − p| − (half the piece's length), p its centre (never above the distance)."""
    finite = np.isfinite(feature_lfs)  # an infinite L_F caps nothing
    if not finite.any():
        return raw
    cap = DistanceCap(feature_points[finite], feature_lfs[finite], half[finite])
    return cap(site_points, upper=raw)


def _result(
    mesh, prepared, patches, sites, poles, midpoints, slope, sharp_angle, rounds, field, vertex_lfs
):
    """The :class:`LfsEstimate` in the input's units, with its warnings; ``field`` is the
    envelope of the last round's sites and ``vertex_lfs`` its values at the vertices."""
    scale, centre, points = prepared.scale, prepared.centre, prepared.points
    lfs_sites = Sites(
        points=scale * sites.points + centre,
        raw=scale * sites.raw,
        lfs=scale * sites.lfs,
        kind=sites.kind,
        areas=scale**2 * sites.areas,
        medial=scale * sites.medial,
        bound=scale * sites.bound,
        thickness=scale * sites.thickness,
        radii=scale * sites.radii,
        values=scale * sites.values,
        vertex=sites.vertex,
        gradient=sites.gradient,
        planes=sites.planes,
    )
    # A vertex is a site: its output is its own L (the envelope of the raw values there).
    # `at` spreads each site's value over its piece, so at a vertex it is at most this (lower
    # where a neighbouring face site's value is; docs/lfs.md). Vertices of no face get `at`.
    vertex_lfs = vertex_lfs.copy()
    own = sites.vertex >= 0
    vertex_lfs[sites.vertex[own]] = sites.lfs[own]
    if not (np.isfinite(vertex_lfs).all() and (vertex_lfs > 0).all()):
        raise VoroboundError(f"mesh {mesh.name}: the estimated L is zero at some vertex")
    first_input = np.zeros(len(points), dtype=np.int64)
    first_input[prepared.original_to_merged[::-1]] = np.arange(len(mesh.points))[::-1]
    notes = prepared.report.problems()
    face = sites.kind == 1
    both = face & np.isfinite(sites.medial) & np.isfinite(sites.bound)
    over = both & (sites.medial > DISAGREE_RATIO * sites.bound)
    disagreement = {"face_sites": int(face.sum()), "compared": int(both.sum())}
    if both.any():
        ratio = sites.medial[both] / sites.bound[both]
        worst = int(np.flatnonzero(both)[np.argmax(ratio)])
        disagreement |= {
            "share_above": float(over.sum() / both.sum()),
            "worst_ratio": float(ratio.max()),
            "worst_at": (scale * sites.points[worst] + centre).tolist(),
        }
        if over.sum() > DISAGREE_SHARE * both.sum():
            where = ", ".join(f"{x:.4g}" for x in disagreement["worst_at"])
            notes.append(
                f"the medial estimate (poles) exceeds the thickness and curvature bound by more "
                f"than {DISAGREE_RATIO:g}x at {100 * over.sum() / both.sum():.1f} % of the face "
                f"sites (worst {ratio.max():.3g}x at {where}); L uses the bound there"
            )
    sharp = patches.sharp_edges
    if len(sharp):
        notes.append(
            f"{len(sharp)} sharp edges (face normals differ by more than {sharp_angle:g}°, up to "
            f"{patches.max_dihedral:.1f}°) split the surface into {patches.count} smooth patches: "
            "L is that of the piecewise-smooth surface (docs/lfs.md), and VoroCrust's smooth-"
            "surface analysis does not cover the sharp features themselves"
        )
    notes += _coarse(prepared, patches, vertex_lfs)
    subject = fingerprint(mesh.points, mesh.triangles)
    for note in notes:
        warn_once(f"mesh {mesh.name}: {note}", subject, stacklevel=3)
    feature_length, feature_inv = _feature_integrals(prepared.points, patches.feature_edges, field)
    feature_length *= scale
    medial_points = np.zeros((0, 3)) if poles is None else scale * poles + centre
    sample_count = int((sites.kind == 0).sum()) + len(midpoints.points)
    return LfsEstimate(
        mesh=mesh,
        lfs=scale * vertex_lfs[prepared.original_to_merged],
        lipschitz=slope,
        medial_points=medial_points,
        sample_count=sample_count,
        added_samples=len(midpoints.points),
        eligible_edges=midpoints.eligible,
        sharp_edges=first_input[sharp],
        feature_segments=first_input[patches.feature_edges].reshape(-1, 2),
        feature_corners=first_input[patches.corners],
        sharp_angle=float(sharp_angle),
        max_dihedral=patches.max_dihedral,
        mesh_report=prepared.report,
        warnings=tuple(notes),
        method=_method(len(midpoints.points), patches, rounds),
        patches=patches.count,
        feature_edges=len(patches.feature_edges),
        feature_length=feature_length,
        feature_inv_lfs=feature_inv,
        rounds=rounds,
        disagreement=disagreement,
        sites=lfs_sites,
    )


def _feature_integrals(points, edges, field) -> tuple[float, float]:
    """Length of the feature edges and ∫ ds/L along them (midpoint rule on pieces no longer
    than L/4 at the edge's midpoint)."""
    if not len(edges):
        return 0.0, 0.0
    a, b = points[edges[:, 0]], points[edges[:, 1]]
    length = np.linalg.norm(b - a, axis=1)
    pieces = np.clip(np.ceil(4 * length / field(0.5 * (a + b))), 1, 4096).astype(np.int64)
    owner = np.repeat(np.arange(len(edges)), pieces)
    index = np.arange(len(owner)) - np.repeat(np.cumsum(pieces) - pieces, pieces)
    f = (index + 0.5) / pieces[owner]
    values = field(a[owner] + f[:, None] * (b - a)[owner])
    return float(length.sum()), float((length[owner] / pieces[owner] / values).sum())


def _method(added: int, patches: Patches, rounds: int) -> str:
    sample = "vertices"
    if added:
        sample += f", {added:,} fitted edge midpoints"
    return (
        f"piecewise-smooth L over {patches.count} patches: min of the distance to the Voronoi "
        f"poles (Amenta-Bern) of the {sample} and face sites, half the thickness along the "
        f"normal, the radius of curvature, and the feature sizes; {rounds} rounds of face sites"
    )


def _rounding(points: np.ndarray) -> float:
    """The rounding error of the coordinates: single precision if every coordinate is a float32
    (as in STL files), else double."""
    points = np.asarray(points, dtype=float)
    with np.errstate(over="ignore", invalid="ignore"):
        single = np.array_equal(points.astype(np.float32).astype(float), points)
    return float(np.abs(points).max()) * float(np.finfo(np.float32 if single else float).eps)


def _refuse_flat(points: np.ndarray, name: str) -> None:
    """A surface in one plane has no medial axis (L is unbounded): refuse it."""
    spread = np.linalg.eigvalsh(np.cov(points.T))
    if spread[0] <= FLAT_RTOL**2 * spread[-1]:
        raise InputError(
            f"mesh {name}: the vertices are (nearly) coplanar: a flat surface has no finite "
            "local feature size"
        )


def _coarse(prepared, patches: Patches, lfs: np.ndarray) -> list[str]:
    """A note when an edge inside a curved patch is long compared with L at its ends."""
    faces = prepared.triangles
    curved_vertex = np.zeros(len(prepared.points), dtype=bool)
    curved = ~patches.flat[patches.face_patch]
    curved_vertex[faces[curved].reshape(-1)] = True
    edges = prepared.edges
    inside = curved_vertex[edges].all(axis=1) & ~patches.feature_vertex[edges].any(axis=1)
    edges = edges[inside]
    if not len(edges):
        return []
    length = np.linalg.norm(prepared.points[edges[:, 0]] - prepared.points[edges[:, 1]], axis=1)
    ratio = length / np.minimum(lfs[edges[:, 0]], lfs[edges[:, 1]])
    bad = ratio > COARSE_EDGE_RATIO
    if not bad.any():
        return []
    return [
        f"{int(bad.sum())} edges of curved patches are longer than {COARSE_EDGE_RATIO:g}·L (up "
        f"to {float(ratio[bad].max()):.2f}·L): the surface between their vertices is "
        "interpolated from the vertex normals there"
    ]
