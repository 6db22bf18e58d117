"""``vorobound validate``: audit every bound on sampled feasible guide triangles."""

from __future__ import annotations

from typing import Annotated

import typer

from .command import grouped, invoke
from .options import (
    Eps,
    Json,
    Lipschitz,
    QualityOptions,
    Seed,
)
from .render import fmt, print_table

SAMPLES = "Feasible configurations to draw (at most 2,000,000)."
"""--samples of validate."""


@grouped
def validate(
    eps: Eps,
    samples: Annotated[int, typer.Option("--samples", metavar="N", help=SAMPLES)] = 20000,
    seed: Seed = 0,
    lipschitz: Lipschitz = None,
    quality: QualityOptions = QualityOptions(),
    no_tight: Annotated[
        bool, typer.Option("--no-tight", metavar="", help="Do not compare with the tight supremum.")
    ] = False,
    as_json: Json = False,
) -> int:
    """Sample feasible guide triangles and check every printed inequality and every mode's bound.

    Samples are uniform over the constraint set and biased to its boundary. A printed step with
    violations is wrong (docs/errata.md); a rigorous or tight ratio above 1 would be a bug (exit
    code 1). Python: vorobound.validate(eps=...).
    """
    return invoke("validate", _show, locals())


def _show(result) -> None:
    report = result.report
    print_table(
        f"Printed chain on {report.samples} feasible guide triangles (ε = {result.eps:g})",
        ("equation", "checked", "violations", "worst value/bound"),
        [
            (label, str(a.checked), str(a.violations), fmt(a.worst_ratio, 6))
            for label, a in report.inequalities.items()
        ],
    )
    print_table(
        "Largest observed (R − R̂) / bound",
        ("mode", "ratio", "verdict"),
        [(mode, fmt(r, 6), "holds" if r <= 1 else "EXCEEDED") for mode, r in report.modes.items()],
    )
