"""``vorobound sweep``: ε* tables over the parameters, or bound curves over ε.

Rows are written as they are computed (CSV and JSON), so memory stays bounded whatever the
grid size; ``-o FILE`` writes to a temporary file that replaces FILE only when the sweep ends.
"""

from __future__ import annotations

import sys
from enum import Enum
from pathlib import Path
from typing import Annotated

import typer

from ..constants import PAPER_DELTA_RATIO, PAPER_RHO_F, PAPER_SIGMA
from ..errors import InputError
from ..rounding import format_toward
from .options import (
    Json,
    MethodChoice,
    ModesOpt,
    TargetsOpt,
    TightMethodOpt,
    parse_modes,
    parse_targets,
    parse_values,
)
from .progress import progress_bar
from .render import fmt, print_table

MAX_TABLE_ROWS = 10_000
"""Larger sweeps are written as CSV or JSON, not drawn as a table."""


class TableFormat(str, Enum):
    table = "table"
    csv = "csv"
    json = "json"


def _opt(name: str, help_: str):
    return typer.Option(
        f"--{name}", metavar="VALUES", help=help_ + " Range start:stop:num or a comma list."
    )


def sweep(
    eps: Annotated[str | None, _opt("eps", "ε values: gives bound curves instead of ε*.")] = None,
    sigma: Annotated[str, _opt("sigma", "Sparsity σ values.")] = f"{PAPER_SIGMA:g}",
    rho_f: Annotated[str, _opt("rho-f", "Quality constant ρ_f values.")] = f"{PAPER_RHO_F:g}",
    delta_ratio: Annotated[str, _opt("delta-ratio", "δ/ε values.")] = f"{PAPER_DELTA_RATIO:g}",
    lipschitz: Annotated[
        str | None,
        _opt("lipschitz", "λ values, tight mode only; 'none' means no Lipschitz condition."),
    ] = None,
    mode: ModesOpt = "rigorous,tight",
    target: TargetsOpt = "additive,ratio",
    lfs: Annotated[float, typer.Option("--lfs", metavar="L", help="Local feature size L_i.")] = 1.0,
    format: Annotated[
        TableFormat, typer.Option("--format", help="table for people, csv or json for programs.")
    ] = TableFormat.table,
    as_json: Json = False,
    output: Annotated[
        Path | None,
        typer.Option(
            "--output",
            "-o",
            metavar="FILE",
            help="Write the rows to FILE: .csv or .json (from the suffix; others are refused).",
        ),
    ] = None,
    method: TightMethodOpt = MethodChoice.auto,
    jobs: Annotated[
        int,
        typer.Option(
            "--jobs", metavar="N", help="Worker processes for tight rows (capped by rows and CPUs)."
        ),
    ] = 1,
    max_rows: Annotated[
        int, typer.Option("--max-rows", metavar="N", help="Refuse grids with more rows than this.")
    ] = 100_000_000,
    yes: Annotated[
        bool,
        typer.Option(
            "--yes", metavar="", help="Run tight grids estimated to take longer than 10 minutes."
        ),
    ] = False,
) -> None:
    """Sweep the parameters: ε* per (mode, target, λ, σ, ρ_f, δ/ε), or with --eps the bound
    per ε (on R − R̂ for the additive target, on R/R̂ for the ratio target).

    A row whose parameters admit no ε* has an empty ε* and its reason in the note column;
    every other problem stops the sweep with an error. -o FILE writes .csv or .json (from the
    suffix). Example: vorobound sweep --rho-f 1.2:1.5:4 --mode paper --format csv.
    Python: vorobound.sweep(rho_f=[1.2, 1.3], ...).
    """
    from ..api.sweep import prepare, sweep_spec, workers_for, write_sweep
    from ..reports.sweep import iter_sweep

    if as_json:
        format = TableFormat.json
    lams = [None] if lipschitz is None else parse_values(lipschitz, "--lipschitz", True)
    spec = sweep_spec(
        sigma=parse_values(sigma, "--sigma"),
        rho_f=parse_values(rho_f, "--rho-f"),
        delta_ratio=parse_values(delta_ratio, "--delta-ratio"),
        lipschitz=lams,
        mode=parse_modes(mode),
        eps=None if eps is None else parse_values(eps, "--eps"),
        lfs=lfs,
        method=method.value,
        target=parse_targets(target),
    )
    if jobs < 1:
        raise InputError(f"--jobs must be at least 1, got {jobs}")
    prepare(spec, jobs, max_rows, yes)
    workers = workers_for(spec, jobs)
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
            from ..api.sweep import output_format
            from ..files import atomic_open

            kind = output_format(output)
            with atomic_open(output, "w") as handle:
                count = write_sweep(rows, spec, handle, kind)
        elif format is TableFormat.table:
            from ..reports.sweep import COLUMN_ROUNDING

            table = [
                [_cell(getattr(r, c), COLUMN_ROUNDING.get(c)) for c in spec.columns] for r in rows
            ]
        else:
            count = write_sweep(rows, spec, sys.stdout, format.value)
    if output is not None:
        print(f"wrote {count} rows to {output}", file=sys.stderr)
    elif format is TableFormat.table:
        print_table("vorobound sweep", spec.columns, table)


def _cell(value, direction) -> str:
    """A table cell: ε* rounded down, bounds up, the rest to nearest (8 digits)."""
    if value is None or isinstance(value, str):
        return fmt(value)
    return format_toward(value, direction, 8)
