"""Checks and clean-up of a triangle mesh before its local feature size is estimated.

:func:`prepare_mesh` refuses what cannot be measured (no triangles, NaN coordinates, faces
naming missing vertices, no face with area) and reports, without refusing, what still allows a
meaningful estimate: duplicate vertices (merged), degenerate faces (ignored), boundary edges
(an open surface), edges shared by more than two faces, inconsistent face orientation.
It also gives orientation-free vertex normals and the sharp edges (large dihedral angles).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from ...errors import InputError
from ...mesh import TriangleMesh, has_area
from ...mesh.rows import row_keys, unique_rows


@dataclass(frozen=True)
class MeshReport:
    """What :func:`prepare_mesh` found; each count is reported, none is fatal."""

    vertices: int
    triangles: int
    duplicate_vertices: int
    """Vertices with the same coordinates as an earlier one (merged)."""
    degenerate_triangles: int
    """Faces with a repeated vertex or no area (ignored)."""
    unreferenced_vertices: int
    """Vertices of no usable face (not part of the surface sample)."""
    boundary_edges: int
    """Edges of one face only: the surface is open there."""
    nonmanifold_edges: int
    """Edges of three or more faces."""
    inconsistent_edges: int
    """Edges whose two faces are oriented against each other."""
    pinched_vertices: np.ndarray = field(default_factory=lambda: np.empty(0, dtype=np.int64))
    """Non-manifold vertices (indices into the merged vertices): the faces around each form
    more than one fan, joined through no edge (two parts touching at a point, where the local
    feature size is 0)."""
    nonmanifold_edge_vertices: np.ndarray = field(
        default_factory=lambda: np.empty((0, 2), dtype=np.int64)
    )
    """The two vertices (merged indices) of each edge of three or more faces."""

    def problems(self) -> list[str]:
        """One sentence per defect found (empty for a clean closed manifold mesh)."""
        found = []
        if self.duplicate_vertices:
            found.append(f"{self.duplicate_vertices} duplicate vertices were merged")
        if self.degenerate_triangles:
            found.append(f"{self.degenerate_triangles} degenerate faces (no area) were ignored")
        if self.unreferenced_vertices:
            found.append(
                f"{self.unreferenced_vertices} vertices belong to no face: they are not used as "
                "samples (their L is evaluated like any other point)"
            )
        if self.boundary_edges:
            found.append(
                f"the mesh is open ({self.boundary_edges} boundary edges): VoroCrust needs a "
                "closed surface, and L near the boundary depends on the mesh resolution"
            )
        if self.nonmanifold_edges:
            found.append(
                f"{self.nonmanifold_edges} edges are shared by more than two faces "
                "(non-manifold): L near them depends on the mesh resolution"
            )
        if self.inconsistent_edges:
            found.append(
                f"{self.inconsistent_edges} edges join faces of opposite orientation "
                "(the estimate does not depend on orientation)"
            )
        return found


@dataclass(frozen=True)
class PreparedMesh:
    """A mesh with duplicates merged and degenerate faces dropped, and its edge topology."""

    points: np.ndarray
    """Distinct vertices (m, 3), in units of the bounding-box diagonal about its centre."""
    centre: np.ndarray
    """Centre of the input's bounding box: input = centre + scale · points."""
    scale: float
    """Diagonal of the input's bounding box."""
    triangles: np.ndarray
    """Faces with area (f, 3), indices into ``points``."""
    original_to_merged: np.ndarray
    """For each input vertex, its index in ``points``."""
    edges: np.ndarray
    """Distinct edges (e, 2), smaller index first."""
    edge_faces: np.ndarray
    """For edges of exactly two faces: those faces (e, 2); −1 elsewhere."""
    edge_consistent: np.ndarray
    """For two-face edges: True when the faces run through the edge in opposite directions."""
    report: MeshReport

    @cached_property
    def mesh(self) -> TriangleMesh:
        """The merged vertices and faces with area as a mesh object (its derived data, such as
        edge lengths and vertex tables, computed once)."""
        return TriangleMesh(self.points, self.triangles, "prepared")


