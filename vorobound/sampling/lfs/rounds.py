"""The rounds of the estimate of L (:mod:`.estimate`): each round cuts the faces into sites
at a spacing set by the last round's L, evaluates every term there (the medial estimate from
the poles, the thickness and curvature bound, the feature sizes, the tangent balls) and takes
their Lipschitz envelope, until L at the vertices is stable. What no round changes is a
:class:`RoundState`, built once; what depends on a site alone is remembered between rounds
(:mod:`.memo`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...errors import VoroboundError
from ...progress import Counter, Progress
from . import features
from .face_sites import EdgeSites, FaceSites, edge_sites, face_sites, pn_points
from .lipschitz import Envelope
from .memo import RoundMemo, site_keys
from .mesh_quality import PreparedMesh
from .patches import Patches
from .poles import nearest_allowed_pole
from .sites import (
    FIRST_SPACING,
    MIN_PIECES,
    SITE_SPACING,
    Sites,
    field_of,
    site_gradients,
    spacings,
    vertex_radius,
)
from .tangent_ball import TangentBalls
from .thickness import RayCaster, Thickness, thickness

ROUNDS = 4
"""Most refinement rounds of the face sites."""

STABLE_RTOL = 0.02
"""Refinement stops when L at every vertex changed by less than this in the last round."""

RAY_NEAR = 0.25
"""Ray hits closer than this times the local mesh spacing are the next faces of a bumpy mesh."""

COARSE_POLE_RATIO = 0.8
"""Where the local mesh edge exceeds this times the medial estimate, the poles along the
medial axis are as sparse as the vertices and overestimate L (an L-bracket's bore with rings
0.9·L apart: 0.93 for 0.6); the curvature radius then caps it too. Below it the vertex-normal
curvature is left out: on irregular meshes it is noisy (a jittered torus: 0.25 for 0.5)."""

SLOPE_SLACK = 1e-6
"""The face sites take the spacing's slope this much (relative) above λ times the factor, so
that the rounding of the envelope's cones cannot make a bound of :func:`.face_sites.face_sites`
wrong."""

BOUND_TOLERANCE = 0.0
"""Where the poles give L, half the thickness lowers it only when it is smaller by more than
this share (ray hits on curved patches are lifted to the smooth PN surface, good to about this
on the test meshes); the curvature from vertex normals is left to the poles there."""


@dataclass(frozen=True)
class RoundState:
    """What every round of :func:`evaluate_round` needs and no round changes (the memo of
    the last round's values aside)."""

    prepared: PreparedMesh
    patches: Patches
    slope: float
    """λ of the envelope."""
    caster: RayCaster
    allowed: np.ndarray
    """(p, p) True for two patches that are not adjacent (poles and hits may count)."""
    surface_ids: np.ndarray
    """The vertices on faces with area."""
    vertex_sites: np.ndarray
    """The vertices inside smooth patches (sites of every round)."""
    vertex_patch: np.ndarray
    """(m,) a patch of each vertex."""
    poles: tuple[np.ndarray, np.ndarray] | None
    """(pole positions, owner patch), or None."""
    radius_face: np.ndarray
    """Radius of curvature of each face from its vertex normals."""
    curved_face: np.ndarray
    """(f,) True for the faces of curved patches."""
    factor: np.ndarray
    """SITE_SPACING of each face."""
    face_floor: np.ndarray
    """Shortest piece of each face (its longest edge over MIN_PIECES)."""
    edge_floor: np.ndarray
    """Shortest piece of each feature edge."""
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


def round_state(
    prepared: PreparedMesh,
    patches: Patches,
    *,
    slope: float,
    caster: RayCaster,
    surface_ids: np.ndarray,
    vertex_sites: np.ndarray,
    vertex_patch: np.ndarray,
    poles: tuple[np.ndarray, np.ndarray] | None,
    radius_face: np.ndarray,
    normals: np.ndarray,
) -> RoundState:
    """The :class:`RoundState` of a prepared mesh split into ``patches``."""
    points, faces = prepared.points, prepared.triangles
    surface = prepared.mesh
    curved_face = ~patches.flat[patches.face_patch]
    allowed = ~patches.adjacent
    ends = points[patches.feature_edges]
    feature_vertices = np.flatnonzero(patches.feature_vertex)
    other = allowed & ~np.eye(patches.count, dtype=bool)
    return RoundState(
        prepared=prepared,
        patches=patches,
        slope=slope,
        caster=caster,
        allowed=allowed,
        surface_ids=surface_ids,
        vertex_sites=vertex_sites,
        vertex_patch=vertex_patch,
        poles=poles,
        radius_face=radius_face,
        curved_face=curved_face,
        factor=np.where(curved_face, SITE_SPACING["curved"], SITE_SPACING["flat"]),
        face_floor=surface.longest_edges / MIN_PIECES,
        edge_floor=np.linalg.norm(ends[:, 1] - ends[:, 0], axis=1) / MIN_PIECES,
        normals=normals,
        feature_vertices=feature_vertices,
        vertex_faces=surface.vertex_label_table(patches.face_patch),
        edge_patches=features.edge_patches(prepared, patches),
        vertex_curves=features.vertex_curves(patches, feature_vertices),
        vertex_face=surface.vertex_face[vertex_sites],
        vertex_size=surface.vertex_longest_edge[vertex_sites],
        vertex_radius=vertex_radius(faces, radius_face, vertex_sites, len(points)),
        longest=surface.longest_edges,
        balls=TangentBalls(points[faces], patches.face_patch, other),
        memo=RoundMemo(),
    )


@dataclass(frozen=True)
class Rounds:
    """The last round: its sites, poles and field (the envelope of its sites' values), L at
    the vertices, and how many rounds were made."""

    sites: Sites
    poles: np.ndarray | None
    field: Envelope
    at_vertices: np.ndarray
    count: int


def run_rounds(state: RoundState, progress: Progress | None = None) -> Rounds:
    """Rounds of face sites until L at every vertex changes by at most STABLE_RTOL (at most
    ROUNDS rounds)."""
    points = state.prepared.points
    field: Envelope | None = None
    sites: Sites | None = None
    previous = None
    count = 0
    for done in range(1, ROUNDS + 1):
        count = done
        # What a round no longer needs is let go as soon as it can be, before the next big
        # arrays are made: the last round's sites before the cut (which needs its field
        # only), its field after it, the cut pieces and the raw envelope once the round's
        # field is made. On a part of long thin faces these are the largest arrays.
        sites = None
        counter = Counter(progress, "face sites", 1)
        on_faces, feature = _cut(state, field)
        counter.step()
        field = None
        sites, poles, envelope = evaluate_round(state, on_faces, feature, progress)
        del on_faces, feature
        counter = Counter(progress, "L at the vertices", 1)
        # L between the sites, the feature cap's cones with them (docs/lfs.md).
        field = field_of(sites, state.slope, like=envelope)
        del envelope
        at_vertices = field(points)
        counter.step()
        current = at_vertices[state.surface_ids]
        if previous is not None and np.all(np.abs(current - previous) <= STABLE_RTOL * previous):
            break
        previous = current
    assert field is not None and sites is not None  # ROUNDS ≥ 1
    return Rounds(sites, poles, field, at_vertices, count)


def _cut(state: RoundState, field: Envelope | None) -> tuple[FaceSites, EdgeSites]:
    """The faces and feature edges cut at SITE_SPACING times the last round's ``field``
    (λ-Lipschitz), or at FIRST_SPACING in the first round (``field`` None)."""
    points, faces = state.prepared.points, state.prepared.triangles
    patches = state.patches
    if field is None:

        def face_spacing(x, face):
            return np.full(len(x), FIRST_SPACING)

        def edge_spacing(x, edge):
            return np.full(len(x), FIRST_SPACING)

    else:
        face_spacing, edge_spacing = spacings(
            field, state.factor, state.face_floor, state.edge_floor
        )
    slope = 0.0 if field is None else state.factor * state.slope * (1 + SLOPE_SLACK)
    on_faces = face_sites(
        points,
        faces,
        patches.corner_normals,
        state.curved_face,
        face_spacing,
        slope=slope,
        groups=patches.face_patch,
        floor=None if field is None else state.face_floor,
    )
    return on_faces, edge_sites(points, patches.feature_edges, edge_spacing)


def evaluate_round(
    state: RoundState, on_faces: FaceSites, feature: EdgeSites, progress: Progress | None
) -> tuple[Sites, np.ndarray | None, Envelope]:
    """One round: estimators A and B, the feature terms and the envelope at every site; the
    sites, the pole positions and the envelope of the raw values (whose tree lends its shape to
    the round's field).

    Sites, in this order: the vertices inside smooth patches, the face sites, the feature
    vertices, the points on feature edges. Values that depend on a site alone are taken over
    from the last round where the site is the same (:mod:`.memo`).
    """
    prepared, patches, slope = state.prepared, state.patches, state.slope
    points, faces = prepared.points, prepared.triangles
    face_patch = patches.face_patch
    vertex_sites, vertex_patch, curved_face = (
        state.vertex_sites,
        state.vertex_patch,
        state.curved_face,
    )
    normals = state.normals
    poles = state.poles
    feature_vertices = state.feature_vertices
    groups = [
        (points[vertex_sites], 0, vertex_patch[vertex_sites][:, None]),
        (on_faces.points, 1, face_patch[on_faces.face][:, None]),
        (points[feature_vertices], 2, state.vertex_faces[feature_vertices]),
        (feature.points, 2, state.edge_patches[feature.edge]),
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
    last = state.memo.match(keys)
    seen = last >= 0
    site_points = np.vstack([g[0] for g in groups])
    kind = np.concatenate([np.full(len(g[0]), g[1]) for g in groups]).astype(np.int8)
    width = max(g[2].shape[1] for g in groups)
    site_patches = np.concatenate(
        [np.pad(g[2], ((0, 0), (0, width - g[2].shape[1])), constant_values=-1) for g in groups]
    )
    count = len(site_points)
    medial = np.full(count, np.inf)
    medial[seen] = state.memo.get("medial", last[seen])
    if poles is not None:
        # Every (site, patch of the site) in one search (the poles' tree is built once).
        row, column = np.nonzero((site_patches >= 0) & ~seen[:, None])
        if len(row):
            lab = site_patches[row, column]
            values = nearest_allowed_pole(*poles, site_points[row], lab, state.allowed)
            np.minimum.at(medial, row, values)
    counter.step()
    # --- B: thickness and curvature at the vertices inside patches and the face sites -------
    counter = Counter(progress, "rays", 1)
    ray_sites = np.flatnonzero(kind < 2)
    n_vertex = len(vertex_sites)
    origin_face = np.concatenate([state.vertex_face, on_faces.face])
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
        state.caster,
        site_points[ray_sites[fresh]],
        ray_normals[fresh],
        origin_face[fresh],
        state.allowed | np.eye(patches.count, dtype=bool),
        face_patch,
        site_patches[ray_sites[fresh], 0],
        lift,
        RAY_NEAR * np.concatenate([state.vertex_size, on_faces.sizes])[fresh],
    )
    ray = _rays_with_last(state.memo, last[ray_sites], fresh, new)
    curvature = np.concatenate([state.vertex_radius, state.radius_face[on_faces.face]])
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
    vertex_curves = state.vertex_curves
    edge_curves = patches.edge_curve[feature.edge][:, None]
    columns = max(vertex_curves.shape[1], 1)
    curves = np.concatenate(
        [
            vertex_curves.reshape(len(feature_vertices), columns),
            np.pad(edge_curves, ((0, 0), (0, columns - 1)), constant_values=-1),
        ]
    )
    radius = np.concatenate(
        [
            patches.vertex_curvature_radius[feature_vertices],
            features.edge_radius(patches, feature.edge),
        ]
    )
    feature_lfs = features.feature_lfs(site_points[feature_site], curves, radius, patches, feature)
    # B is itself estimated: the distances from facets, the curvature from differences of
    # vertex normals, which are noisy on irregular meshes. Where the poles give L on a fine
    # mesh, only the distances cap it; where the mesh is coarse against the poles' L, the poles
    # along the medial axis are as far apart as the vertices (their distance overestimates L)
    # and the curvature caps it too; elsewhere B is the estimate.
    size = np.full(count, np.inf)
    size[ray_sites] = np.concatenate([state.vertex_size, state.longest[on_faces.face]])
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
    raw = features.feature_cap(site_points, raw, site_points[feature_site], feature_lfs, half)
    counter.step()
    counter = Counter(progress, "tangent balls", 1)
    # The largest ball tangent at the site that no other non-adjacent patch enters: medial
    # balls across the part that no normal ray finds (an L-bracket's corner). Inward always;
    # outward only where a ray found a gap (a convex outside has no medial ball to find).
    tangent, balls = _tangent_balls(
        state.balls,
        site_points[ray_sites],
        ray_normals,
        ray,
        site_patches[ray_sites, 0],
        raw[ray_sites],
        _last_balls(state.memo, last[ray_sites]),
    )
    across[ray_sites] = np.minimum(across[ray_sites], tangent)
    raw[ray_sites] = np.minimum(raw[ray_sites], tangent)
    bound = np.minimum(across, bend)
    # A feature site takes the values of its patches next to it (their limit at the feature).
    raw[feature_site] = np.minimum(
        raw[feature_site],
        features.patch_limit(site_points, site_patches, raw, kind, np.flatnonzero(feature_site)),
    )
    if not np.isfinite(raw).any():
        raise VoroboundError("no finite local feature size anywhere: is the mesh closed?")
    raw = np.where(np.isfinite(raw), raw, np.nanmax(raw[np.isfinite(raw)]))
    counter.step()
    counter = Counter(progress, "Lipschitz repair", 1)
    envelope = Envelope(site_points, raw, slope)
    # Each site's own cone is its raw value there: a first bound that changes no value and
    # spares the search most of the tree.
    lfs = envelope(site_points, progress, upper=raw)
    counter = Counter(progress, "site radii", 1)
    areas = np.zeros(count)
    areas[n_vertex : n_vertex + len(on_faces.points)] = on_faces.areas
    radii = np.zeros(count)
    face_rows = slice(n_vertex, n_vertex + len(on_faces.points))
    if on_faces.reach is None:
        assert on_faces.corners is not None  # cut without groups: the pieces are kept
        radii[face_rows] = np.linalg.norm(on_faces.corners - on_faces.points[:, None], axis=2).max(
            axis=1
        )
    else:
        radii[face_rows] = on_faces.reach
    radii[len(site_points) - len(feature.points) :] = feature.lengths / 2
    # A site's value is spread over a ball of radius ρ(1 − g/λ), g the local rate of change of
    # L, beyond which its cone rises at λ; at a face site it follows L's tangent plane there
    # (the gradient fitted to the nearest sites of its patch) rather than staying flat, so L
    # between the sites is right to first order where it changes (docs/lfs.md).
    if slope > 0:
        site_normals = np.zeros((count, 3))
        site_normals[ray_sites] = ray_normals
        gradient, planes = site_gradients(
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
    # The feature cap's cones (sites.field_of): L below the cap at every point.
    cap = {}
    if feature_site.any():
        finite = np.isfinite(feature_lfs)
        cap = {
            "cap_points": site_points[feature_site][finite],
            "cap_values": feature_lfs[finite],
            "cap_radii": feature_lfs[finite] + half[finite],
        }
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
        **cap,
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
    state.memo.remember(keys, medial=medial, **remembered)
    counter.step()
    medial_points = None if poles is None else poles[0]
    return sites, medial_points, envelope


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
