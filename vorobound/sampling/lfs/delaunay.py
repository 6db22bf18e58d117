"""The Delaunay tetrahedra of a point set and their neighbours (geogram, or CGAL via GUDHI).

The Voronoi poles (:mod:`.medial`) need every Delaunay tetrahedron of a surface sample and the
four tetrahedra across its faces. scipy's qhull gives both, but on samples with many
cospherical points, as every regularly meshed curved surface is, it slows down far more than
linearly even after the jitter of :mod:`.medial`: 80 s for the 262 144 vertices of a torus grid,
against 5 s for a quarter of them. CGAL's incremental triangulation with exact predicates
(GUDHI's Delaunay complex) takes a few seconds for the same points; the tetrahedra are read out
of its simplex tree in bulk (no Python loop per simplex: issue 35 measured that loop at as much
CPU as qhull's whole triangulation of a 65 536-vertex torus). Where the package's compiled module
was built, geogram's exact triangulation hands over the tetrahedra as an array instead, without
any simplex tree, with the neighbours from geogram's own adjacency
(:func:`vorobound.sampling.geogram_delaunay.delaunay_neighbours`); otherwise (CGAL, or repeated
points) the neighbours come from matching the faces of the tetrahedra.

The triangulation is the same as before (GUDHI's ``AlphaComplex``, read simplex by simplex):
both are CGAL's Delaunay triangulation with exact predicates, unique for the jittered points
(no five cospherical), and the vertex indices are those of the input (tested).
"""

from __future__ import annotations

import functools

import numpy as np

from ...errors import VoroboundError
from ...geometry.kernels import load_kernel
from ..geogram_delaunay import delaunay_neighbours
from ..simplices import delaunay_tetrahedra as engine_tetrahedra
from ..simplices import face_neighbours, kernel_available


def delaunay_tetrahedra(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The tetrahedra (t, 4) of the Delaunay triangulation of ``points`` (n, 3), and for each
    the tetrahedron across the face opposite each corner (t, 4), −1 on the convex hull (the
    layout of scipy's ``Delaunay.simplices`` and ``neighbors``). No tetrahedron at all for
    coplanar points."""
    points = np.asarray(points, dtype=float)
    found = delaunay_neighbours(points)  # geogram's own adjacency: no face matching
    if found is not None:
        return found
    tets = engine_tetrahedra(points, ordered=False)  # any row order
    if not len(tets):
        return tets, np.zeros((0, 4), dtype=np.int64)
    kernel = _facets_kernel()
    if kernel is not None:  # linear (a counting sort of the faces); the same array
        neighbours, ok = kernel.face_neighbours(tets, int(tets.max()) + 1)
        neighbours = neighbours if ok else None
    else:
        neighbours = face_neighbours(tets)
    if neighbours is None:  # a face of three tetrahedra: not a triangulation
        raise VoroboundError("CGAL's triangulation has a face of more than two tetrahedra")
    return tets, neighbours


@functools.cache
def _load_facets_kernel():
    return load_kernel("vorobound.sampling.reconstruct.facets_kernel")


def _facets_kernel():
    """The compiled face matching of M̂ (:mod:`vorobound.sampling.reconstruct.facets_kernel`,
    tested equal to :func:`vorobound.sampling.simplices.face_neighbours`), or None without
    numba or with ``VOROBOUND_PURE_NUMPY`` set."""
    return _load_facets_kernel() if kernel_available() else None
