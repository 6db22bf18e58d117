"""The README's advisor example: sampling advice for the unit sphere, per mode and target, and
the recommended ε."""

from vorobound.bounds.params import QualityParams
from vorobound.reports.advisor import advise
from vorobound.sampling.surfaces.analytic import SphereShape

COMMAND = "vorobound advise --sphere 1"


def render() -> str:
    advice = advise(QualityParams(), SphereShape(1.0).counts(), ["rigorous", "tight"])
    lines = [
        f"`{COMMAND}` (the table, condensed):",
        "",
        "| mode | target | ε* | claim | ball radius δL | samples (low–high) | vs ε = 1/500 |",
        "|---|---|---|---|---|---|---|",
    ]
    for a in advice.rows:
        versus = a.reduction_vs_1_500
        words = f"{versus:.2f}× fewer" if versus >= 1 else f"{1 / versus:.2f}× more"
        lines.append(
            f"| {a.mode} | {a.target} | {a.eps_star:.5g} | {a.claim} | {a.ball_radius:.5g} "
            f"| {a.samples_low:,.0f} – {a.samples_high:,.0f} | {words} |"
        )
    h3 = advice.h3_route
    lines.append(f"| H3 alone | (55) only | {h3.eps_star:.5g} | given H3 | | | — |")
    rec = advice.recommendation
    lines += [
        "",
        f"Recommended: ε = {rec.eps:.5g} ({rec.claim}, {rec.mode} mode, binding target "
        f"{rec.binding_target}), ball radius {rec.ball_radius:.5g}, "
        f"{rec.samples_low:,.0f} – {rec.samples_high:,.0f} samples, "
        f"{rec.reduction_vs_1_500:.2f}× fewer than at ε = 1/500.",
    ]
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    print(render(), end="")
