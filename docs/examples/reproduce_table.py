"""The README's table: every number the paper states beside this project's value per mode.

Command: ``vorobound reproduce`` (the same table, with the figures).
"""

from vorobound.bounds.params import QualityParams
from vorobound.bounds.tight.method import tight_eps_star
from vorobound.reports.figure_data import TIGHT_SETTINGS
from vorobound.reports.reproduce import reproduction_rows, summarize_chain, summarize_tight


def render() -> str:
    quality = QualityParams()
    summaries = [summarize_chain(quality, mode) for mode in ("paper", "rigorous")]
    for lam in TIGHT_SETTINGS:
        summaries.append(summarize_tight(quality, lam, tight_eps_star(quality, lam)))
    modes = [s.mode.replace("λ=", "λ = ").replace("tight λ", "tight, λ") for s in summaries]
    lines = [
        "| quantity | paper says | " + " | ".join(modes) + " |",
        "|---" * (len(modes) + 2) + "|",
    ]
    for row in reproduction_rows(quality, summaries):
        cells = [
            "—" if row.values[s.mode] is None else f"{row.values[s.mode]:.5g}" for s in summaries
        ]
        quantity = row.quantity.replace("|", "\\|")
        lines.append(f"| {quantity} | {row.paper} | " + " | ".join(cells) + " |")
    lines.append("| claim | — | " + " | ".join(s.star.claim for s in summaries) + " |")
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    print(render(), end="")