def prepare_mesh(mesh: TriangleMesh) -> PreparedMesh:
    """Validate ``mesh``, merge duplicate vertices, drop faces without area, find edge topology.

    Raises
    ------
    InputError
        No vertices or faces, non-finite coordinates, faces naming missing vertices, or no face
        with area.
    """
    points = np.asarray(mesh.points, dtype=float)
    faces = np.asarray(mesh.triangles)
    name = mesh.name
    if points.ndim != 2 or points.shape[1] != 3 or len(points) == 0:
        raise InputError(f"mesh {name}: need vertices of shape (n, 3), got {points.shape}")
    if faces.ndim != 2 or faces.shape[1] != 3 or len(faces) == 0:
        raise InputError(f"mesh {name} has no triangles")
    if not np.issubdtype(faces.dtype, np.integer):
        raise InputError(f"mesh {name}: face indices must be integers")
    if not np.isfinite(points).all():
        raise InputError(f"mesh {name}: some vertex coordinates are NaN or infinite")
    if faces.min() < 0 or faces.max() >= len(points):
        raise InputError(f"mesh {name}: a face refers to a vertex that does not exist")
    centre, scale = _frame(points, name)
    unique, merged = np.unique(points, axis=0, return_inverse=True)
    unique = (unique - centre) / scale  # the difference is exact: no digits lost far out
    merged = merged.reshape(-1)
    faces = merged[faces]
    keep = has_area(unique, faces)
    if not keep.any():
        raise InputError(f"mesh {name}: every triangle is degenerate (no area)")
    good = faces[keep]
    edges, edge_faces, consistent, counts = _edge_topology(good)
    report = MeshReport(
        vertices=len(points),
        triangles=len(faces),
        duplicate_vertices=len(points) - len(unique),
        degenerate_triangles=int((~keep).sum()),
        unreferenced_vertices=len(unique) - len(np.unique(good)),
        boundary_edges=int((counts == 1).sum()),
        nonmanifold_edges=int((counts > 2).sum()),
        inconsistent_edges=int(((counts == 2) & ~consistent).sum()),
        pinched_vertices=pinched_vertices(good, len(unique)),
        nonmanifold_edge_vertices=edges[counts > 2],
    )
    return PreparedMesh(unique, centre, scale, good, merged, edges, edge_faces, consistent, report)


def _frame(points: np.ndarray, name: str) -> tuple[np.ndarray, float]:
    """Centre and diagonal of the bounding box, computed without overflow."""
    low, high = points.min(axis=0), points.max(axis=0)
    centre = low / 2 + high / 2
    half = high / 2 - low / 2
    peak = float(np.abs(half).max())
    scale = 2 * peak * float(np.linalg.norm(half / peak)) if peak > 0 else 0.0
    if not (np.isfinite(scale) and scale > 0):
        raise InputError(f"mesh {name}: its vertices do not span a measurable region")
    return centre, scale


