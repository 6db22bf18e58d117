"""Geometry of weighted triangles: numpy, with an optional compiled kernel for big batches."""

from .result import WeightedTriangles
from .triangle import theorem1_from_edges, weighted_triangles

__all__ = ["WeightedTriangles", "theorem1_from_edges", "weighted_triangles"]
