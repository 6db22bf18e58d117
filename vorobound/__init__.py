"""vorobound: weighted-triangle geometry and the VoroCrust circumradius/orthoradius bounds."""

from .errors import VoroboundError
from .geometry import WeightedTriangles, theorem1_from_edges, weighted_triangles

__version__ = "0.1.0"

__all__ = [
    "VoroboundError",
    "WeightedTriangles",
    "theorem1_from_edges",
    "weighted_triangles",
    "__version__",
]
