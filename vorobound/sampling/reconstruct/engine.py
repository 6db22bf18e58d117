"""The Delaunay tetrahedra of M̂'s seeds: the one call of the triangulation engine.

Both the whole set (:func:`.facets.inout_facets`) and each slab (:mod:`.slabs`) take their
tetrahedra from :func:`delaunay_tetrahedra`, so another engine plugs in here. What the callers
rely on: exact predicates with CGAL's symbolic perturbation (the triangulation of a subset
agrees with the whole set's wherever a tetrahedron's circumscribed ball holds no other seed);
each row ascending and the rows in lexicographic order (a slab's walks then start at the whole
set's tetrahedra, :mod:`.slabs`); a seed at the very coordinates of an earlier one left out.
"""

from __future__ import annotations

import numpy as np


def delaunay_tetrahedra(points: np.ndarray) -> np.ndarray:
    """Tetrahedra (k, 4) of the Delaunay triangulation of ``points`` (n, 3), as seed indices
    (int64; module docstring for the order); no rows when the points span no volume.

    CGAL through GUDHI's ``DelaunayComplex``, read in bulk from its simplex tree
    (:func:`vorobound.sampling.simplices.delaunay_simplices`; with the compiled reader at any
    size where numba is there: M̂'s compiled steps load it anyway, and the slabs' probe and
    boxes are small trees, which GUDHI's iterator read in 0.5 CPU-s each at the cube's
    ε = 0.0094977).
    """
    from ..simplices import delaunay_simplices, kernel_available

    compiled = True if kernel_available() else None
    _, tetrahedra, _ = delaunay_simplices(points, compiled=compiled, triangles=False)
    return tetrahedra
