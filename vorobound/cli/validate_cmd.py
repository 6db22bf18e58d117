"""``vorobound validate``: audit every bound on sampled feasible guide triangles."""

from __future__ import annotations

from typing import Annotated

import typer

from .options import (
    DeltaRatio,
    Eps,
    Json,
    Lfs,
    Lipschitz,
    RhoF,
    Seed,
    Sigma,
    params_dict,
    quality_params,
)
from .progress import progress_bar
from .render import fmt, print_json, print_table


def validate(
    eps: Eps,
    samples: Annotated[
        int, typer.Option("--samples", help="Feasible configurations to draw (at most 2,000,000).")
    ] = 20000,
    seed: Seed = 0,
    lipschitz: Lipschitz = None,
    sigma: Sigma = 0.75,
    delta_ratio: DeltaRatio = 2.0,
    lfs: Lfs = 1.0,
    rho_f: RhoF = 1.38,
    no_tight: Annotated[
        bool, typer.Option("--no-tight", help="Do not compare with the tight supremum.")
    ] = False,
    as_json: Json = False,
) -> None:
    """Sample feasible guide triangles and check every printed inequality and every mode's bound.

    Samples are uniform over the constraint set and biased to its boundary. A printed step with
    violations is wrong (docs/errata.md); a rigorous or tight ratio above 1 would be a bug.
    """
    from ..reports.validate import validate as run_validation

    params = quality_params(sigma, delta_ratio, rho_f, lfs).at(eps)
    with progress_bar(not as_json) as progress:
        progress("sampling and auditing", 0, None)
        report = run_validation(params, samples, seed, lipschitz, tight=not no_tight)
    if as_json:
        print_json(
            {
                "params": params_dict(params.quality, params.eps),
                "samples": report.samples,
                "seed": report.seed,
                "lipschitz": report.lipschitz,
                "max_radius_gap": report.max_radius_gap,
                "inequalities": report.inequalities,
                "modes": report.modes,
            }
        )
        return
    print_table(
        f"Printed chain on {report.samples} feasible guide triangles (ε = {eps:g})",
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
