"""``vorobound figure``: regenerate the figures (Figure 3 of the paper, comparison of modes)."""

from __future__ import annotations

from enum import Enum
from pathlib import Path
from typing import Annotated

import typer

from .options import DeltaRatio, Json, Lfs, RhoF, Sigma, quality_params
from .progress import progress_bar
from .render import print_json

DEFAULT_OUT = Path("vorobound-figures")
"""Default output folder (not the repository's committed figures/)."""

Out = Annotated[
    Path,
    typer.Option(
        "--out", help=f"Folder to write the figures into (default: ./{DEFAULT_OUT}, created)."
    ),
]
NoTight = Annotated[
    bool, typer.Option("--no-tight", help="Skip the tight mode (its optimizations take time).")
]


class FigureFormat(str, Enum):
    png = "png"
    pdf = "pdf"
    svg = "svg"


def write_figures(quality, out: Path, fmt_: str, tight_stars: dict, progress) -> list[Path]:
    """Figure 3 and the comparison of modes, written as one set (all files or none)."""
    from ..plotting import plot_comparison, plot_figure3, save_set
    from ..reports.figure_data import figure_set_data

    figure3, comparison = figure_set_data(quality, tight_stars, progress)
    figures = {"figure3": plot_figure3(figure3), "comparison": plot_comparison(comparison)}
    return save_set(figures, out, fmt_)


def tight_stars(quality, progress) -> dict:
    """The tight ε* for each setting of :data:`vorobound.reports.figure_data.TIGHT_SETTINGS`."""
    from ..bounds.tight.method import tight_eps_star
    from ..reports.figure_data import TIGHT_SETTINGS

    return {lam: tight_eps_star(quality, lam, progress=progress) for lam in TIGHT_SETTINGS}


def figure(
    out: Out = DEFAULT_OUT,
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
    """Regenerate all figures: Figure 3 of the paper and the comparison of modes.

    The set is replaced as a whole: if anything fails, the previous files stay as they were.
    """
    quality = quality_params(sigma, delta_ratio, rho_f, lfs)
    with progress_bar(not as_json) as progress:
        stars = {} if no_tight else tight_stars(quality, progress)
        paths = write_figures(quality, out, format.value, stars, progress)
    if as_json:
        print_json({"figures": [str(p) for p in paths]})
    else:
        for path in paths:
            print(f"wrote {path}")
