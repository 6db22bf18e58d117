"""Local feature size L (distance to the medial axis) of the surface a triangle mesh samples.

The surface sample is every mesh vertex (a random subset leaves holes whose poles sit near the
surface) plus, up to a sample size ``samples``, edge midpoints placed on a smooth surface fitted
to the vertices (:mod:`.curved`; midpoints on the flat triangles would lie off the surface by
about h²/(8L) and shrink the estimate by tens of percent, docs/lfs.md). The sample's Voronoi
poles (:mod:`.medial`) approximate the medial axis, and L at a point is its distance to the
nearest pole: a distance to a set, hence 1-Lipschitz everywhere. For a Lipschitz constant
λ < 1 the vertex values are then lowered to the largest λ-Lipschitz function below them
(:mod:`.lipschitz`).

Edges whose dihedral angle exceeds ``sharp_angle`` are reported: there the mesh is not a
sample of a smooth surface, nothing is fitted near them, and the estimate is that of the
surface rounded at the scale of the mesh edges.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from ..bounds.params import LIPSCHITZ_RANGE
from ..checks import checked_number, checked_seed
from ..errors import InputError, VoroboundError, VoroboundWarning
from ..progress import Counter, Progress
from .curved import edge_midpoints
from .lipschitz import lipschitz_envelope
from .medial import vertex_poles
from .mesh_io import TriangleMesh
from .mesh_quality import MeshReport, dihedral_angles, prepare_mesh, vertex_normals
from .surfaces import Surface, surface_from_mesh_areas

SHARP_ANGLE = 30.0
"""Default threshold (degrees) on the angle between the normals of two adjacent faces above
which their edge is sharp (VTK's and ParaView's default feature angle)."""
COARSE_EDGE_RATIO = 0.5
"""A vertex with an incident edge longer than COARSE_EDGE_RATIO·L is reported as too coarse:
the error of the estimate grows like (edge/L)² (docs/lfs.md)."""
FLAT_RTOL = 1e-9
"""Vertices whose spread across their best plane is below FLAT_RTOL times their extent are
coplanar."""
AUTO_SAMPLES = 60_000
"""Without a sample size, every edge gets a midpoint if the sample then has at most
AUTO_SAMPLES points (a closed mesh has about three edges per vertex: meshes of up to about
15 000 vertices), and none otherwise. The midpoints matter on coarse meshes, and the time grows
faster than the sample (docs/lfs.md measures both)."""


@dataclass(frozen=True)
class LfsEstimate:
    """Estimated local feature size at the vertices of a mesh, and at any point via :meth:`at`."""

    mesh: TriangleMesh
    lfs: np.ndarray
    """L at each vertex of ``mesh`` (in its order), λ-Lipschitz."""
    lipschitz: float
    """λ: |L(x) − L(y)| ≤ λ|x − y| for all points (1 for the distance to the medial axis)."""
    medial_points: np.ndarray
    """The estimated medial axis: distinct Voronoi poles (k, 3)."""
    sample_count: int
    """Size of the surface sample: distinct vertices on faces with area, plus added points."""
    added_samples: int
    """Edge midpoints on the fitted surface in the sample."""
    eligible_edges: int
    """Edges that could get a midpoint (usable fits at both ends, away from sharp, boundary and
    non-manifold edges); 0 when the sample size asked for no midpoints."""
    sharp_edges: np.ndarray
    """Vertex index pairs (e, 2) of the edges sharper than ``sharp_angle``."""
    sharp_angle: float
    max_dihedral: float
    """Largest angle (degrees) between the normals of adjacent faces."""
    mesh_report: MeshReport
    warnings: tuple[str, ...]
    method: str
    _sites: np.ndarray = field(default=None, repr=False)
    """Vertices of the surface (sites of the λ < 1 envelope)."""

    def at(self, points) -> np.ndarray:
        """L at arbitrary points (m, 3): the same function whose vertex values are ``lfs``.

        For λ ≥ 1 it is the distance to the nearest medial point; for λ < 1 it is
        min over surface vertices v of L(v) + λ|x − v|.
        """
        points = np.asarray(points, dtype=float)
        if points.ndim != 2 or points.shape[1] != 3 or not np.isfinite(points).all():
            raise InputError(f"need finite points of shape (m, 3), got shape {points.shape}")
        if self.lipschitz >= 1:
            return self._medial_tree.query(points, workers=-1)[0]
        site_lfs = self.lfs[self._sites]
        return lipschitz_envelope(self.mesh.points[self._sites], site_lfs, self.lipschitz, points)

    def surface(self) -> Surface:
        """The advisor's :class:`Surface`: each triangle with the mean L of its vertices."""
        tri_lfs = self.lfs[self.mesh.triangles].mean(axis=1)
        return surface_from_mesh_areas(self.mesh.name, self.mesh.triangle_areas(), tri_lfs)

    @cached_property
    def _medial_tree(self):
        from scipy.spatial import cKDTree

        return cKDTree(self.medial_points)


