"""What every workflow returns: a frozen result whose ``to_dict()`` is the command's JSON.

Every JSON object carries ``vorobound_version``, ``command`` and a ``params`` object in one
nested form (ε, σ, δ/ε, ρ_f, L_i, λ, target, mode: whichever the command takes), and names the
same quantity the same way in every command (R − R̂ is ``radius_gap``). A result prints as a
short summary of its scalar fields; ``ok`` says whether everything the command checked holds
(the exit code 0 or 1).
"""

from __future__ import annotations

import dataclasses
import enum
import math
from collections.abc import Mapping, Sequence

REPR_LIMIT = 200
"""Longest repr of a result, in characters."""


def jsonable(value):
    """Plain JSON types for numpy values, dataclasses, enums, paths and tuples; NaN and
    infinity become null."""
    if isinstance(value, Result):
        return value.to_dict()
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        value = {f.name: getattr(value, f.name) for f in dataclasses.fields(value)}
    if isinstance(value, enum.Enum):
        value = value.value
    if hasattr(value, "tolist"):
        value = value.tolist()
    if hasattr(value, "__fspath__"):
        value = str(value)
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, Mapping):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [jsonable(v) for v in value]
    return value


def params_json(quality=None, eps: float | Sequence[float] | None = None, **asked) -> dict:
    """The ``params`` object: ε (if given), the quality parameters (σ, δ/ε, ρ_f, L_i, λ, target)
    and whatever else the command was asked (mode, ...), in one order for every command."""
    out = {} if eps is None else {"eps": eps}
    if quality is not None:
        out |= quality.as_dict()
    for key, value in asked.items():
        out[key] = value.value if isinstance(value, enum.Enum) else value
    return out


def typed_view(cls, data: Mapping, **given):
    """The frozen dataclass ``cls`` read from a command's JSON object ``data`` by field name:
    each field takes the value of the key of its name (its default where ``data`` lacks the
    key); ``given`` sets fields that are not read from ``data``. The CLI renders such views, so
    its tables show the numbers of ``--json`` and name each one once, as a typed field."""
    values = {f.name: data[f.name] for f in dataclasses.fields(cls) if f.name in data}
    return cls(**(values | given))


CONSTANT_LFS_RTOL = 1e-12
"""A sample's L counts as one value when its spread is within this share of its largest."""


def sample_lfs(params: dict, lfs) -> dict:
    """The L of a sample in a command's JSON, not the default L_i = 1 of the bounds' units:
    ``params["lfs"]`` becomes the one L every ball has (a sphere, a mesh with ``lfs``) or None
    when L varies, and the returned ``lfs_min``, ``lfs_max`` give its range."""
    import numpy as np

    lfs = np.asarray(lfs, dtype=float)
    if not len(lfs):
        params["lfs"] = None
        return {"lfs_min": None, "lfs_max": None}
    low, high = float(lfs.min()), float(lfs.max())
    params["lfs"] = high if high - low <= CONSTANT_LFS_RTOL * high else None
    return {"lfs_min": low, "lfs_max": high}


class Result:
    """Base of the workflows' results (frozen dataclasses).

    Subclasses set ``command`` and implement :meth:`payload` (the command-specific part of
    the JSON, ``params`` included).
    """

    command: str = ""

    def payload(self) -> dict:
        raise NotImplementedError

    def to_dict(self) -> dict:
        """The command's ``--json`` object."""
        from .. import __version__

        head = {"vorobound_version": __version__, "command": self.command}
        return jsonable(head | self.payload())

    @property
    def ok(self) -> bool:
        """True when everything the command checked holds (exit code 0; else 1)."""
        return True

    @property
    def verdict(self) -> str:
        """One line on what failed (printed last, with exit code 1); empty when ``ok``."""
        return ""

    def __repr__(self) -> str:
        parts = []
        for field in dataclasses.fields(self):  # type: ignore[arg-type]  # subclasses are
            if field.name.startswith("_") or not field.repr:
                continue
            value = getattr(self, field.name)
            if isinstance(value, bool | int | str | enum.Enum) or value is None:
                parts.append(f"{field.name}={_short(value)}")
            elif isinstance(value, float):
                parts.append(f"{field.name}={value:.6g}")
        text = f"{type(self).__name__}({', '.join(parts)})"
        return text if len(text) <= REPR_LIMIT else text[: REPR_LIMIT - 4] + "...)"


def _short(value) -> str:
    if isinstance(value, enum.Enum):
        value = value.value
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "...'"


class FigureFormat(str, enum.Enum):
    """File formats of the figures (``figure_format``)."""

    png = "png"
    pdf = "pdf"
    svg = "svg"


FIGURE_FORMATS = tuple(f.value for f in FigureFormat)
"""File formats of the figures (``figure_format``), by name."""


class TableFormat(str, enum.Enum):
    """How a check's output folder holds the per-triangle rows (``table``)."""

    parquet = "parquet"
    npz = "npz"
    csv = "csv"
    none = "none"


def checked_outputs(out, figure_format: str) -> None:
    """Refuse an unknown figure format, or an output folder that is a file, before any work."""
    from ..errors import InputError
    from ..files import checked_folder

    if not isinstance(figure_format, str) or figure_format not in FIGURE_FORMATS:
        raise InputError(f"figure_format: expected png, pdf or svg, got {figure_format!r}")
    if out is not None:
        checked_folder(out)


def as_float(value) -> float | None:
    """A numpy or Python scalar as a plain float (None stays None)."""
    return None if value is None else float(value)


def frame(rows: list[dict]):
    """Rows as a pandas DataFrame (pandas is optional: an InputError says how to get it)."""
    try:
        import pandas as pd
    except ImportError:
        from ..errors import MissingDependency

        raise MissingDependency("to_frame() needs pandas: pip install pandas") from None
    return pd.DataFrame(rows)
