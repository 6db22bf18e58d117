"""The README's advisor example: sampling advice for the unit sphere, per mode."""

from vorobound.bounds.params import QualityParams
from vorobound.reports.advisor import advise
from vorobound.sampling.surfaces import sphere

COMMAND = "vorobound advise --sphere 1 --mode rigorous,tight"


def render() -> str:
    rows = advise(QualityParams(), sphere(1.0), ["rigorous", "tight"])
    lines = [
        f"`{COMMAND}` (the table, condensed):",
        "",
        "| mode | ε* | claim | ball radius δL | spacing σεL | samples (low–high) | vs ε = 1/500 |",
        "|---|---|---|---|---|---|---|",
    ]
    for a in rows:
        lines.append(
            f"| {a.mode} | {a.eps_star:.5g} | {a.claim} | {a.ball_radius:.5g} "
            f"| {a.min_spacing:.5g} | {a.samples_low:,.0f} – {a.samples_high:,.0f} "
            f"| {a.reduction_vs_1_500:.2f}× fewer |"
        )
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    print(render(), end="")
