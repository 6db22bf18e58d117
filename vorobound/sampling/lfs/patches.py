"""A mesh as a piecewise-smooth surface: smooth patches separated by sharp features.

Two faces belong to the same patch when they share an edge of exactly two faces whose normals
differ by at most the sharp angle. Every other edge (sharper, on the boundary, or of three or
more faces) is a *feature edge*. Feature edges form *feature curves*: chains through the
vertices where exactly two of them meet without turning by more than the sharp angle; every
other vertex of a feature edge is a *corner*. Two patches are *adjacent* when they share a
vertex, two curves when they share a corner.

The local feature size of docs/lfs.md is defined on this structure: medial balls that touch
two adjacent patches are the ones a sharp feature creates, and they are left out.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...mesh.rows import unique_rows
from .mesh_quality import PreparedMesh, dihedral_angles, face_normals

FLAT_TOLERANCE = 1e-9
"""A patch is flat when every face normal is within this (radians, about) of the first one's
line."""


@dataclass(frozen=True)
class Patches:
    """The smooth patches, feature curves and corners of a prepared mesh."""

    face_patch: np.ndarray
    """(f,) patch of each face of ``prepared.triangles``."""
    count: int
    """Number of patches."""
    adjacent: np.ndarray
    """(count, count) True for two different patches that share a vertex."""
    flat: np.ndarray
    """(count,) True for a planar patch."""
    corner_normals: np.ndarray
    """(f, 3, 3) unit normal line at each face corner, averaged over the faces of its vertex
    in the same patch (one normal per vertex and patch; the sign follows the face)."""
    feature_edges: np.ndarray
    """(e, 2) vertex pairs of the feature edges."""
    edge_curve: np.ndarray
    """(e,) feature curve of each feature edge."""
    curves: int
    curve_adjacent: np.ndarray
    """(curves, curves) True for two different curves that share a corner."""
    corners: np.ndarray
    """Vertex indices of the corners."""
    feature_vertex: np.ndarray
    """(m,) True for vertices on a feature edge."""
    vertex_curvature_radius: np.ndarray
    """(m,) radius of the circle through a feature vertex and its two neighbours on its curve
    (inf at corners, where a curve is straight, and off the features)."""
    sharp_edges: np.ndarray
    """(s, 2) vertex pairs of the edges sharper than the sharp angle (a subset of the
    feature edges)."""
    max_dihedral: float


def find_patches(prepared: PreparedMesh, sharp_angle: float) -> Patches:
    """Split ``prepared`` into smooth patches at edges sharper than ``sharp_angle`` degrees."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    faces = prepared.triangles
    angles = dihedral_angles(prepared)
    two = prepared.edge_faces[:, 0] >= 0
    smooth = two & (np.nan_to_num(angles, nan=180.0) <= sharp_angle)
    sharp = two & ~smooth
    pairs = prepared.edge_faces[smooth]
    graph = coo_matrix(
        (np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(len(faces), len(faces))
    )
    count, face_patch = connected_components(graph, directed=False)
    feature = ~smooth
    feature_edges = prepared.edges[feature]
    adjacent = _patch_adjacency(faces, face_patch, count, len(prepared.points))
    normals, _ = face_normals(prepared.points, faces)
    flat = _flat_patches(normals, face_patch, count)
    corner_normals = _patch_vertex_normals(prepared.points, faces, face_patch)
    curves, edge_curve, corners, curve_adjacent, radius = _feature_curves(
        prepared.points, feature_edges, sharp_angle
    )
    on_feature = np.zeros(len(prepared.points), dtype=bool)
    on_feature[feature_edges.reshape(-1)] = True
    max_dihedral = float(np.nanmax(angles)) if np.isfinite(angles).any() else 0.0
    return Patches(
        face_patch=face_patch,
        count=int(count),
        adjacent=adjacent,
        flat=flat,
        corner_normals=corner_normals,
        feature_edges=feature_edges,
        edge_curve=edge_curve,
        curves=curves,
        curve_adjacent=curve_adjacent,
        corners=corners,
        feature_vertex=on_feature,
        vertex_curvature_radius=radius,
        sharp_edges=prepared.edges[sharp],
        max_dihedral=max_dihedral,
    )


def _patch_adjacency(faces, face_patch, count: int, vertices: int) -> np.ndarray:
    """Patches sharing a vertex (a dense boolean matrix: CAD parts have few patches)."""
    vertex = faces.reshape(-1)
    patch = np.repeat(face_patch, 3)
    pairs = unique_rows(np.c_[vertex, patch])
    adjacent = np.zeros((count, count), dtype=bool)
    starts = np.flatnonzero(np.r_[True, pairs[1:, 0] != pairs[:-1, 0]])
    sizes = np.diff(np.r_[starts, len(pairs)])
    for start, size in zip(starts[sizes > 1], sizes[sizes > 1], strict=True):
        group = pairs[start : start + size, 1]
        adjacent[np.ix_(group, group)] = True
    np.fill_diagonal(adjacent, False)
    return adjacent


def _flat_patches(normals, face_patch, count: int) -> np.ndarray:
    """True for patches whose face normals all lie on one line."""
    first = np.full(count, -1)
    first[face_patch[::-1]] = np.arange(len(face_patch))[::-1]
    reference = normals[first[face_patch]]
    cosine = np.abs((normals * reference).sum(axis=1))
    flat = np.ones(count, dtype=bool)
    np.logical_and.at(flat, face_patch, cosine >= 1 - FLAT_TOLERANCE)
    return flat


def _patch_vertex_normals(points, faces, face_patch) -> np.ndarray:
    """Per face corner: the normal line of its vertex within its patch.

    Max's weights (each face's cross product over the squared lengths of its two edges at the
    vertex), every face first turned to agree with the face it is summed into, so that faces
    of opposite orientation do not cancel. The result keeps each face's own sign.
    """
    unit, areas = face_normals(points, faces)
    key = np.c_[faces.reshape(-1), np.repeat(face_patch, 3)]
    _, group = unique_rows(key, return_inverse=True)
    group = group.reshape(-1, 3)
    corners = points[faces]
    # A reference line per (vertex, patch): the area-weighted principal direction.
    moments = np.zeros((group.max() + 1, 3, 3))
    outer = areas[:, None, None] * unit[:, :, None] * unit[:, None, :]
    for corner in range(3):
        np.add.at(moments, group[:, corner], outer)
    axis = np.linalg.eigh(moments)[1][:, :, -1]
    total = np.zeros((len(moments), 3))
    for corner in range(3):
        first = corners[:, (corner + 1) % 3] - corners[:, corner]
        second = corners[:, (corner + 2) % 3] - corners[:, corner]
        weight = 2 * areas / ((first * first).sum(axis=1) * (second * second).sum(axis=1))
        sign = np.where((unit * axis[group[:, corner]]).sum(axis=1) < 0, -1.0, 1.0)
        np.add.at(total, group[:, corner], unit * (weight * sign)[:, None])
    length = np.linalg.norm(total, axis=1)
    total[length == 0] = axis[length == 0]
    total /= np.linalg.norm(total, axis=1)[:, None]
    per_corner = total[group]  # (f, 3, 3)
    # Give every corner normal the sign of its own face.
    agree = np.einsum("fkd,fd->fk", per_corner, unit)
    return np.where((agree < 0)[..., None], -per_corner, per_corner)


def _feature_curves(points, edges: np.ndarray, sharp_angle: float):
    """Curves (chains of feature edges between corners), corners, curve adjacency, and the
    radius of the circle through each feature vertex and its two curve neighbours."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    count = len(points)
    radius = np.full(count, np.inf)
    if len(edges) == 0:
        empty = np.zeros(0, dtype=np.int64)
        return 0, empty, empty, np.zeros((0, 0), dtype=bool), radius
    degree = np.bincount(edges.reshape(-1), minlength=count)
    corner = (degree > 0) & (degree != 2)
    # Degree-2 vertices: the turning angle between their two edges decides.
    ends = np.c_[edges[:, 0], edges[:, 1]].reshape(-1)
    other = np.c_[edges[:, 1], edges[:, 0]].reshape(-1)
    order = np.argsort(ends, kind="stable")
    ends, other = ends[order], other[order]
    two = np.flatnonzero(degree[ends] == 2)
    first = two[::2]  # each degree-2 vertex appears twice in a row
    vertex = ends[first]
    a, b = other[first], other[first + 1]
    incoming = points[vertex] - points[a]
    outgoing = points[b] - points[vertex]
    cosine = (incoming * outgoing).sum(axis=1) / (
        np.linalg.norm(incoming, axis=1) * np.linalg.norm(outgoing, axis=1)
    )
    turning = np.degrees(np.arccos(np.clip(cosine, -1, 1)))
    corner[vertex[turning > sharp_angle]] = True
    smooth = ~corner[vertex]
    chord = np.linalg.norm(points[b] - points[a], axis=1)
    sine = np.sin(np.radians(turning))
    with np.errstate(divide="ignore", invalid="ignore"):
        circle = np.where(sine > 1e-12, chord / (2 * sine), np.inf)
    radius[vertex[smooth]] = circle[smooth]
    # Edges are joined through their non-corner ends.
    joined = []
    for side in (0, 1):
        through = ~corner[edges[:, side]]
        joined.append(np.c_[np.flatnonzero(through), edges[through, side]])
    links = np.concatenate(joined)
    shared: dict[int, int] = {}
    joins: list[tuple[int, int]] = []
    for edge, v in links.tolist():
        if v in shared:
            joins.append((shared[v], edge))
        else:
            shared[v] = edge
    pairs = np.array(joins, dtype=np.int64).reshape(-1, 2)
    graph = coo_matrix(
        (np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(len(edges), len(edges))
    )
    curves, edge_curve = connected_components(graph, directed=False)
    corners = np.flatnonzero(corner)
    curve_adjacent = np.zeros((curves, curves), dtype=bool)
    for c in corners:
        touching = np.unique(edge_curve[(edges == c).any(axis=1)])
        curve_adjacent[np.ix_(touching, touching)] = True
    np.fill_diagonal(curve_adjacent, False)
    return int(curves), edge_curve, corners, curve_adjacent, radius
