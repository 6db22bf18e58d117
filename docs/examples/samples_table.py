"""docs/samples.md: real samples of a sphere and two tori, their guide triangles against every
bound of both targets and against H3 (seed 0, σ = 3/4, δ = 2ε, ρ_f = 1.38; about 10 minutes,
3 GB).

The test recomputes one row (the torus (1.5, 1) at ε = 0.03, a few seconds) with
``quick_check`` and checks it against the table.
"""

from vorobound.bounds.params import QualityParams
from vorobound.bounds.tight.method import tight_eps_star
from vorobound.constants import PAPER_EPS
from vorobound.reports.check import check_surface
from vorobound.rounding import format_down, format_up
from vorobound.sampling.surfaces.analytic import SphereShape, TorusShape

CASES = (
    ("sphere", (1.0,), ("0.03", "tight", "0.01", "ratio", "0.005", "paper")),
    ("torus", (3.0, 1.0), ("0.03", "tight", "0.01", "ratio")),
    ("torus", (1.5, 1.0), ("0.03", "tight", "0.01", "ratio")),
)
"""Surfaces and ε (numbers, or the paper's / the tight additive / the tight ratio ε*) whose
samples fit in memory."""
FIRST_HEADER = (
    "| surface | ε | samples | guide triangles | half-covered share | coverage_max | "
    "sparsity_min | max R/(δL_i) | outside constraint set |\n"
    "|---|---|---|---|---|---|---|---|---|\n"
)
SECOND_HEADER = (
    "| surface | ε | max (R − R̂)/(εL_i) | paper | rigorous | tight | tight, λ = 1 |\n"
    "|---|---|---|---|---|---|---|\n"
)
THIRD_HEADER = (
    "| surface | ε | max R/R̂ | tight sup R/R̂ | tight, λ = 1 | above ρ_f = 1.38 | "
    "max R(1−ε)/(εL_i) (H3: ≤ 1) |\n"
    "|---|---|---|---|---|---|---|\n"
)
MODES = ("paper", "rigorous", "tight", "tight_lipschitz")


def rows(kind: str, dims: tuple, value: str) -> tuple[str, str, str]:
    """The three table rows of one surface and ε."""
    quality = QualityParams()
    named = {
        "paper": PAPER_EPS,
        "tight": tight_eps_star(quality.but(target="additive")).eps_star,
        "ratio": tight_eps_star(quality.but(target="ratio")).eps_star,
    }
    shape = TorusShape(*dims) if kind == "torus" else SphereShape(*dims)
    eps = named.get(value) or float(value)
    names = {"paper": "paper ε*", "tight": "tight ε*", "ratio": "tight ratio ε*"}
    # a named ε* is printed rounded down (vorobound.rounding), as every admissible ε
    label = (format_down(eps, 6) + f" ({names[value]})") if value in named else f"{eps:.6g}"
    s = check_surface(shape, eps, quality, seed=0).summary()
    first = (
        f"| {shape.name} | {label} | {s['n_samples']:,} | {s['n_guide_triangles']:,} | "
        f"{100 * s['half_covered_share']:.2f} % | {s['coverage_max']:.4f} | "
        f"{s['sparsity_min']:.9f} | {s['rho_max']:.4f} | {s['outside_constraint_set']} |\n"
    )
    gap = s["gap_ratio_max"]
    cells = []
    for mode in MODES:
        bound = s["bound"][mode]["gap_ratio"]
        over = s["violations"][mode]
        ratio = "" if bound is None or bound == 0 else f" ({gap / bound:.3f})"
        text = "n/a" if bound is None else format_up(bound, 4)
        cells.append(text + ratio + (f", {over} above" if over else ""))
    second = f"| {shape.name} | {label} | {gap:.4g} | " + " | ".join(cells) + " |\n"
    sups = [s["ratio_bound"][mode]["value"] for mode in ("tight", "tight_lipschitz")]
    sup_cells = [
        "∞" if sup is None else f"{format_up(sup, 4)} ({s['ratio_max'] / sup:.3f})" for sup in sups
    ]
    third = (
        f"| {shape.name} | {label} | {s['ratio_max']:.4f} | "
        + " | ".join(sup_cells)
        + f" | {s['ratio_violations']} | {s['h3_ratio_max']:.4f} |\n"
    )
    return first, second, third


def render() -> str:
    rows_ = [rows(kind, dims, value) for kind, dims, values in CASES for value in values]
    return (
        FIRST_HEADER
        + "".join(r[0] for r in rows_)
        + "\n"
        + SECOND_HEADER
        + "".join(r[1] for r in rows_)
        + "\n"
        + THIRD_HEADER
        + "".join(r[2] for r in rows_)
    )


def quick_check(block: str) -> None:
    assert block.startswith(FIRST_HEADER)
    first, second, third = rows("torus", (1.5, 1.0), "0.03")
    stale = "docs/samples.md is stale: run python scripts/update_docs.py"
    assert first in block and second in block and third in block, stale


if __name__ == "__main__":
    print(render(), end="")
