"""``vorobound sweep``: bound curves over ε or ε* tables over the parameters."""

from __future__ import annotations

import csv
import io
import json
from enum import Enum
from pathlib import Path
from typing import Annotated

import typer

from ..errors import VoroboundError
from .output import fmt, jsonable, print_table


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
        str | None, _opt("lipschitz", "λ values (tight mode only; 'none' = no condition).")
    ] = None,
    mode: Annotated[
        str, typer.Option("--mode", help="Comma list of modes: paper, rigorous, tight.")
    ] = "paper,rigorous",
    lfs: Annotated[float, typer.Option("--lfs", help="Local feature size L_i.")] = 1.0,
    format: Annotated[
        TableFormat, typer.Option("--format", help="table for people, csv or json for programs.")
    ] = TableFormat.table,
    output: Annotated[
        Path | None, typer.Option("--output", "-o", help="Write to this file instead of stdout.")
    ] = None,
    jobs: Annotated[int, typer.Option("--jobs", help="Processes for tight-mode rows.")] = 1,
) -> None:
    """Sweep the parameters: ε* per (mode, λ, σ, ρ_f, δ/ε), or with --eps the bound per ε.

    Example: vorobound sweep --rho-f 1.2:1.5:4 --mode paper
    """
    from ..bounds.params import Mode
    from ..reports.sweep import SweepSpec, parse_values, run_sweep

    try:
        modes = [Mode(m.strip()) for m in mode.split(",")]
    except ValueError:
        raise VoroboundError(f"--mode: expected paper, rigorous or tight, got {mode!r}") from None
    if jobs < 1:
        raise VoroboundError(f"--jobs must be at least 1, got {jobs}")
    if lipschitz is None or lipschitz.strip().lower() == "none":
        lams = [None]
    else:
        lams = parse_values(lipschitz, "lipschitz")
    spec = SweepSpec(
        sigma=parse_values(sigma, "sigma"),
        rho_f=parse_values(rho_f, "rho-f"),
        delta_ratio=parse_values(delta_ratio, "delta-ratio"),
        lipschitz=lams,
        modes=modes,
        eps=None if eps is None else parse_values(eps, "eps"),
        lfs=lfs,
    )
    tight_rows = sum(1 for c in spec.combos() if c[0] is Mode.tight) * len(spec.eps or [None])
    if tight_rows:
        from rich.console import Console
        from rich.progress import Progress

        with Progress(console=Console(stderr=True), transient=True) as progress:
            task = progress.add_task("tight rows", total=tight_rows)
            table = run_sweep(spec, jobs=jobs, step=lambda: progress.advance(task))
    else:
        table = run_sweep(spec)
    text = _render(table, format)
    if output is None:
        if text is not None:
            print(text, end="")
        else:
            print_table(
                "vorobound sweep", table.columns, [[_cell(v) for v in row] for row in table.rows]
            )
        return
    try:
        output.write_text(text if text is not None else _render(table, TableFormat.csv))
    except OSError as exc:
        raise VoroboundError(f"cannot write {output}: {exc.strerror}") from None
    print(f"wrote {len(table.rows)} rows to {output}")


def _cell(value) -> str:
    if value is None:
        return "—"
    return fmt(value, 8) if isinstance(value, float) else str(value)


def _render(table, format: TableFormat) -> str | None:
    if format is TableFormat.json:
        rows = [dict(zip(table.columns, row, strict=True)) for row in table.rows]
        return json.dumps(jsonable(rows), indent=2) + "\n"
    if format is TableFormat.csv:
        buffer = io.StringIO()
        writer = csv.writer(buffer, lineterminator="\n")
        writer.writerow(table.columns)
        for row in table.rows:
            writer.writerow(
                ["" if v is None else repr(v) if isinstance(v, float) else v for v in row]
            )
        return buffer.getvalue()
    return None
