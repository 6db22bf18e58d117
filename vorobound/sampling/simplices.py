"""Triangles and tetrahedra of CGAL's 3-D (regular) Delaunay triangulations, in bulk.

GUDHI's ``DelaunayComplex`` (CGAL's incremental triangulation with exact predicates) hands its
result over only as a simplex tree, whose Python iterators build one list per simplex: for a
triangulation of 10⁶ points that loop cost more CPU time than CGAL itself (issue 35). The tree
pickles itself into one byte array (``SimplexTree.__getstate__``, GUDHI's pickle support), and
:mod:`.simplex_kernel` (compiled, with the optional numba) reads every triangle and
tetrahedron out of that array (a pass that counts, a pass that fills: 0.05–0.13 CPU-s for the
4·10⁶ simplices of 2·10⁵ weighted points, against 0.4–0.6 for the serialization and 1.4 for
the iterator). The bytes must end where the last block does. Where numba is missing, the tree
is small (loading numba costs a process about 0.7 s) or the layout is not the expected one
(another GUDHI version), GUDHI's iterator gives the same simplices. docs/performance.md
compares the alternatives.
"""

from __future__ import annotations

import functools

import numpy as np

from ..errors import InputError
from ..geometry.kernels import load_kernel, pure_numpy

COMPILED_MIN_VERTICES = 30_000
"""Trees on fewer vertices (about 13 simplices each) are read with GUDHI's iterator (no numba
load for them)."""
PACKED_BITS = 21
"""Vertex indices below 2**PACKED_BITS are packed three to an int64 when faces are matched."""


def tree_simplices(
    tree, compiled: bool | None = None, triangles: bool = True, tetrahedra: bool = True
) -> tuple[np.ndarray, np.ndarray]:
    """The triangles (m, 3) and tetrahedra (k, 4) of a GUDHI simplex tree, as vertex indices
    (int64, ascending within a row, rows in the tree's order); an array not asked for
    (``triangles``/``tetrahedra`` False) has no rows.

    ``compiled``: True reads the tree with the compiled kernel, False with GUDHI's iterator,
    None (default) chooses by size and by what is installed.
    """
    if compiled is None:
        compiled = tree.num_vertices() >= COMPILED_MIN_VERTICES and kernel_available()
    if compiled:
        found = _read_compiled(tree, triangles, tetrahedra)
        if found is not None:
            return found
    counts = _counts_by_dimension(tree)
    return _read_iterated(tree, counts[2] if triangles else 0, counts[3] if tetrahedra else 0)


def kernel_available() -> bool:
    """True when the compiled reader can run (numba installed, ``VOROBOUND_PURE_NUMPY`` unset)."""
    return not pure_numpy() and _load_kernel() is not None


@functools.cache
def _load_kernel():
    return load_kernel(
        f"{__package__}.simplex_kernel", "the compiled simplex reader", "GUDHI's iterator"
    )


def _read_compiled(tree, triangles: bool, tetrahedra: bool):
    """The simplices read from the serialized tree (a pass that counts, then one that
    fills), or None when its layout is not the one expected (the bytes end early or go on)."""
    kernel = _load_kernel()
    if kernel is None:
        return None
    data = np.asarray(tree.__getstate__()).view(np.uint8)
    none_tri, none_tet = np.empty((0, 3), dtype=np.int64), np.empty((0, 4), dtype=np.int64)
    n_tri, n_tet, end = kernel.read_tree(data, none_tri, none_tet)
    if n_tri < 0 or end != len(data):
        return None
    out_tri = np.empty((n_tri if triangles else 0, 3), dtype=np.int64)
    out_tet = np.empty((n_tet if tetrahedra else 0, 4), dtype=np.int64)
    if len(out_tri) or len(out_tet):
        if kernel.read_tree(data, out_tri, out_tet) != (n_tri, n_tet, end):
            return None
    return out_tri, out_tet


def _counts_by_dimension(tree) -> list[int]:
    """Simplices per dimension 0..3 (and zeros above): GUDHI's own count where it has one
    (3.12 on), else one pass over the 3-skeleton (GUDHI 3.11, the declared floor)."""
    by_dimension = getattr(tree, "num_simplices_by_dimension", None)
    if by_dimension is not None:
        return list(by_dimension()) + [0, 0, 0, 0]
    counts = [0] * 8
    for simplex, _ in tree.get_skeleton(3):
        counts[len(simplex) - 1] += 1
    return counts


def _read_iterated(tree, n_triangles: int, n_tetrahedra: int):
    """The simplices from GUDHI's iterator (one Python list per simplex)."""
    triangles = np.empty((n_triangles, 3), dtype=np.int64)
    tetrahedra = np.empty((n_tetrahedra, 4), dtype=np.int64)
    tri = tet = 0
    for simplex, _ in tree.get_skeleton(3 if n_tetrahedra else 2):
        if len(simplex) == 3 and n_triangles:
            triangles[tri] = simplex
            tri += 1
        elif len(simplex) == 4:
            tetrahedra[tet] = simplex
            tet += 1
    return triangles, tetrahedra


