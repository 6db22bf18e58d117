"""The README's advisor example: sampling advice for the unit sphere, per mode and target, and
the recommended ε."""

from vorobound.bounds.params import QualityParams
from vorobound.reports.advisor import advise, versus_baseline
from vorobound.rounding import format_down
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
        lines.append(
            f"| {a.mode} | {a.target} | {format_down(a.eps_star)} | {a.claim} "
            f"| {format_down(a.ball_radius)} | {a.samples_low:,.0f} – {a.samples_high:,.0f} "
            f"| {versus_baseline(a.reduction_vs_1_500)} |"
        )
    h3 = advice.h3_route
    lines.append(f"| H3 alone | (55) only | {format_down(h3.eps_star)} | given H3 | | | — |")
    rec = advice.recommendation
    lines += [
        "",
        f"Recommended: ε = {format_down(rec.eps)} ({rec.claim}, {rec.mode} mode, binding target "
        f"{rec.binding_target}), ball radius {format_down(rec.ball_radius)}, "
        f"{rec.samples_low:,.0f} – {rec.samples_high:,.0f} samples, "
        f"{versus_baseline(rec.reduction_vs_1_500)} than at ε = 1/500.",
    ]
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    print(render(), end="")
