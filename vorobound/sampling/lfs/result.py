"""The result of the estimate of L (:mod:`.estimate`): :class:`LfsEstimate` in the input's
units, with its warnings (defects of the mesh, disagreement of the two estimators, sharp
features, coarse curved patches).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np

from ...errors import InputError, VoroboundError
from ...mesh import TriangleMesh
from ..surfaces.base import SurfaceCounts
from .features import feature_integrals
from .lipschitz import Envelope
from .mesh_quality import MeshReport, PreparedMesh
from .patches import Patches
from .poles import Midpoints
from .rounds import Rounds
from .sites import Sites, field_of

COARSE_EDGE_RATIO = 0.5
"""An edge of a curved patch longer than COARSE_EDGE_RATIO·L is reported as coarse: the
curvature and poles there rest on interpolated normals (docs/lfs.md)."""

DISAGREE_RATIO = 2.0
"""The medial estimate above DISAGREE_RATIO times the thickness and curvature bound at more
than DISAGREE_SHARE of the face sites is reported (L uses the bound there)."""

DISAGREE_SHARE = 0.01


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

    @property
    def _sites(self) -> Sites:
        """The sites (an estimate made by :func:`~.estimate.estimate_lfs` always has them)."""
        if self.sites is None:
            raise InputError(f"mesh {self.mesh.name}: this estimate keeps no sites")
        return self.sites

    @cached_property
    def _field(self) -> Envelope:
        return field_of(self._sites, self.lipschitz)

    def surface(self) -> SurfaceCounts:
        """Area and ∫ dA/L² from the face sites (:class:`SurfaceCounts`, what the advice
        needs)."""
        sites = self._sites
        face = sites.kind == 1
        areas, lfs = sites.areas[face], sites.lfs[face]
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


def build_result(
    mesh: TriangleMesh,
    prepared: PreparedMesh,
    patches: Patches,
    midpoints: Midpoints,
    sharp_angle: float,
    slope: float,
    rounds: Rounds,
) -> LfsEstimate:
    """The :class:`LfsEstimate` in the input's units, with its warnings (given by
    :func:`~.estimate.estimate_lfs`), from the last of the ``rounds`` (its sites, poles, field
    and L at the vertices)."""
    sites, poles, envelope = rounds.sites, rounds.poles, rounds.field
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
        cap_points=scale * sites.cap_points + centre,
        cap_values=scale * sites.cap_values,
        cap_radii=scale * sites.cap_radii,
    )
    # A vertex is a site: its output is its own L (the envelope of the raw values there).
    # `at` spreads each site's value over its piece, so at a vertex it is at most this (lower
    # where a neighbouring face site's value is; docs/lfs.md). Vertices of no face get `at`.
    vertex_lfs = rounds.at_vertices.copy()
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
    disagreement: dict[str, Any] = {"face_sites": int(face.sum()), "compared": int(both.sum())}
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
    feature_length, feature_inv = feature_integrals(
        prepared.points, patches.feature_edges, envelope
    )
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
        method=_method(len(midpoints.points), patches, rounds.count),
        patches=patches.count,
        feature_edges=len(patches.feature_edges),
        feature_length=feature_length,
        feature_inv_lfs=feature_inv,
        rounds=rounds.count,
        disagreement=disagreement,
        sites=lfs_sites,
    )


def _method(added: int, patches: Patches, rounds: int) -> str:
    sample = "vertices"
    if added:
        sample += f", {added:,} fitted edge midpoints"
    return (
        f"piecewise-smooth L over {patches.count} patches: min of the distance to the Voronoi "
        f"poles (Amenta-Bern) of the {sample} and face sites, half the thickness along the "
        f"normal, the radius of curvature, and the feature sizes; {rounds} rounds of face sites"
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
