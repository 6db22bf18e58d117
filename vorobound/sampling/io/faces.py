"""Quadrilateral and polygonal faces of a mesh split into triangles.

A quad is split along the diagonal whose two triangles face the same way (the one through the
reflex vertex of a non-convex quad), and of two such diagonals along the shorter one (better
shaped triangles). A larger polygon is fanned from its first vertex when every fan triangle
faces the way of the polygon's normal (Newell's), and otherwise cut into ears in its best-fit
plane. Triangles that repeat a vertex (a triangle stored as a quad with its last vertex twice,
as some exporters do) are dropped.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Triangulation:
    """Triangles of a set of faces, and what was done to get them (for the one-line note)."""

    triangles: np.ndarray
    """(m, 3) int64 vertex indices."""
    quads: int
    """Quadrilateral faces split."""
    polygons: int
    """Faces of five or more vertices split."""
    dropped: int
    """Triangles dropped because they repeat a vertex."""

    def note(self, name: str) -> str | None:
        """One line saying what was split, or None if every face was a triangle."""
        counts = ((self.quads, "quadrilateral"), (self.polygons, "polygonal"))
        parts = [f"{count:,} {kind}" for count, kind in counts if count]
        if not parts:
            return None
        dropped = f"; {self.dropped:,} with a repeated vertex dropped" if self.dropped else ""
        return (
            f"mesh {name}: {' and '.join(parts)} faces split into triangles "
            f"({len(self.triangles):,} triangles in all{dropped})"
        )


def triangulate(points: np.ndarray, blocks: list[np.ndarray]) -> Triangulation:
    """Triangles of face blocks (each (m, k) vertex indices with k ≥ 3) on ``points`` (n, 3)."""
    pieces = [np.zeros((0, 3), dtype=np.int64)]
    quads = polygons = dropped = 0
    for faces in blocks:
        corners = faces.shape[1]
        if corners == 3:
            pieces.append(faces)
            continue
        if corners == 4:
            split, quads = _split_quads(points, faces), quads + len(faces)
        else:
            split, polygons = _split_polygons(points, faces), polygons + len(faces)
        kept = _without_repeated_vertices(split)
        dropped += len(split) - len(kept)
        pieces.append(kept)
    triangles = np.concatenate(pieces).astype(np.int64)
    return Triangulation(triangles, quads, polygons, dropped)


def _without_repeated_vertices(triangles: np.ndarray) -> np.ndarray:
    a, b, c = triangles.T
    return triangles[(a != b) & (b != c) & (a != c)]


def _split_quads(points: np.ndarray, quads: np.ndarray) -> np.ndarray:
    """Two triangles per quad (module docstring: the consistent, then the shorter diagonal)."""
    p = points[quads]
    through_02 = _agreement(p[:, [0, 1, 2]], p[:, [0, 2, 3]])
    through_13 = _agreement(p[:, [0, 1, 3]], p[:, [1, 2, 3]])
    shorter_02 = np.linalg.norm(p[:, 2] - p[:, 0], axis=1) <= np.linalg.norm(
        p[:, 3] - p[:, 1], axis=1
    )
    use_02 = np.where(through_02 == through_13, shorter_02, through_02)
    first = np.where(use_02[:, None], quads[:, [0, 1, 2]], quads[:, [0, 1, 3]])
    second = np.where(use_02[:, None], quads[:, [0, 2, 3]], quads[:, [1, 2, 3]])
    return np.stack([first, second], axis=1).reshape(-1, 3)


def _agreement(first: np.ndarray, second: np.ndarray) -> np.ndarray:
    """Whether two triangles (…, 3 corners, 3) face the same way (normals at an acute angle)."""
    return np.einsum("ij,ij->i", _normals(first), _normals(second)) > 0


def _normals(triangles: np.ndarray) -> np.ndarray:
    return np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0])


def _newell_normals(polygons: np.ndarray) -> np.ndarray:
    """Area-weighted normals (m, 3) of polygons (m, k, 3), exact for planar ones (Newell)."""
    following = np.roll(polygons, -1, axis=1)
    return 0.5 * np.cross(polygons, following).sum(axis=1)


def _split_polygons(points: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """k − 2 triangles per polygon: a fan where it is valid, ears elsewhere."""
    corners = faces.shape[1]
    p = points[faces]
    normal = _newell_normals(p)
    fan = np.stack(
        [np.zeros(corners - 2, dtype=int), np.arange(1, corners - 1), np.arange(2, corners)],
        axis=1,
    )
    fan_normals = np.cross(p[:, fan[:, 1]] - p[:, fan[:, 0]], p[:, fan[:, 2]] - p[:, fan[:, 0]])
    fan_ok = (np.einsum("mtj,mj->mt", fan_normals, normal) > 0).all(axis=1)
    local = np.empty((len(faces), corners - 2, 3), dtype=np.int64)
    local[fan_ok] = fan
    for index in np.flatnonzero(~fan_ok):
        local[index] = _ear_clipping(p[index], normal[index])
    return faces[np.arange(len(faces))[:, None, None], local].reshape(-1, 3)


def _ear_clipping(polygon: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """Local indices (k − 2, 3) of an ear decomposition of one polygon (k, 3) in the plane
    across its normal; a polygon with no ear left (self-intersecting) is fanned."""
    drop = int(np.argmax(np.abs(normal)))
    axes = [axis for axis in range(3) if axis != drop]
    flat = polygon[:, axes]
    if normal[drop] < 0:  # counter-clockwise seen from the normal's side
        flat = flat[:, ::-1]
    remaining = list(range(len(polygon)))
    triangles = []
    while len(remaining) > 3:
        for position, vertex in enumerate(remaining):
            before = remaining[position - 1]
            after = remaining[(position + 1) % len(remaining)]
            if _cross(flat[before], flat[vertex], flat[after]) <= 0:
                continue  # reflex or flat corner
            others = [v for v in remaining if v not in (before, vertex, after)]
            if any(_inside(flat[v], flat[before], flat[vertex], flat[after]) for v in others):
                continue
            triangles.append((before, vertex, after))
            remaining.pop(position)
            break
        else:  # no ear: a self-intersecting polygon; fan the rest
            rest = remaining
            triangles += [(rest[0], rest[i], rest[i + 1]) for i in range(1, len(rest) - 1)]
            remaining = []
    if len(remaining) == 3:
        triangles.append((remaining[0], remaining[1], remaining[2]))
    return np.array(triangles, dtype=np.int64)


def _cross(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> float:
    return float((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))


def _inside(point, a, b, c) -> bool:
    """Whether ``point`` lies in the counter-clockwise triangle abc (boundary included)."""
    return _cross(a, b, point) >= 0 and _cross(b, c, point) >= 0 and _cross(c, a, point) >= 0
