"""The sites of the estimate of L (:mod:`.estimate`): the points where its terms are
evaluated, how finely the faces are cut into them, and the local rate of change of L there.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ...geometry.threads import thread_count
from .curved import tangent_basis
from .lipschitz import Envelope

SITE_SPACING = {"curved": 0.5, "flat": 1.0}
"""Face sites are refined until no piece is longer than this times L at its centroid: on
curved patches the poles and the curvature need the denser sample, on flat ones the thickness
bound is exact at any spacing."""

FIRST_SPACING = 1 / 25
"""Spacing of the first round of face sites, relative to the part's diagonal."""

MIN_PIECES = 32
"""No piece is made shorter than its face's longest edge over MIN_PIECES: where L from the
vertex normals is far below the mesh spacing (an edge just below the sharp angle), the mesh
does not resolve it anyway."""

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
    cap_points: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    """The feature points whose cap max(|x − p| − h, L_F(p)) bounds L everywhere."""
    cap_values: np.ndarray = field(default_factory=lambda: np.zeros(0))
    """L_F at each cap point."""
    cap_radii: np.ndarray = field(default_factory=lambda: np.zeros(0))
    """L_F + h at each cap point (h: half its piece of feature edge)."""


def field_of(sites: Sites, slope: float, like: Envelope | None = None) -> Envelope:
    """L everywhere: min over sites y of v(y) + max(a(y)·(x − y), λ(|x − y| − ρ(y))) and over
    cap points p of L_F(p) + λ·max(0, |x − p| − h(p) − L_F(p)).

    The second cone is the largest λ-Lipschitz function below the feature cap of p,
    max(|x − p| − h, L_F(p)) (λ ≤ 1; for λ = 1 the cap itself): on the segment from p to x the
    cap plus λ times the rest of the way is smallest at distance h + L_F(p) from p. So L is
    at most the cap at every point, not only at the sites, and stays λ-Lipschitz (a minimum
    of λ-Lipschitz cones). ``like``: an envelope of the sites alone, whose tree lends its shape
    when there are no cap points.
    """
    if not len(sites.cap_points):
        return Envelope(
            sites.points, sites.values, slope, sites.radii, like=like, gradients=sites.planes
        )
    return Envelope(
        np.vstack([sites.points, sites.cap_points]),
        np.concatenate([sites.values, sites.cap_values]),
        slope,
        np.concatenate([sites.radii, sites.cap_radii]),
        gradients=np.vstack([sites.planes, np.zeros((len(sites.cap_points), 3))]),
    )


def spacings(field: Envelope, factor: np.ndarray, face_floor, edge_floor):
    """The next round's spacing: SITE_SPACING (per face) times L of the last round, at least
    the floors (:data:`MIN_PIECES`)."""

    def face_spacing(x, face):
        scale, floor = factor[face], face_floor[face]
        return np.maximum(scale * field(x, cutoff=_cutoff(floor, scale)), floor)

    def edge_spacing(x, edge):
        scale, floor = SITE_SPACING["curved"], edge_floor[edge]
        return np.maximum(scale * field(x, cutoff=_cutoff(floor, scale)), floor)

    return face_spacing, edge_spacing


def _cutoff(floor, scale) -> np.ndarray:
    """t = floor/scale, stepped down where rounding put it above, so that scale·t ≤ floor in
    floating point (``scale`` positive). Where L is at most t, max(scale·L, floor) is the
    floor whatever L is, so the field's search may stop at the first cone at most t
    (:meth:`.lipschitz.Envelope.__call__`): any value v ≤ t gives scale·v ≤ scale·t ≤ floor
    (rounding is monotone), and the spacing is the same, bit for bit."""
    scale = np.broadcast_to(np.asarray(scale, dtype=float), np.shape(floor))
    cut = floor / scale
    for _ in range(CUTOFF_STEPS):  # a step below the rounded quotient is enough
        over = scale * cut > floor
        cut = np.where(over, np.nextafter(cut, -np.inf), cut)
    # Never reached for a finite positive scale; no cutoff (the full search) is always right.
    return np.where(scale * cut > floor, -np.inf, cut)


CUTOFF_STEPS = 4
"""Steps down from floor/scale that :func:`_cutoff` takes at most."""


def site_gradients(points, lfs, labels, kind, normals, slope: float):
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
    few = min(SLOPE_NEIGHBOURS + 1, count)
    for start in range(0, count, GRADIENT_BLOCK):
        rows = np.arange(start, min(start + GRADIENT_BLOCK, count))
        # One query per site: the face sites' FIT_NEIGHBOURS nearest hold the SLOPE_NEIGHBOURS
        # nearest (the k-d tree returns them by distance).
        face = kind[rows] == 1
        dist, near = np.zeros((len(rows), k)), np.zeros((len(rows), k), dtype=np.int64)
        for mine, width in ((face, k), (~face, few)):
            if mine.any():
                found = tree.query(points[rows[mine]], k=width, workers=thread_count())
                dist[mine, :width], near[mine, :width] = found
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.abs(lfs[near[:, 1:few]] - lfs[rows, None]) / dist[:, 1:few]
        slopes[rows] = np.minimum(np.where(np.isfinite(ratio), ratio, 0.0).max(axis=1), slope)
        # A plane only where L changes: elsewhere it would move the value by less than
        # PLANE_MIN_RATE times the piece radius.
        fit = face & (slopes[rows] > PLANE_MIN_RATE * slope)
        rows, near = rows[fit], near[fit][:, 1:]
        if not len(rows):
            continue
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


def vertex_radius(faces, radius_face, vertices, count: int) -> np.ndarray:
    """Smallest radius of curvature of the faces around each vertex."""
    per_vertex = np.full(count, np.inf)
    np.minimum.at(per_vertex, faces.reshape(-1), np.repeat(radius_face, 3))
    return per_vertex[vertices]
