"""Topology of a polygon surface (a triangle mesh, or VoroCrust's M̂): closed 2-manifold or
not, components, Euler characteristic.

A closed 2-manifold has every edge in exactly two polygons and, around every vertex, one cycle
of polygons (its link is one circle, not two cones touching at a point). The Euler
characteristic is χ = V − E + F; for a closed orientable surface with c components,
χ = 2c − 2g and the genus g is c − χ/2 (a sphere: χ = 2, a torus: χ = 0).

References
----------
VoroCrust's guarantee that M̂ is isotopic to the surface (so it has the surface's components
and Euler characteristic), which the measurements test.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Topology:
    """What a polygon surface is, combinatorially."""

    vertices: int
    edges: int
    facets: int
    euler_characteristic: int
    """χ = V − E + F."""
    components: int
    """Connected components (through shared edges and vertices)."""
    boundary_edges: int
    """Edges in one polygon only (a hole, or a facet left out because it reaches infinity)."""
    nonmanifold_edges: int
    """Edges in more than two polygons."""
    nonmanifold_vertices: int
    """Vertices whose polygons form more than one cycle around them (a pinch)."""
    misoriented_edges: int
    """Edges of two polygons that run the same way along them (the polygons' normals disagree:
    not the boundary of a region)."""
    unbounded: int
    """Facets left out because they reach infinity."""
    bad_facets: np.ndarray
    """Indices of the polygons with a boundary or non-manifold edge or vertex."""

    @property
    def closed_manifold(self) -> bool:
        """Every edge in two polygons, one cycle around each vertex, nothing at infinity."""
        return (
            self.facets > 0
            and self.boundary_edges == 0
            and self.nonmanifold_edges == 0
            and self.nonmanifold_vertices == 0
            and self.unbounded == 0
        )

    @property
    def genus(self) -> int | None:
        """Total genus c − χ/2 of a closed orientable surface (None otherwise)."""
        if not self.closed_manifold or self.misoriented_edges:
            return None
        return self.components - self.euler_characteristic // 2


def polygon_topology(
    corners: np.ndarray, offsets: np.ndarray, vertex_count: int, unbounded: int = 0
) -> Topology:
    """Edges, components, χ and the manifold conditions of oriented polygons on shared
    vertices.

    Parameters
    ----------
    corners, offsets : np.ndarray
        Polygon f has the vertex indices ``corners[offsets[f]:offsets[f + 1]]``.
    vertex_count : int
        Number of vertices (indices below it).
    unbounded : int
        Facets that were left out because they reach infinity (the surface is then not
        closed).
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    count_v, count_f = vertex_count, len(offsets) - 1
    sizes = np.diff(offsets)
    nxt = np.arange(len(corners)) + 1
    nxt[offsets[1:] - 1] = offsets[:-1]
    prv = np.empty_like(nxt)
    prv[nxt] = np.arange(len(nxt))
    head, tail = corners, corners[nxt]
    low, high = np.minimum(head, tail), np.maximum(head, tail)
    keys, edge, uses = np.unique(low * count_v + high, return_inverse=True, return_counts=True)
    forward = np.bincount(edge, head < tail, len(keys))
    boundary = uses == 1
    nonmanifold = uses > 2
    misoriented = (uses == 2) & (forward != 1)
    # The link of each vertex: corner c at v joins v's edge to the previous corner with v's
    # edge to the next corner. Node 2e + s stands for edge e seen from its endpoint s (0 low).
    edge_in = edge[prv]
    node_in = 2 * edge_in + (corners > corners[prv])
    node_out = 2 * edge + (corners > tail)
    nodes = 2 * len(keys)
    graph = coo_matrix((np.ones(len(corners)), (node_in, node_out)), shape=(nodes, nodes))
    _, link = connected_components(graph, directed=False)
    pairs = np.unique(np.column_stack([corners, link[node_out]]), axis=0)
    cycles = np.bincount(pairs[:, 0], minlength=count_v)
    pinched = cycles > 1
    skeleton = coo_matrix((np.ones(len(keys)), (keys // count_v, keys % count_v)), (count_v,) * 2)
    used = np.zeros(count_v, dtype=bool)
    used[corners] = True
    components, vertex_component = connected_components(skeleton, directed=False)
    components -= int((~used).sum())  # isolated unused vertices are not components
    facet = np.repeat(np.arange(count_f), sizes)
    bad_corner = boundary[edge] | nonmanifold[edge] | pinched[corners]
    bad = np.unique(facet[bad_corner])
    return Topology(
        vertices=int(used.sum()),
        edges=len(keys),
        facets=count_f,
        euler_characteristic=int(used.sum()) - len(keys) + count_f,
        components=int(components),
        boundary_edges=int(boundary.sum()),
        nonmanifold_edges=int(nonmanifold.sum()),
        nonmanifold_vertices=int(pinched.sum()),
        misoriented_edges=int(misoriented.sum()),
        unbounded=int(unbounded),
        bad_facets=bad,
    )


def triangle_topology(points: np.ndarray, triangles: np.ndarray) -> Topology:
    """The topology of a triangle mesh, with vertices at the same position taken as one (an STL
    file repeats them per triangle)."""
    _, vertex = np.unique(points, axis=0, return_inverse=True)
    vertex = vertex.reshape(-1)
    corners = vertex[triangles].reshape(-1)
    offsets = np.arange(0, len(corners) + 1, 3)
    count = int(vertex.max()) + 1
    return polygon_topology(corners, offsets, count)