def face_normals(points: np.ndarray, triangles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit normals (f, 3) of faces with area, and their areas (f,)."""
    corners = points[triangles]
    cross = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    double_area = np.linalg.norm(cross, axis=1)
    return cross / double_area[:, None], 0.5 * double_area


def vertex_normals(prepared: PreparedMesh) -> np.ndarray:
    """Unit normal line per vertex, blind to face orientation (sign arbitrary).

    Max's weights (each face's cross product divided by the squared lengths of its two edges at
    the vertex; exact for vertices on a sphere), summed after orienting every face along the
    principal axis of its vertex's area-weighted face normals, so that faces of opposite
    orientation do not cancel. Vertices of no face get (0, 0, 1).

    References
    ----------
    N. Max, "Weights for computing vertex normals from facet normals", J. Graphics Tools (1999).
    """
    points, faces = prepared.points, prepared.triangles
    unit, areas = face_normals(points, faces)
    outer = areas[:, None, None] * unit[:, :, None] * unit[:, None, :]
    moments = np.zeros((len(points), 3, 3))
    for corner in range(3):
        np.add.at(moments, faces[:, corner], outer)
    moments[np.abs(moments).sum(axis=(1, 2)) == 0] = np.diag([0.0, 0.0, 1.0])
    axis = np.linalg.eigh(moments)[1][:, :, -1]
    corners = points[faces]
    total = np.zeros_like(points)
    for corner in range(3):
        vertex = faces[:, corner]
        first = corners[:, (corner + 1) % 3] - corners[:, corner]
        second = corners[:, (corner + 2) % 3] - corners[:, corner]
        weight = 2 * areas / ((first * first).sum(axis=1) * (second * second).sum(axis=1))
        sign = np.where((unit * axis[vertex]).sum(axis=1) < 0, -1.0, 1.0)
        np.add.at(total, vertex, unit * (weight * sign)[:, None])
    length = np.linalg.norm(total, axis=1)
    total[length == 0] = axis[length == 0]
    return total / np.linalg.norm(total, axis=1)[:, None]


def dihedral_angles(prepared: PreparedMesh) -> np.ndarray:
    """Angle in degrees between the normals of the two faces of each edge (0 = flat).

    NaN for edges that do not have exactly two faces. A face pair of opposite orientation is
    measured as if one face were flipped.
    """
    normals, _ = face_normals(prepared.points, prepared.triangles)
    angles = np.full(len(prepared.edges), np.nan)
    two = prepared.edge_faces[:, 0] >= 0
    first, second = normals[prepared.edge_faces[two, 0]], normals[prepared.edge_faces[two, 1]]
    cosine = (first * second).sum(axis=1) * np.where(prepared.edge_consistent[two], 1.0, -1.0)
    angles[two] = np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0)))
    return angles


def pinched_vertices(faces: np.ndarray, count: int) -> np.ndarray:
    """Vertices whose faces form more than one fan (faces around a vertex are one fan when
    they are joined through edges at that vertex): where parts of the surface touch at a
    point, not across an edge (two tetrahedra sharing a vertex)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    corner = np.arange(faces.size).reshape(-1, 3)  # one node per (face, vertex)
    rows = []
    for a, b in ((0, 1), (1, 2), (2, 0)):
        key = np.sort(faces[:, [a, b]], axis=1)
        # Both ends of each edge: (edge, vertex at the end, the face's corner there).
        rows.append(np.c_[key, faces[:, a], corner[:, a]])
        rows.append(np.c_[key, faces[:, b], corner[:, b]])
    table = np.concatenate(rows)
    keys = row_keys(table[:, :3])
    if keys is None:
        table = table[np.lexsort(table[:, :3].T[::-1])]
        same = (table[1:, :3] == table[:-1, :3]).all(axis=1)
    else:  # the same order: both sorts are stable
        order = np.argsort(keys, kind="stable")
        table, keys = table[order], keys[order]
        same = keys[1:] == keys[:-1]
    graph = coo_matrix(
        (np.ones(int(same.sum())), (table[:-1][same, 3], table[1:][same, 3])),
        shape=(faces.size, faces.size),
    )
    _, fan = connected_components(graph, directed=False)
    vertex = faces.reshape(-1)
    pairs = unique_rows(np.c_[vertex, fan])
    fans = np.bincount(pairs[:, 0], minlength=count)
    return np.flatnonzero(fans > 1)


def _edge_topology(faces: np.ndarray):
    """Distinct edges, their two faces (−1 unless exactly two), orientation agreement, counts."""
    start = faces.reshape(-1)
    end = faces[:, [1, 2, 0]].reshape(-1)
    face = np.repeat(np.arange(len(faces)), 3)
    pairs = np.sort(np.c_[start, end], axis=1)
    edges, inverse, counts = unique_rows(pairs, return_inverse=True, return_counts=True)
    order = np.argsort(inverse, kind="stable")
    first_slot = np.r_[0, np.cumsum(counts)[:-1]]
    edge_faces = np.full((len(edges), 2), -1)
    two = counts == 2
    slots = first_slot[two]
    edge_faces[two, 0] = face[order[slots]]
    edge_faces[two, 1] = face[order[slots + 1]]
    forward = start < end
    consistent = np.zeros(len(edges), dtype=bool)
    consistent[two] = forward[order[slots]] != forward[order[slots + 1]]
    return edges, edge_faces, consistent, counts
