"""vorobound: weighted-triangle geometry and the VoroCrust circumradius/orthoradius bounds.

The top-level names load their modules on first use (module ``__getattr__``), so importing
the package, or running ``vorobound --help``, does not import numpy.
"""

from __future__ import annotations

import importlib

from .errors import VoroboundError

__version__ = "0.2.0"

_LAZY = {
    "WeightedTriangles": "vorobound.geometry",
    "theorem1_from_edges": "vorobound.geometry",
    "weighted_triangles": "vorobound.geometry",
    "QualityParams": "vorobound.bounds.params",
    "SamplingParams": "vorobound.bounds.params",
    "Target": "vorobound.bounds.targets",
    "h3_route": "vorobound.bounds.targets",
    "eps_star": "vorobound.bounds.guarantee",
    "bound_at": "vorobound.bounds.guarantee",
}

__all__ = ["VoroboundError", "__version__", *_LAZY]


def __getattr__(name: str):
    if name in _LAZY:
        value = getattr(importlib.import_module(_LAZY[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'vorobound' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(__all__)
