"""``vorobound cheng``: Cheng et al.'s constant, the conjectured one, and the numeric supremum."""

from __future__ import annotations

from typing import Annotated

import typer

from .command import invoke
from .options import Json, Seed
from .render import fmt, print_table


def cheng(
    alpha: Annotated[
        float, typer.Option("--alpha", metavar="ALPHA", help="Weight factor α in [0, 1/2).")
    ],
    dim: Annotated[
        int,
        typer.Option(
            "--dim", metavar="2|3", help="2: triangles; 3: tetrahedra (circumsphere/orthosphere)."
        ),
    ] = 2,
    seed: Seed = 0,
    as_json: Json = False,
) -> int:
    """R/R̂ for weights in [0, α²N(s)²]: c_rad = 1/sqrt(1−4α²), the conjectured 1/sqrt(1−3α²),
    and the numerically maximized ratio (docs/cheng.md)."""
    return invoke("cheng", _show, locals())


def _show(result) -> None:
    print_table(
        f"Cheng et al. constant, α = {result.alpha:g}, "
        f"{'triangles' if result.dim == 2 else 'tetrahedra'}",
        ("quantity", "value"),
        [
            ("c_rad = 1/sqrt(1 − 4α²)", fmt(result.c_rad, 12)),
            ("conjectured 1/sqrt(1 − 3α²)", fmt(result.c_conjectured, 12)),
            (
                "numeric sup R/R̂",
                "unbounded (grows like 1/height)"
                if result.unbounded
                else fmt(result.numeric_sup, 12),
            ),
        ],
    )
