"""``vorobound figure`` and ``vorobound reproduce``: the paper's figure and numbers."""

from __future__ import annotations

from enum import Enum
from pathlib import Path
from typing import Annotated

import typer

from .common import DeltaRatio, Json, Lfs, RhoF, Sigma, make_params, params_dict
from .output import fmt, print_json, print_table

TIGHT_SETTINGS = (None, 1.0)
"""Tight-mode variants shown: the paper's constraints, and with the 1-Lipschitz condition."""


class FigureFormat(str, Enum):
    png = "png"
    pdf = "pdf"
    svg = "svg"


Out = Annotated[Path, typer.Option("--out", help="Folder to write the figures into.")]
NoTight = Annotated[
    bool, typer.Option("--no-tight", help="Skip the tight mode (its optimizations take time).")
]


def _progress(enabled: bool, total: int):
    """A rich progress bar on stderr, or a no-op, as a context manager yielding step()."""
    import contextlib

    @contextlib.contextmanager
    def bar():
        if not enabled or total == 0:
            yield lambda: None
            return
        from rich.console import Console
        from rich.progress import Progress

        with Progress(console=Console(stderr=True), transient=True) as progress:
            task = progress.add_task("tight curves", total=total)
            yield lambda: progress.advance(task)

    return bar()


def write_figures(params, out: Path, fmt_: str, tight_stars: dict, progress: bool) -> list[Path]:
    """Figure 3 and the comparison of modes; ``tight_stars`` maps λ (or None) to its ε*."""
    from ..plotting import plot_comparison, plot_figure3, save
    from ..reports.figure_data import (
        TIGHT_CURVE_POINTS,
        chain_curve,
        comparison_data,
        figure3_data,
        tight_curve,
    )

    paths = [save(plot_figure3(figure3_data(params)), out, "figure3", fmt_)]
    curves = [chain_curve(params, mode) for mode in ("paper", "rigorous")]
    with _progress(progress, TIGHT_CURVE_POINTS * len(tight_stars)) as step:
        for lipschitz, star in tight_stars.items():
            curves.append(tight_curve(params, star, lipschitz, step))
    paths.append(save(plot_comparison(comparison_data(curves, params)), out, "comparison", fmt_))
    return paths


def _tight_stars(params, progress: bool) -> dict:
    from ..bounds.tight import solve_tight

    return {lam: solve_tight(params, lipschitz=lam, progress=progress) for lam in TIGHT_SETTINGS}


def figure(
    out: Out = Path("figures"),
    format: Annotated[
        FigureFormat, typer.Option("--format", help="File format of the figures.")
    ] = FigureFormat.png,
    sigma: Sigma = 0.75,
    delta_ratio: DeltaRatio = 2.0,
    lfs: Lfs = 1.0,
    rho_f: RhoF = 1.38,
    no_tight: NoTight = False,
    as_json: Json = False,
) -> None:
    """Regenerate all figures: Figure 3 of the paper and the comparison of modes."""
    params = make_params(0.5, sigma, delta_ratio, lfs, rho_f)
    stars = {} if no_tight else _tight_stars(params, progress=not as_json)
    paths = write_figures(params, out, format.value, stars, progress=not as_json)
    if as_json:
        print_json({"figures": [str(p) for p in paths]})
    else:
        for path in paths:
            print(f"wrote {path}")


def reproduce(
    out: Out = Path("figures"),
    sigma: Sigma = 0.75,
    delta_ratio: DeltaRatio = 2.0,
    lfs: Lfs = 1.0,
    rho_f: RhoF = 1.38,
    no_tight: NoTight = False,
    as_json: Json = False,
) -> None:
    """Every number the paper states beside this project's value for each mode; writes figures.

    Modes: paper (the printed chain), rigorous (corrected chain, docs/errata.md), tight (exact
    supremum over feasible guide triangles) and tight with the 1-Lipschitz condition (λ = 1).
    """
    from ..reports.reproduce import reproduction_rows, summarize_chain, summarize_tight

    params = make_params(0.5, sigma, delta_ratio, lfs, rho_f)
    summaries = [summarize_chain(params, mode) for mode in ("paper", "rigorous")]
    if not no_tight:
        summaries += [summarize_tight(params, lam, progress=not as_json) for lam in TIGHT_SETTINGS]
    rows = reproduction_rows(params, summaries)
    stars = {lam: s.star for lam, s in zip(TIGHT_SETTINGS, summaries[2:], strict=False)}
    paths = write_figures(params, out, "png", stars, progress=not as_json)
    if as_json:
        print_json(
            {
                "params": params_dict(params),
                "eps_star": {s.mode: s.star.eps_star for s in summaries},
                "rows": [
                    {"quantity": r.quantity, "paper": r.paper, "values": r.values} for r in rows
                ],
                "figures": [str(p) for p in paths],
            }
        )
        return
    modes = [s.mode for s in summaries]
    print_table(
        "The paper's claims and this project's values",
        ("quantity", "paper says", *modes),
        [(r.quantity, r.paper, *(fmt(r.values[m], 5) for m in modes)) for r in rows],
    )
    for path in paths:
        print(f"wrote {path}")
