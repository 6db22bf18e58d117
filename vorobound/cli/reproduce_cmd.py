"""``vorobound reproduce``: every number the paper states beside this project's values."""

from __future__ import annotations

from .figure_cmd import DEFAULT_OUT, NoTight, Out, tight_stars, write_figures
from .options import DeltaRatio, Json, Lfs, RhoF, Sigma, params_dict, quality_params
from .progress import progress_bar
from .render import fmt, print_json, print_table


def _cell(value) -> str:
    if value is None:
        return "—"
    return "∞" if value == float("inf") else fmt(value, 5)


def reproduce(
    out: Out = DEFAULT_OUT,
    sigma: Sigma = 0.75,
    delta_ratio: DeltaRatio = 2.0,
    lfs: Lfs = 1.0,
    rho_f: RhoF = 1.38,
    no_tight: NoTight = False,
    as_json: Json = False,
) -> None:
    """Every number the paper states beside this project's value for each mode; writes figures.

    Modes: paper (the printed chain: invalid), rigorous (the corrected chain: proven), tight
    (the supremum over the constraint set: proven in closed form, docs/tight.md) and tight with
    the 1-Lipschitz condition (λ = 1). The paper's target is the additive one, R − R̂ ≤
    (ρ_f − 1)·δ·L_i; the table adds the ratio target R ≤ ρ_f·R̂ (eq. (54)) and the ε up to which
    H3 alone gives (55). The tight modes are also certified by interval arithmetic up to
    0.999·ε* for both targets (`vorobound certify` writes the file).
    """
    from ..reports.reproduce import reproduce as run_reproduce

    quality = quality_params(sigma, delta_ratio, rho_f, lfs)
    with progress_bar(not as_json) as progress:
        summaries, rows = run_reproduce(quality, tight=not no_tight, progress=progress)
        stars = {}
        if not no_tight:
            stars = tight_stars(quality, progress)
        paths = write_figures(quality, out, "png", stars, progress)
    if as_json:
        print_json(
            {
                "params": params_dict(quality),
                "eps_star": {s.mode: s.star.eps_star for s in summaries},
                "eps_star_ratio": {s.mode: s.ratio_star.eps_star for s in summaries},
                "claims": {s.mode: s.star.claim for s in summaries},
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
        [(r.quantity, r.paper, *(_cell(r.values[m]) for m in modes)) for r in rows],
    )
    print("claims: " + ", ".join(f"{s.mode}: {s.star.claim}" for s in summaries))
    for path in paths:
        print(f"wrote {path}")
