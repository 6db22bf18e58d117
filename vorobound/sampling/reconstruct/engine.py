"""The Delaunay tetrahedra of M̂'s seeds: the one call of the triangulation engine.

Both the whole set (:func:`.facets.inout_facets`) and each slab (:mod:`.slabs`) take their
tetrahedra from :func:`delaunay_tetrahedra`, so another engine plugs in here. What the callers rely
on: exact predicates with a symbolic perturbation that depends on the coordinates only (geogram's
lexicographic one; CGAL's, the fallback, too): the triangulation of a subset agrees with the whole
set's wherever a tetrahedron's circumscribed ball holds no other seed; each row ascending and the
rows in lexicographic order (a slab's walks then start at the whole set's tetrahedra,
:mod:`.slabs`); a seed at the very coordinates of an earlier one left out.
"""

from __future__ import annotations

import numpy as np


def delaunay_tetrahedra(points: np.ndarray, engine: str | None = None) -> np.ndarray:
    """Tetrahedra (k, 4) of the Delaunay triangulation of ``points`` (n, 3), as seed indices
    (int64; module docstring for the order); no rows when the points span no volume.

    ``engine`` None: geogram's module (:func:`vorobound.sampling.simplices.delaunay_tetrahedra`,
    CGAL where the module is missing or the seeds leave its exact range); "cgal": CGAL through
    GUDHI's simplex tree. VoroCrust's seeds are cospherical up to rounding: many in-sphere tests
    fail geogram's double filter, and only with the double-double stage
    (``native/insphere_dd.cpp``) does geogram beat CGAL's route through the simplex tree on them
    (``python benchmarks/bench_engines.py cells --eps 0.0094977 --cube``, docs/performance.md).
    """
    from ..simplices import delaunay_tetrahedra as engine_tetrahedra

    return engine_tetrahedra(points, engine=engine)
