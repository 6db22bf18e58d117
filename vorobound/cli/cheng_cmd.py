"""``vorobound cheng``: Cheng et al.'s constant, the conjectured one, and the numeric supremum."""

from __future__ import annotations

import math
from typing import Annotated

import typer

from .options import Json, Seed
from .progress import progress_bar
from .render import fmt, print_json, print_table


def cheng(
    alpha: Annotated[float, typer.Option("--alpha", help="Weight factor α in [0, 1/2).")],
    dim: Annotated[
        int, typer.Option("--dim", help="2: triangles; 3: tetrahedra (circumsphere/orthosphere).")
    ] = 2,
    seed: Seed = 0,
    as_json: Json = False,
) -> None:
    """R/R̂ for weights in [0, α²N(s)²]: c_rad = 1/sqrt(1−4α²), the conjectured 1/sqrt(1−3α²),
    and the numerically maximized ratio (docs/cheng.md)."""
    from ..studies.cheng import cheng_constants

    with progress_bar(not as_json) as progress:
        progress("global search and polishes", 0, None)
        result = cheng_constants(alpha, dim=dim, seed=seed)
    unbounded = math.isinf(result.numeric_sup)
    if as_json:
        print_json(
            {
                "alpha": result.alpha,
                "dim": result.dim,
                "c_rad": result.c_rad,
                "c_conjectured": result.c_conjectured,
                "numeric_sup": result.numeric_sup,
                "unbounded": unbounded,
                "maximizer": result.maximizer,
                "evidence": result.evidence,
            }
        )
        return
    print_table(
        f"Cheng et al. constant, α = {alpha:g}, {'triangles' if dim == 2 else 'tetrahedra'}",
        ("quantity", "value"),
        [
            ("c_rad = 1/sqrt(1 − 4α²)", fmt(result.c_rad, 12)),
            ("conjectured 1/sqrt(1 − 3α²)", fmt(result.c_conjectured, 12)),
            (
                "numeric sup R/R̂",
                "unbounded (grows like 1/height)" if unbounded else fmt(result.numeric_sup, 12),
            ),
        ],
    )
