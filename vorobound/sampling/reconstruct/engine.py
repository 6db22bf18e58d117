"""The Delaunay tetrahedra of M̂'s seeds: the one call of the triangulation engine.

Both the whole set (:func:`.facets.inout_facets`) and each slab (:mod:`.slabs`) take their
tetrahedra from :func:`delaunay_tetrahedra`, so another engine plugs in here. What the callers
rely on: exact predicates with a symbolic perturbation that depends on the coordinates only
(CGAL's; geogram's lexicographic one would do too): the triangulation of a subset agrees with
the whole set's wherever a tetrahedron's circumscribed ball holds no other seed; each row
ascending and the rows in lexicographic order (a slab's walks then start at the whole set's
tetrahedra, :mod:`.slabs`); a seed at the very coordinates of an earlier one left out.
"""

from __future__ import annotations

import numpy as np


def delaunay_tetrahedra(points: np.ndarray) -> np.ndarray:
    """Tetrahedra (k, 4) of the Delaunay triangulation of ``points`` (n, 3), as seed indices
    (int64; module docstring for the order); no rows when the points span no volume.

    CGAL through GUDHI's simplex tree (:func:`vorobound.sampling.simplices.delaunay_tetrahedra`
    with ``engine="cgal"``), not geogram's module, which ``lfs`` uses: VoroCrust's seeds are
    cospherical up to rounding, and geogram decides nearly every such in-sphere test with its
    exact expansions (42.9 CPU-s for the tetrahedra of the 1.08·10⁶ seeds of the cube at
    ε = 0.0094977, against 16.4 for CGAL's build and 37.3 for this route with the simplex tree,
    its reading and the face neighbours; ``python benchmarks/bench_engines.py cells --eps
    0.0094977 --cube``, docs/performance.md).
    """
    from ..simplices import delaunay_tetrahedra as engine_tetrahedra

    return engine_tetrahedra(points, engine="cgal")
