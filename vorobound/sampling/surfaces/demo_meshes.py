"""Triangle meshes built in code whose local feature size is known exactly: sphere and torus.

Their vertices lie exactly on the smooth surface, so the exact L there is
:meth:`~vorobound.sampling.surfaces.analytic.SphereShape.lfs_at` or
:meth:`~vorobound.sampling.surfaces.analytic.TorusShape.lfs_at`. Tests, benchmarks and the
docs use them to measure the estimator of :mod:`vorobound.sampling.lfs.estimate`.
"""

from __future__ import annotations

import math

import numpy as np

from ...errors import InputError
from ...mesh import TriangleMesh

_ICOSAHEDRON_FACES = np.array(
    [
        [0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11],
        [1, 5, 9], [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8],
        [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9],
        [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1],
    ]
)  # fmt: skip
MAX_SUBDIVISIONS = 8
"""An icosphere with 8 subdivisions has 655 362 vertices; more would not fit a test machine."""


def icosphere(radius: float = 1.0, subdivisions: int = 4) -> TriangleMesh:
    """Sphere mesh: an icosahedron split ``subdivisions`` times, vertices pushed onto the sphere.

    Parameters
    ----------
    radius : float
        Sphere radius R (the exact L is R everywhere).
    subdivisions : int
        Each split turns a triangle into four; 10·4^k + 2 vertices.

    Returns
    -------
    TriangleMesh
        Outward-oriented closed mesh.
    """
    if not (math.isfinite(radius) and radius > 0):
        raise InputError(f"sphere radius must be positive and finite, got {radius}")
    if not 0 <= subdivisions <= MAX_SUBDIVISIONS:
        raise InputError(f"subdivisions must be in 0..{MAX_SUBDIVISIONS}, got {subdivisions}")
    golden = (1 + math.sqrt(5)) / 2
    base = [(-1, golden), (1, golden), (-1, -golden), (1, -golden)]
    points = np.array(
        [(a, b, 0) for a, b in base] + [(0, a, b) for a, b in base] + [(b, 0, a) for a, b in base],
        dtype=float,
    )
    points /= np.linalg.norm(points, axis=1, keepdims=True)
    faces = _ICOSAHEDRON_FACES
    for _ in range(subdivisions):
        edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), 1)
        unique, inverse = np.unique(edges, axis=0, return_inverse=True)
        middle = points[unique].sum(axis=1)
        middle /= np.linalg.norm(middle, axis=1, keepdims=True)
        mid = inverse.reshape(3, -1).T + len(points)
        points = np.vstack([points, middle])
        a, b, c = faces.T
        ab, bc, ca = mid.T
        faces = np.concatenate(
            [np.c_[a, ab, ca], np.c_[b, bc, ab], np.c_[c, ca, bc], np.c_[ab, bc, ca]]
        )
    return TriangleMesh(radius * points, faces, f"icosphere R={radius:g} level {subdivisions}")


def torus_mesh(
    major: float, minor: float, around: int, tube: int, jitter: float = 0.0, seed: int = 0
) -> TriangleMesh:
    """Ring-torus mesh on a staggered (θ, φ) grid, every vertex exactly on the torus.

    Parameters
    ----------
    major, minor : float
        Radii R > r > 0 (the exact L is min(r, distance to the z axis)).
    around, tube : int
        Vertices per parallel circle (θ) and per meridian circle (φ); ``tube`` even, both ≥ 6.
    jitter : float
        Moves each vertex by up to ``jitter`` grid steps in θ and φ (uniform, in [0, 0.3]), to
        break the grid's symmetry (rows of equal φ share their medial points).
    seed : int
        Seed of the jitter.

    Returns
    -------
    TriangleMesh
        Closed, consistently oriented mesh of ``around·tube`` vertices.
    """
    if not (math.isfinite(major) and math.isfinite(minor) and major > minor > 0):
        raise InputError(f"a ring torus needs R > r > 0, got R={major}, r={minor}")
    if around < 6 or tube < 6 or tube % 2:
        raise InputError(f"need around ≥ 6 and an even tube ≥ 6, got {around}, {tube}")
    if not 0 <= jitter <= 0.3:
        raise InputError(f"jitter must be in [0, 0.3] grid steps, got {jitter}")
    i, j = np.meshgrid(np.arange(around), np.arange(tube), indexing="ij")
    rng = np.random.default_rng(seed)
    shift = jitter * rng.uniform(-1, 1, (2, around, tube))
    theta = 2 * math.pi * (i + 0.5 * (j % 2) + shift[0]) / around
    phi = 2 * math.pi * (j + shift[1]) / tube
    rho = major + minor * np.cos(phi)
    points = np.stack([rho * np.cos(theta), rho * np.sin(theta), minor * np.sin(phi)], -1)

    def index(a, b):
        return (a % around) * tube + (b % tube)

    rows = []
    ring = np.arange(around)
    for row in range(tube):
        odd = row % 2
        a, b = index(ring, row), index(ring + 1, row)
        c, d = index(ring + odd, row + 1), index(ring + odd - 1, row + 1)
        rows += [np.c_[a, b, c], np.c_[a, c, d]]
    name = f"torus R={major:g} r={minor:g} {around}x{tube}"
    return TriangleMesh(points.reshape(-1, 3), np.concatenate(rows), name)


def cube_mesh(half: float = 1.0, divisions: int = 4) -> TriangleMesh:
    """Cube [−half, half]³, each face split into divisions² squares of two triangles.

    The 12 cube edges are sharp (dihedral angle 90°): a polyhedron's L is 0 on them.
    """
    if not (math.isfinite(half) and half > 0):
        raise InputError(f"cube half-width must be positive and finite, got {half}")
    if not 1 <= divisions <= 1000:
        raise InputError(f"divisions must be in 1..1000, got {divisions}")
    grid = np.linspace(-half, half, divisions + 1)
    u, v = (a.reshape(-1) for a in np.meshgrid(grid, grid, indexing="ij"))
    i, j = (a.reshape(-1) for a in np.meshgrid(*(np.arange(divisions),) * 2, indexing="ij"))
    corner = i * (divisions + 1) + j
    quads = np.c_[corner, corner + divisions + 1, corner + divisions + 2, corner + 1]
    points: list[np.ndarray] = []
    faces: list[np.ndarray] = []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            face_points = np.zeros((len(u), 3))
            face_points[:, axis] = sign * half
            face_points[:, (axis + 1) % 3], face_points[:, (axis + 2) % 3] = u, v
            base = sum(len(p) for p in points)
            q = quads + base if sign > 0 else quads[:, ::-1] + base
            faces += [q[:, [0, 1, 2]], q[:, [0, 2, 3]]]
            points.append(face_points)
    unique, merged = np.unique(np.concatenate(points), axis=0, return_inverse=True)
    triangles = merged.reshape(-1)[np.concatenate(faces)]
    return TriangleMesh(unique, triangles, f"cube half={half:g} {divisions}x{divisions}")
