"""``vorobound sweep``: ε* tables over the parameters, or bound curves over ε.

Rows stream out as they are computed, so memory stays bounded whatever the grid size: to a
file (:func:`sweep` with ``output``), to any text stream (:func:`write_sweep`), or collected
into the result when neither is asked for.
"""

from __future__ import annotations

import csv
import json
import os
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from numbers import Number

from ..bounds.params import checked_modes, checked_targets
from ..checks import parse_values
from ..constants import PAPER_DELTA_RATIO, PAPER_RHO_F, PAPER_SIGMA
from ..errors import InputError
from ..progress import Progress
from ..reports.sweep import MAX_GRID_ROWS, SweepRow, SweepSpec
from .arguments import checked_arguments
from .result import Result, frame, jsonable

MAX_JOBS = 1 << 16
"""Larger job counts are taken as this (the pool is capped by the rows and the CPUs)."""
FORMATS = ("csv", "json")
"""File formats of a sweep, chosen by the output's suffix."""


def _axis(value, name: str, allow_none: bool = False) -> tuple:
    """A scalar, a sequence or the option's text (``"start:stop:num"`` or a comma list, as
    ``--name`` takes it) as a tuple of values (numpy scalars and 0-d arrays are scalars;
    anything not iterable is one value, for the checks to refuse or accept)."""
    if isinstance(value, str):
        return tuple(parse_values(value, name, allow_none))
    scalar = isinstance(value, bytes | Number) or getattr(value, "ndim", None) == 0
    if value is None or scalar or not isinstance(value, Iterable):
        return (value,)
    return tuple(value)


def sweep_spec(
    *, eps, sigma, rho_f, delta_ratio, lipschitz, mode, target, lfs, method
) -> SweepSpec:
    """The validated axes of a sweep (each argument a value or a sequence of values; the
    keywords and defaults are :func:`sweep`'s)."""
    return SweepSpec(
        sigma=_axis(sigma, "sigma"),
        rho_f=_axis(rho_f, "rho_f"),
        delta_ratio=_axis(delta_ratio, "delta_ratio"),
        lipschitz=_axis(lipschitz, "lipschitz", allow_none=True),
        modes=checked_modes(mode),
        eps=None if eps is None else _axis(eps, "eps"),
        lfs=lfs,
        method=method,
        targets=checked_targets(target),
    )


def spec_json(spec: SweepSpec) -> dict:
    """The sweep's ``params`` object (each axis a list)."""
    return {
        "eps": None if spec.eps is None else list(spec.eps),
        "sigma": list(spec.sigma),
        "delta_ratio": list(spec.delta_ratio),
        "rho_f": list(spec.rho_f),
        "lfs": spec.lfs,
        "lipschitz": list(spec.lipschitz),
        "target": [t.value for t in spec.targets],
        "mode": [m.value for m in spec.modes],
        "method": spec.method,
    }


def row_dict(row: SweepRow, columns: Sequence[str]) -> dict:
    return {c: getattr(row, c) for c in columns}


@dataclass(frozen=True, repr=False)
class SweepResult(Result):
    """The rows of a sweep (or, when they were streamed to a file, how many and where)."""

    command = "sweep"
    n_rows: int
    output: str | None
    rows: tuple[SweepRow, ...] = field(repr=False)
    spec: SweepSpec = field(repr=False)

    def payload(self) -> dict:
        return {
            "params": spec_json(self.spec),
            "columns": list(self.spec.columns),
            "n_rows": self.n_rows,
            "output": self.output,
            "rows": [row_dict(r, self.spec.columns) for r in self.rows],
        }

    def to_frame(self):
        """The rows as a pandas DataFrame (pandas optional)."""
        return frame([row_dict(r, self.spec.columns) for r in self.rows])


def output_format(path: str | os.PathLike) -> str:
    """The format a sweep file is written in, from its suffix (.csv or .json)."""
    suffix = os.fspath(path).rsplit(".", 1)[-1].lower() if "." in os.fspath(path) else ""
    if suffix not in FORMATS:
        raise InputError(
            f"cannot tell the format of {os.fspath(path)!r} from its suffix: use .csv or .json"
        )
    return suffix