def estimate_lfs(
    mesh: TriangleMesh,
    *,
    samples: int | None = None,
    lipschitz: float = 1.0,
    sharp_angle: float = SHARP_ANGLE,
    seed: int = 0,
    progress: Progress | None = None,
) -> LfsEstimate:
    """Estimate the local feature size at the vertices of a triangle mesh.

    Parameters
    ----------
    mesh : TriangleMesh
        The surface; vertices should lie on the smooth surface it approximates.
    samples : int, optional
        Size N ≥ 0 of the surface sample. Every vertex is in it; when N exceeds their number,
        up to N − (vertices) edge midpoints on the fitted surface are added, longest edges
        first, at most one per edge and none near sharp, boundary or non-manifold edges.
        0 (or any N up to the vertex count): the vertices only. None: every eligible edge
        gets a midpoint if that makes at most AUTO_SAMPLES points, else none.
    lipschitz : float
        λ > 0. The distance to the estimated medial axis is 1-Lipschitz; for λ < 1 the values
        become min_y L(y) + λ|x − y| over the vertices y.
    sharp_angle : float
        Edges whose adjacent face normals differ by more than this (degrees) are sharp.
    seed : int
        Seed of the triangulation's jitter.
    progress : Progress, optional
        Progress callback (tasks "surface fit", "Delaunay", "poles", "distances",
        "Lipschitz repair").

    Returns
    -------
    LfsEstimate

    Raises
    ------
    InputError
        Empty or invalid mesh, NaN coordinates, coplanar vertices, bad parameters.

    References
    ----------
    Local feature size and ε-samples as in Section 4.1 of "Analytic formula for the difference
    of the circumradius and orthoradius of a weighted triangle"; poles from Amenta & Bern (1999).
    """
    if samples is not None and (
        isinstance(samples, bool) or not isinstance(samples, int | np.integer) or samples < 0
    ):
        raise InputError(f"--samples must be a whole number ≥ 0, got {samples!r}")
    lipschitz = checked_number(lipschitz, "lipschitz", *LIPSCHITZ_RANGE)
    if not (math.isfinite(sharp_angle) and 0 < sharp_angle < 180):
        raise InputError(f"--sharp-angle must be between 0 and 180 degrees, got {sharp_angle}")
    seed = checked_seed(seed)
    prepared = prepare_mesh(mesh)
    points = prepared.points
    surface_ids = np.unique(prepared.triangles)
    if len(surface_ids) < 5:
        raise InputError(f"mesh {mesh.name}: need at least 5 vertices on faces with area")
    unit, centre, scale = points, prepared.centre, prepared.scale
    _refuse_flat(unit[surface_ids], mesh.name)
    angles = dihedral_angles(prepared)
    sharp = np.nan_to_num(angles, nan=0.0) > sharp_angle
    normals = vertex_normals(prepared)
    counter = Counter(progress, "surface fit", 1)
    added = edge_midpoints(
        prepared,
        normals,
        sharp | (prepared.edge_faces[:, 0] < 0),
        _budget(samples, len(surface_ids), len(prepared.edges)),
    )
    counter.step()
    medial = vertex_poles(
        np.vstack([unit[surface_ids], added.points]),
        np.vstack([normals[surface_ids], added.normals]),
        noise=_rounding(mesh.points) / scale,
        seed=seed,
        progress=progress,
    )
    if len(medial.points) == 0:
        raise VoroboundError(f"mesh {mesh.name}: no medial-axis point found (is it a surface?)")
    from scipy.spatial import cKDTree

    counter = Counter(progress, "distances", 1)
    merged_lfs = cKDTree(medial.points).query(unit, workers=-1)[0]
    counter.step()
    if lipschitz < 1:
        merged_lfs = lipschitz_envelope(
            unit[surface_ids], merged_lfs[surface_ids], lipschitz, unit, progress
        )
    if not (np.isfinite(merged_lfs).all() and (merged_lfs > 0).all()):
        raise VoroboundError(f"mesh {mesh.name}: the estimated L is zero at some vertex")
    max_dihedral = float(np.nanmax(angles)) if np.isfinite(angles).any() else 0.0
    # Report vertex ids of the caller's mesh: the first input vertex of each merged one.
    first_input = np.zeros(len(points), dtype=np.int64)
    first_input[prepared.original_to_merged[::-1]] = np.arange(len(mesh.points))[::-1]
    notes = prepared.report.problems()
    if sharp.any():
        notes.append(
            f"{int(sharp.sum())} sharp edges (face normals differ by more than {sharp_angle:g}°, "
            f"up to {max_dihedral:.1f}°): the paper's analysis covers smooth surfaces only; "
            "near them L is that of the surface rounded at the scale of the mesh edges"
        )
    notes += _coarse(prepared, merged_lfs, sharp)
    for note in notes:
        warnings.warn(f"mesh {mesh.name}: {note}", VoroboundWarning, stacklevel=2)
    merged_to_sites = np.asarray(first_input[surface_ids])
    return LfsEstimate(
        mesh=mesh,
        lfs=scale * merged_lfs[prepared.original_to_merged],
        lipschitz=float(min(lipschitz, 1.0)),
        medial_points=scale * medial.points + centre,
        sample_count=len(surface_ids) + len(added.points),
        added_samples=len(added.points),
        eligible_edges=added.eligible,
        sharp_edges=first_input[prepared.edges[sharp]],
        sharp_angle=float(sharp_angle),
        max_dihedral=max_dihedral,
        mesh_report=prepared.report,
        warnings=tuple(notes),
        method=_method(len(added.points)),
        _sites=merged_to_sites,
    )