def delaunay_simplices(
    points: np.ndarray,
    weights: np.ndarray | None = None,
    compiled: bool | None = None,
    triangles: bool = True,
    tetrahedra: bool = True,
) -> tuple[np.ndarray, np.ndarray, int]:
    """Triangles (m, 3), tetrahedra (k, 4) and vertex count of CGAL's Delaunay triangulation of
    ``points`` (n, 3), regular when ``weights`` are given (GUDHI's ``DelaunayComplex``, exact
    predicates; :func:`tree_simplices` for the other options). A point equal to an earlier
    one, or hidden by the weights, is no vertex."""
    import gudhi

    complex_ = gudhi.DelaunayComplex(
        points=np.ascontiguousarray(points, dtype=float),
        weights=None if weights is None else np.ascontiguousarray(weights, dtype=float),
        precision="fast",
    )
    tree = complex_.create_simplex_tree()
    del complex_
    found = tree_simplices(tree, compiled, triangles, tetrahedra)
    return *found, tree.num_vertices()


TETRAHEDRA_ENGINES = ("geogram", "cgal")
"""Engines of :func:`delaunay_tetrahedra`: geogram's compiled module, CGAL through GUDHI."""


def delaunay_tetrahedra(
    points: np.ndarray, engine: str | None = None, ordered: bool = True
) -> np.ndarray:
    """Tetrahedra (k, 4) of the Delaunay triangulation of ``points`` (n, 3), as point indices
    (int64, ascending within a row; with ``ordered``, rows in lexicographic order, otherwise in
    the engine's); no rows when the points span no volume; a point equal to an earlier one is
    no vertex. The one call of the unweighted triangulation (M̂'s seeds, the poles of ``lfs``).

    ``engine``: "geogram" (:mod:`.geogram_delaunay`: exact, no simplex tree; 0.57 times CGAL's
    bare build and 0.17 times the CGAL route's CPU time on 10⁶ random points), "cgal" (GUDHI's
    ``DelaunayComplex`` read from its simplex tree), None (default): the same as "geogram", which
    falls back to CGAL where the module was not built or the input leaves its exact range. Both
    are exact; among cospherical
    points they may choose different tetrahedra (each a Delaunay triangulation).
    """
    if engine not in (None, *TETRAHEDRA_ENGINES):
        raise InputError(f"engine must be one of {TETRAHEDRA_ENGINES} or None, not {engine!r}")
    if np.ndim(points) != 2 or np.shape(points)[1] != 3:
        raise InputError(f"points must be an (n, 3) array, not of shape {np.shape(points)}")
    from .geogram_delaunay import delaunay_tetrahedra as geogram_tetrahedra
    from .geogram_delaunay import first_copies, lexicographic_rows

    if engine != "cgal":
        found = geogram_tetrahedra(points, ordered)
        if found is not None:
            return found
    compiled = True if kernel_available() else None
    _, tetrahedra, _ = delaunay_simplices(points, compiled=compiled, triangles=False)
    # CGAL keeps whichever copy of a point its spatial sort meets first: the first one instead.
    first = first_copies(np.asarray(points, dtype=float), tetrahedra)
    if first is tetrahedra or not ordered:
        return first
    return lexicographic_rows(first, len(points))


def face_neighbours(tets: np.ndarray) -> np.ndarray | None:
    """The tetrahedron sharing the face opposite each corner of ``tets`` (t, 4), −1 where none
    (scipy's ``Delaunay.neighbors`` layout); None when a face is shared by more than two
    tetrahedra (not a triangulation)."""
    out = np.full(tets.shape, -1, dtype=np.int64)
    if not len(tets):
        return out
    presorted = bool((tets[:, :-1] < tets[:, 1:]).all())  # as a simplex tree gives them
    ordered = tets if presorted else np.sort(tets, axis=1)
    by_corner = np.empty((4, len(tets), 3), dtype=np.int64)
    for corner, keep in enumerate(((1, 2, 3), (0, 2, 3), (0, 1, 3), (0, 1, 2))):
        by_corner[corner] = ordered[:, keep]
    faces = by_corner.reshape(-1, 3)  # face k·t + i is tetrahedron i without corner k
    if int(ordered.max()) < 1 << PACKED_BITS:
        key = (faces[:, 0] << (2 * PACKED_BITS)) | (faces[:, 1] << PACKED_BITS) | faces[:, 2]
        order = np.argsort(key)
        key = key[order]
        same = key[1:] == key[:-1]
    else:
        order = np.lexsort((faces[:, 2], faces[:, 1], faces[:, 0]))
        ordered_faces = faces[order]
        same = (ordered_faces[1:] == ordered_faces[:-1]).all(axis=1)
    if (same[1:] & same[:-1]).any():
        return None
    twin = np.flatnonzero(same)
    first, second = order[twin], order[twin + 1]
    count = len(tets)
    # The corner opposite a face is the one left out of ``ordered``; map it back to ``tets``.
    row_a, row_b = first % count, second % count
    col_a, col_b = first // count, second // count
    if not presorted:
        col_a = _original_corner(tets, ordered, row_a, col_a)
        col_b = _original_corner(tets, ordered, row_b, col_b)
    out[row_a, col_a] = row_b
    out[row_b, col_b] = row_a
    return out


def _original_corner(tets, ordered, rows, sorted_corner):
    """Column of ``tets`` holding the vertex ``ordered[rows, sorted_corner]``."""
    vertex = ordered[rows, sorted_corner]
    return np.argmax(tets[rows] == vertex[:, None], axis=1)
