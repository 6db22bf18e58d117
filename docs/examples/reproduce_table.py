"""The README's table: every number the paper states beside this project's value per mode,
for the paper's additive target and for the ratio target R ≤ ρ_f·R̂ (eq. (54)).

Command: ``vorobound reproduce`` (the same table, with the figures).
"""

from vorobound.bounds.params import QualityParams
from vorobound.reports.reproduce import reproduce
from vorobound.rounding import format_toward


def render() -> str:
    summaries, rows = reproduce(QualityParams())
    modes = [s.mode.replace("λ=", "λ = ").replace("tight λ", "tight, λ") for s in summaries]
    lines = [
        "| quantity | paper says | " + " | ".join(modes) + " |",
        "|---" * (len(modes) + 2) + "|",
    ]
    for row in rows:
        cells = [_cell(row.values[s.mode], row.rounding) for s in summaries]
        quantity = row.quantity.replace("|", "\\|")
        lines.append(f"| {quantity} | {row.paper} | " + " | ".join(cells) + " |")
    lines.append("| claim | — | " + " | ".join(s.star.claim for s in summaries) + " |")
    return "\n".join(lines) + "\n"


def _cell(value, rounding: str) -> str:
    if value is None:
        return "—"
    return format_toward(value, rounding)


if __name__ == "__main__":
    print(render(), end="")
