"""``vorobound sweep``: ε* tables over the parameters, or bound curves over ε.

Rows are written as they are computed (CSV and JSON), so memory stays bounded whatever the
grid size; ``-o FILE`` writes to a temporary file that replaces FILE only when the sweep ends.
"""

from __future__ import annotations

import csv
import json
import sys
from enum import Enum
from pathlib import Path
from typing import Annotated

import typer

from ..errors import InputError
from .options import (
    Json,
    MethodChoice,
    TargetsOpt,
    TightMethodOpt,
    parse_modes,
    parse_targets,
    parse_values,
)
from .progress import progress_bar
from .render import fmt, jsonable, print_table

MAX_TABLE_ROWS = 10_000
"""Larger sweeps are written as CSV or JSON, not drawn as a table."""


class TableFormat(str, Enum):
    table = "table"
    csv = "csv"
    json = "json"


def _opt(name: str, help_: str):
    return typer.Option(f"--{name}", help=help_ + " Range start:stop:num or a comma list.")


def sweep(
    eps: Annotated[str | None, _opt("eps", "ε values: gives bound curves instead of ε*.")] = None,
    sigma: Annotated[str, _opt("sigma", "Sparsity σ values.")] = "0.75",
    rho_f: Annotated[str, _opt("rho-f", "Quality constant ρ_f values.")] = "1.38",
    delta_ratio: Annotated[str, _opt("delta-ratio", "δ/ε values.")] = "2",
    lipschitz: Annotated[
        str | None,
        _opt("lipschitz", "λ values, tight mode only; 'none' means no Lipschitz condition."),
    ] = None,
    mode: Annotated[
        str, typer.Option("--mode", help="Comma list of modes: paper, rigorous, tight.")
    ] = "rigorous,tight",
    target: TargetsOpt = "additive,ratio",
    lfs: Annotated[float, typer.Option("--lfs", help="Local feature size L_i.")] = 1.0,
    format: Annotated[
        TableFormat, typer.Option("--format", help="table for people, csv or json for programs.")
    ] = TableFormat.table,
    as_json: Json = False,
    output: Annotated[
        Path | None,
        typer.Option("--output", "-o", help="Write to this file (CSV unless --format json)."),
    ] = None,
    method: TightMethodOpt = MethodChoice.auto,
    jobs: Annotated[
        int,
        typer.Option("--jobs", help="Worker processes for tight rows (capped by rows and CPUs)."),
    ] = 1,
    max_rows: Annotated[
        int, typer.Option("--max-rows", help="Refuse grids with more rows than this.")
    ] = 100_000_000,
    yes: Annotated[
        bool,
        typer.Option("--yes", help="Run tight grids estimated to take longer than 10 minutes."),
    ] = False,
) -> None:
    """Sweep the parameters: ε* per (mode, target, λ, σ, ρ_f, δ/ε), or with --eps the bound
    per ε (on R − R̂ for the additive target, on R/R̂ for the ratio target).

    A row whose parameters admit no ε* has an empty ε* and its reason in the note column;
    every other problem stops the sweep with an error. Example:
    vorobound sweep --rho-f 1.2:1.5:4 --mode paper --format csv
    """
    from ..parallel import usable_workers
    from ..reports.sweep import SweepSpec, check_size, iter_sweep

    if jobs < 1:
        raise InputError(f"--jobs must be at least 1, got {jobs}")
    if as_json:
        format = TableFormat.json
    lams = [None] if lipschitz is None else parse_values(lipschitz, "--lipschitz", True)
    spec = SweepSpec(
        sigma=tuple(parse_values(sigma, "--sigma")),
        rho_f=tuple(parse_values(rho_f, "--rho-f")),
        delta_ratio=tuple(parse_values(delta_ratio, "--delta-ratio")),
        lipschitz=tuple(lams),
        modes=tuple(parse_modes(mode)),
        eps=None if eps is None else tuple(parse_values(eps, "--eps")),
        lfs=lfs,
        method=method.value,
        targets=tuple(parse_targets(target)),
    )
    workers = usable_workers(jobs, spec.tight_rows)
    check_size(spec, workers, max_rows=max_rows, allow_long=yes)
    if workers < jobs and spec.tight_rows:
        print(
            f"note: using {workers} worker process(es) (capped by rows and CPUs)", file=sys.stderr
        )
    if format is TableFormat.table and output is None and spec.rows > MAX_TABLE_ROWS:
        raise InputError(
            f"{spec.rows:,} rows are too many for a table; use --format csv or json, or -o FILE"
        )
    with progress_bar(spec.tight_rows > 0) as progress:
        rows = iter_sweep(spec, jobs=workers, progress=progress)
        if output is not None:
            from ..files import atomic_open

            kind = TableFormat.json if format is TableFormat.json else TableFormat.csv
            with atomic_open(output, "w") as handle:
                count = _write(rows, spec.columns, kind, handle)
        elif format is TableFormat.table:
            table = [[fmt(getattr(r, c), 8) for c in spec.columns] for r in rows]
        else:
            count = _write(rows, spec.columns, format, sys.stdout)
    if output is not None:
        print(f"wrote {count} rows to {output}", file=sys.stderr)
    elif format is TableFormat.table:
        print_table("vorobound sweep", spec.columns, table)


def _write(rows, columns: tuple[str, ...], format: TableFormat, handle) -> int:
    """Stream ``rows`` to ``handle`` as CSV or as a JSON array; return how many."""
    count = 0
    if format is TableFormat.csv:
        writer = csv.writer(handle, lineterminator="\n")
        writer.writerow(columns)
        for row in rows:
            values = (getattr(row, c) for c in columns)
            writer.writerow(
                ["" if v is None else repr(v) if isinstance(v, float) else v for v in values]
            )
            count += 1
        return count
    handle.write("[")
    for row in rows:
        record = {c: getattr(row, c) for c in columns}
        handle.write(
            ("," if count else "") + "\n  " + json.dumps(jsonable(record), allow_nan=False)
        )
        count += 1
    handle.write("\n]\n" if count else "]\n")
    return count
