"""Topology of VoroCrust's M̂: closed 2-manifold or not, components, Euler characteristic
(:mod:`vorobound.mesh.topology` measures any polygon surface).

References
----------
VoroCrust's guarantee that M̂ is isotopic to the surface (so it has the surface's components
and Euler characteristic), which the measurements test.
"""

from __future__ import annotations

from ...mesh.topology import Topology, polygon_topology
from .facets import PolygonSurface

__all__ = ["Topology", "surface_topology"]


def surface_topology(surface: PolygonSurface, unbounded: int = 0) -> Topology:
    """Edges, components, χ and the manifold conditions of ``surface``.

    Parameters
    ----------
    surface : PolygonSurface
        Oriented polygons on shared vertices.
    unbounded : int
        Facets that were left out because they reach infinity (M̂ is then not closed).
    """
    return polygon_topology(surface.corners, surface.offsets, len(surface.vertices), unbounded)