def write_sweep(rows: Iterable[SweepRow], spec: SweepSpec, handle, fmt: str) -> int:
    """Stream ``rows`` to a text ``handle`` as CSV or as the command's JSON object; return how
    many were written."""
    columns = spec.columns
    count = 0
    if fmt == "csv":
        writer = csv.writer(handle, lineterminator="\n")
        writer.writerow(columns)
        for row in rows:
            values = (getattr(row, c) for c in columns)
            writer.writerow(
                ["" if v is None else repr(v) if isinstance(v, float) else v for v in values]
            )
            count += 1
        return count
    head = SweepResult(n_rows=0, output=None, rows=(), spec=spec).to_dict()
    del head["n_rows"], head["output"], head["rows"]
    text = json.dumps(head, indent=2, allow_nan=False)
    handle.write(text[: text.rindex("}")].rstrip() + ',\n  "rows": [')
    for row in rows:
        record = json.dumps(jsonable(row_dict(row, columns)), allow_nan=False)
        handle.write(("," if count else "") + "\n    " + record)
        count += 1
    handle.write(("\n  " if count else "") + f'],\n  "n_rows": {count}\n}}\n')
    return count


@checked_arguments
def sweep(
    *,
    eps=None,
    sigma=PAPER_SIGMA,
    rho_f=PAPER_RHO_F,
    delta_ratio=PAPER_DELTA_RATIO,
    lipschitz=None,
    mode="rigorous,tight",
    target="additive,ratio",
    lfs: float = 1.0,
    method: str = "auto",
    jobs: int = 1,
    max_rows: int = MAX_GRID_ROWS,
    allow_long: bool = False,
    output: str | os.PathLike | None = None,
    progress: Progress | None = None,
) -> SweepResult:
    """Sweep the parameters: ε* per (mode, target, λ, σ, ρ_f, δ/ε), or with ``eps`` the bound
    per ε (on R − R̂ for the additive target, on R/R̂ for the ratio target).

    Each axis is a value, a sequence of values (a list, a numpy array) or the option's text:
    ``"start:stop:num"`` or a comma list (``mode`` and ``target`` a comma list too).
    A row whose parameters admit no ε* has ``eps_star`` None and the reason in ``note``. With
    ``output`` (``.csv`` or ``.json``) the rows stream into that file (written to a temporary
    name and renamed when the sweep ends) and the result holds none of them.

    Raises
    ------
    InputError
        A bad axis, more than ``max_rows`` rows, or tight rows estimated to take over ten
        minutes unless ``allow_long``.
    """
    spec = prepare(
        sweep_spec(
            eps=eps,
            sigma=sigma,
            rho_f=rho_f,
            delta_ratio=delta_ratio,
            lipschitz=lipschitz,
            mode=mode,
            target=target,
            lfs=lfs,
            method=method,
        ),
        jobs,
        max_rows,
        allow_long,
    )
    from ..reports.sweep import iter_sweep

    workers = workers_for(spec, jobs)
    rows = iter_sweep(spec, jobs=workers, progress=progress)
    if output is None:
        collected = tuple(rows)
        return SweepResult(n_rows=len(collected), output=None, rows=collected, spec=spec)
    from ..files import atomic_open

    fmt = output_format(output)
    with atomic_open(output, "w") as handle:
        count = write_sweep(rows, spec, handle, fmt)
    return SweepResult(n_rows=count, output=os.fspath(output), rows=(), spec=spec)


def workers_for(spec: SweepSpec, jobs: int) -> int:
    """Worker processes for the tight rows: ``jobs``, capped by the rows and the CPUs."""
    from ..parallel import usable_workers

    return usable_workers(jobs, spec.tight_rows)


def prepare(spec: SweepSpec, jobs: int, max_rows: int, allow_long: bool) -> SweepSpec:
    """Check the job count and the size of the grid before any row is computed."""
    from ..checks import checked_count
    from ..reports.sweep import check_size

    if isinstance(jobs, int) and not isinstance(jobs, bool) and jobs > MAX_JOBS:
        jobs = MAX_JOBS  # capped by the rows and the CPUs anyway
    jobs = checked_count(jobs, "jobs", 1, MAX_JOBS)
    max_rows = checked_count(max_rows, "max_rows", 1, MAX_GRID_ROWS)
    check_size(spec, workers_for(spec, jobs), max_rows=max_rows, allow_long=allow_long)
    return spec
