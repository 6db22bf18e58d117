"""Geometry of weighted triangles (pure numpy)."""

from .triangle import WeightedTriangles, theorem1_from_edges, weighted_triangles

__all__ = ["WeightedTriangles", "theorem1_from_edges", "weighted_triangles"]