def _budget(samples: int | None, vertices: int, edges: int) -> int:
    """How many midpoints to add at most."""
    if samples is not None:
        return int(samples) - vertices
    return edges if vertices + edges <= AUTO_SAMPLES else 0


def _method(added: int) -> str:
    sample = "the mesh vertices"
    if added:
        sample += f" and {added:,} edge midpoints on a quartic fit of the surface"
    return f"distance to the Voronoi poles (Amenta-Bern) of {sample}"


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


def _coarse(prepared, lfs: np.ndarray, sharp: np.ndarray) -> list[str]:
    """A note when some edge away from sharp edges is long compared with L at its ends."""
    edges = prepared.edges[~sharp]
    on_sharp = np.zeros(len(prepared.points), dtype=bool)
    on_sharp[prepared.edges[sharp].reshape(-1)] = True
    length = np.linalg.norm(prepared.points[edges[:, 0]] - prepared.points[edges[:, 1]], axis=1)
    ratio = length / np.minimum(lfs[edges[:, 0]], lfs[edges[:, 1]])
    bad = (ratio > COARSE_EDGE_RATIO) & ~on_sharp[edges].any(axis=1)
    if not bad.any():
        return []
    return [
        f"{int(bad.sum())} edges are longer than {COARSE_EDGE_RATIO:g}·L (up to "
        f"{float(ratio[bad].max()):.2f}·L): the mesh is too coarse there for an accurate "
        "estimate (the error grows like (edge/L)²)"
    ]
