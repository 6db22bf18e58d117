"""vorobound: weighted-triangle geometry and the VoroCrust circumradius/orthoradius bounds.

Every command has a function of the same name here (``vorobound.solve``, ``vorobound.check``,
...; the command ``bounds`` is ``vorobound.bound``, since ``vorobound.bounds`` is the package of
the bounds). The top-level names load their modules on first use (module ``__getattr__``), so
importing the package, or running ``vorobound --help``, does not import numpy.
"""

from __future__ import annotations

import importlib

from .errors import VoroboundError

__version__ = "0.3.0"

_LAZY = {
    # One function per command (vorobound.api): keyword arguments like the options, a result
    # whose to_dict() is the command's --json.
    "solve": "vorobound.api.solve",
    "bound": "vorobound.api.bound",
    "sweep": "vorobound.api.sweep",
    "advise": "vorobound.api.advise",
    "certify": "vorobound.api.certify",
    "check_certificate": "vorobound.api.certify",
    "sample": "vorobound.api.sample",
    "check": "vorobound.api.check",
    "reconstruct": "vorobound.api.reconstruct",
    "lfs": "vorobound.api.lfs",
    "triangle": "vorobound.api.triangle",
    "validate": "vorobound.api.validate",
    "figure": "vorobound.api.figures",
    "reproduce": "vorobound.api.figures",
    "cheng": "vorobound.api.cheng",
    # The library underneath.
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
