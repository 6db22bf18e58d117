"""The optional compiled kernels (numba): whether they may run, and loading one.

Every module of numba kernels is imported through :func:`load_kernel`, so one environment
variable switches them all off and a kernel that cannot load falls back the same way
everywhere: ``VOROBOUND_PURE_NUMPY`` set to a non-empty value forces the numpy paths.
"""

from __future__ import annotations

import importlib
import importlib.util
import os
import warnings
from types import ModuleType

from ..errors import VoroboundWarning


def pure_numpy() -> bool:
    """True when the environment variable ``VOROBOUND_PURE_NUMPY`` switches the kernels off."""
    return bool(os.environ.get("VOROBOUND_PURE_NUMPY"))


def load_kernel(module: str, what: str | None = None, instead: str = "") -> ModuleType | None:
    """The module of compiled kernels ``module`` (a full dotted name), or None where numba is
    missing or the module does not load (e.g. a numba that cannot cache); then, with ``what``,
    a VoroboundWarning says that ``what`` could not be loaded and ``instead`` runs. Callers
    cache the answer and check :func:`pure_numpy` first."""
    if importlib.util.find_spec("numba") is None:
        return None
    try:
        return importlib.import_module(module)
    except (ImportError, RuntimeError, OSError) as exc:
        if what is not None:
            warnings.warn(
                f"{what} could not be loaded ({exc}); using {instead}",
                VoroboundWarning,
                stacklevel=4,
            )
        return None
