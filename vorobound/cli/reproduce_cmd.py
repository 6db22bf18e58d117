"""``vorobound reproduce``: every number the paper states beside this project's values."""

from __future__ import annotations

from ..api.figures import DEFAULT_OUT
from ..rounding import format_toward
from .command import grouped, invoke
from .options import Json, NoTight, Out, QualityOptions
from .render import print_table


def _cell(value, rounding: str) -> str:
    if value is None:
        return "—"
    return format_toward(value, rounding)


@grouped
def reproduce(
    out: Out = DEFAULT_OUT,
    quality: QualityOptions = QualityOptions(),
    no_tight: NoTight = False,
    as_json: Json = False,
) -> int:
    """Every number the paper states beside this project's value for each mode; writes figures.

    Modes: paper (the printed chain: invalid), rigorous (the corrected chain: proven), tight
    (the supremum over the constraint set: proven in closed form, docs/tight.md) and tight with
    the 1-Lipschitz condition (λ = 1). The paper's target is the additive one, R − R̂ ≤
    (ρ_f − 1)·δ·L_i; the table adds the ratio target R ≤ ρ_f·R̂ (eq. (54)) and the ε up to which
    H3 alone gives (55). The tight modes are also certified by interval arithmetic up to
    0.999·ε* for both targets (`vorobound certify` writes the file).
    """
    return invoke("reproduce", _show, locals())


def _show(result) -> None:
    summaries, rows = result.summaries, result.rows
    modes = [s.mode for s in summaries]
    print_table(
        "The paper's claims and this project's values",
        ("quantity", "paper says", *modes),
        [(r.quantity, r.paper, *(_cell(r.values[m], r.rounding) for m in modes)) for r in rows],
    )
    print("claims: " + ", ".join(f"{s.mode}: {s.star.claim}" for s in summaries))
    for path in result.written:
        print(f"wrote {path}")
