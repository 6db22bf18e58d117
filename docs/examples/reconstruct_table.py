"""docs/reconstruct.md: M̂ of a sphere and two tori over ε, and every bound's ε* beside it
(seed 0, σ = 3/4, δ = 2ε; both seeds of every guide triangle, labelled by the surface, and the
labels from the union's sheets compared). The full table takes several minutes and about
3 GB (the tori at the smallest ε have 1–2·10⁵ samples).

The test recomputes one row (the sphere at ε = 0.45, under a second) and the ε* table with
``quick_check`` and checks them against the block.
"""

from vorobound.bounds.params import QualityParams
from vorobound.reports.reconstruct_sweep import bound_marks, reconstruct_sweep
from vorobound.sampling.surfaces.analytic import SphereShape, TorusShape

SURFACES = (SphereShape(1.0), TorusShape(3.0, 1.0), TorusShape(1.5, 1.0))
GRID = (0.1, 0.2, 0.3, 0.4, 0.45, 0.48, 0.5)
"""ε swept besides the ε* of the tight bounds with λ = 1 (the smallest ε* whose samples stay
small enough for the docs)."""
SWEPT_STARS = ("tight, λ = 1",)
QUICK = (0, 0.45)
"""(surface index, ε) of the row the test recomputes."""
FIRST_HEADER = (
    "| surface | ε | samples | facets of M̂ | M̂ | χ (surface's) | Hausdorff / (εL) | "
    "max normal deviation | smallest angle | sheet labels |\n"
    "|---|---|---|---|---|---|---|---|---|---|\n"
)
SECOND_HEADER = (
    "| bound | target | claim | ε* | "
    + " | ".join(s.name for s in SURFACES)
    + " |\n|---|---|---|---|"
    + "---|" * len(SURFACES)
    + "\n"
)


def eps_values(marks) -> list[tuple[float, str]]:
    """(ε, label) of the sweep: the marked ε* first, then the grid."""
    named = [
        (m.eps_star, f"{m.eps_star:.4g} ({m.label} {m.target} ε*)")
        for m in marks
        if m.label in SWEPT_STARS
    ]
    return sorted(named) + [(eps, f"{eps:g}") for eps in GRID]


def row_text(shape, label: str, row, expected) -> str:
    """One row of the first table."""
    if row.facets == 0:
        verdict = "none"
    elif row.topology_correct:
        verdict = "right"
    else:
        verdict = "**wrong**" + ("" if row.closed_manifold else " (not closed)")
    if row.sheet_note is not None:
        sheets = "not two sheets"
    elif row.sheet_disagreements is None:
        sheets = "n/a"
    else:
        sheets = "agree" if row.sheet_disagreements == 0 else f"{row.sheet_disagreements} differ"

    def number(value, digits=3, unit=""):
        return "n/a" if value is None else f"{value:.{digits}g}{unit}"

    samples = "" if row.samples is None else f"{row.samples:,}"
    return (
        f"| {shape.name} | {label} | {samples} | {row.facets:,} | {verdict} | "
        f"{row.euler_characteristic if row.facets else 'n/a'} ({expected.euler_characteristic}) | "
        f"{number(row.hausdorff)} | {number(row.normal_deviation_max, 3, '°')} | "
        f"{number(row.min_angle_min, 3, '°')} | {sheets} |\n"
    )


def verdict_at(star: float, rows) -> str:
    """What the sweep says about M̂ at ε ≤ ε*."""
    below = [row for row in rows if row.eps <= star * (1 + 1e-12)]
    if not below:
        return "below the sweep"
    wrong = [row for row in below if not row.topology_correct]
    if wrong:
        return f"wrong from ε = {wrong[0].eps:g}"
    return f"right at every swept ε ≤ ε* (Hausdorff ≤ {max(r.hausdorff for r in below):.3g})"


def second_table(marks, sweeps) -> str:
    lines = [
        f"| {m.label} | {m.target} | {m.claim} | {m.eps_star:.5g} | "
        + " | ".join(verdict_at(m.eps_star, sweep.rows) for sweep in sweeps)
        + " |\n"
        for m in marks
    ]
    return SECOND_HEADER + "".join(lines)


def render() -> str:
    quality = QualityParams()
    marks = bound_marks(quality)
    values = eps_values(marks)
    first, sweeps = [], []
    for shape in SURFACES:
        sweep = reconstruct_sweep(shape, [v for v, _ in values], quality, compare_sheets=True)
        sweeps.append(sweep)
        for (_, label), row in zip(values, sweep.rows, strict=True):
            first.append(row_text(shape, label, row, sweep.expected))
    return FIRST_HEADER + "".join(first) + "\n" + second_table(marks, sweeps)


def quick_check(block: str) -> None:
    """One row and the ε* column, recomputed."""
    quality = QualityParams()
    marks = bound_marks(quality)
    index, eps = QUICK
    shape = SURFACES[index]
    sweep = reconstruct_sweep(shape, [eps], quality, compare_sheets=True)
    row = row_text(shape, f"{eps:g}", sweep.rows[0], sweep.expected)
    assert row in block, row
    for m in marks:
        assert f"| {m.label} | {m.target} | {m.claim} | {m.eps_star:.5g} | " in block, m


if __name__ == "__main__":
    print(render())
