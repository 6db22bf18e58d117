"""docs/reconstruct.md: M̂ of a sphere and two tori over ε, 8 draws of the sampler per ε (seeds
0–7), the transition band of each surface, and every bound's ε* beside it (σ = 3/4, δ = 2ε;
both seeds of every guide triangle, labelled by the surface, and the labels from the union's
sheets compared).

The full table takes about 6 CPU-minutes (8 draws of 3 surfaces at 8 ε). ``--cache DIR``
keeps each (surface, ε) cell in DIR so the work can be split into several runs
(``--surface I`` computes the cells of one surface only and prints nothing); the table is
printed when every cell is there.

The test recomputes one cell (the sphere at ε = 0.45, 8 draws, a few seconds) and the ε* table
with ``quick_check`` and checks them against the block.
"""

import argparse
import json
from collections import Counter
from pathlib import Path

from vorobound.bounds.params import QualityParams
from vorobound.reports.reconstruct import MhatOptions
from vorobound.reports.reconstruct_draws import DrawsRow, ReconstructDraws, reconstruct_draws
from vorobound.reports.reconstruct_sweep import SweepRow, bound_marks
from vorobound.rounding import format_down
from vorobound.sampling.surfaces.analytic import SphereShape, TorusShape

SURFACES = (SphereShape(1.0), TorusShape(3.0, 1.0), TorusShape(1.5, 1.0))
REPEATS = 8
"""Draws per ε (seeds 0 to 7)."""
GRID = (0.2, 0.3, 0.4, 0.42, 0.45, 0.46, 0.48, 0.5)
"""ε swept, finer where M̂ breaks. Every bound's ε* lies below it except H3's: 8 draws of
the tori at the ε* themselves (2·10⁴ to 2·10⁵ samples each) cost too much for the docs."""
QUICK = (0, 0.45)
"""(surface index, ε) of the cell the test recomputes."""
FIRST_HEADER = (
    "| surface | ε | samples (median) | M̂ right in | Hausdorff / (εL), median (max) | "
    "max normal deviation, median (max) | smallest angle, min | sheet labels |\n"
    "|---|---|---|---|---|---|---|---|\n"
)
BAND_HEADER = (
    "| surface | every draw right up to ε | no draw right from ε | share right between |\n"
    "|---|---|---|---|\n"
)
SECOND_HEADER = (
    "| bound | target | claim | ε* | "
    + " | ".join(s.name for s in SURFACES)
    + " |\n|---|---|---|---|"
    + "---|" * len(SURFACES)
    + "\n"
)


def eps_values() -> list[tuple[float, str]]:
    """(ε, label) of the sweep."""
    return [(eps, f"{eps:g}") for eps in GRID]


def number(value, digits=3, unit=""):
    return "n/a" if value is None else f"{value:.{digits}g}{unit}"


def spread_text(spread, unit=""):
    if spread.median is None:
        return "n/a"
    return f"{number(spread.median, 3, unit)} ({number(spread.max, 3, unit)})"


def verdict_text(row: DrawsRow) -> str:
    """Draws with the right M̂, and why the others are wrong."""
    why = Counter(
        "no M̂" if d.facets == 0 else "not closed" if not d.closed_manifold else "wrong χ"
        for d in row.draws
        if not d.ok
    )
    reasons = ", ".join(f"{n} {reason}" for reason, n in sorted(why.items()))
    text = f"{row.correct}/{len(row.draws)}"
    return text if not reasons else f"**{text}** ({reasons})"


def sheets_text(row: DrawsRow) -> str:
    def one(d: SweepRow) -> str:
        if d.sheet_note is not None:
            return "not two sheets"
        if d.sheet_disagreements is None:
            return "n/a"
        return "agree" if d.sheet_disagreements == 0 else "differ"

    counts = Counter(one(d) for d in row.draws)
    return ", ".join(f"{kind} {n}/{len(row.draws)}" for kind, n in sorted(counts.items()))


def row_text(shape, label: str, row: DrawsRow) -> str:
    """One line of the first table (one surface, one ε, every draw)."""
    samples = [d.samples for d in row.draws if d.samples is not None]
    median = "" if not samples else f"{sorted(samples)[len(samples) // 2]:,}"
    angles = [d.min_angle_min for d in row.draws if d.min_angle_min is not None]
    return (
        f"| {shape.name} | {label} | {median} | {verdict_text(row)} | "
        f"{spread_text(row.hausdorff)} | {spread_text(row.normal_deviation_max, '°')} | "
        f"{number(min(angles), 3, '°') if angles else 'n/a'} | {sheets_text(row)} |\n"
    )


def band_text(draws: ReconstructDraws) -> str:
    low, high = draws.largest_all_correct_eps, draws.smallest_none_correct_eps
    between = [
        f"{r.correct}/{len(r.draws)} at {r.eps:g}"
        for r in draws.rows
        if (low is None or r.eps > low) and (high is None or r.eps < high)
    ]
    return (
        f"| {draws.source} | {'none' if low is None else f'{low:g}'} | "
        f"{'beyond the sweep' if high is None else f'{high:g}'} | "
        f"{', '.join(between) or '(adjacent swept ε)'} |\n"
    )


def verdict_at(star: float, rows) -> str:
    """What the draws say about M̂ at ε ≤ ε*."""
    below = [row for row in rows if row.eps <= star * (1 + 1e-12)]
    if not below:
        return "below the sweep"
    wrong = [row for row in below if row.correct < len(row.draws)]
    if wrong:
        return f"wrong in some draw from ε = {wrong[0].eps:g}"
    largest = max(row.hausdorff.max for row in below)
    return f"right in every draw at every swept ε ≤ ε* (Hausdorff ≤ {largest:.3g})"


def marks_line(m, verdicts: list[str]) -> str:
    return (
        f"| {m.label} | {m.target} | {m.claim} | {format_down(m.eps_star)} | "
        + " | ".join(verdicts)
        + " |\n"
    )


def cell(shape, eps: float, quality, cache: Path | None) -> DrawsRow:
    """The draws of one surface at one ε, from the cache when it has them."""
    path = None if cache is None else cache / f"{shape.name}-{eps!r}-{REPEATS}.json"
    if path is not None and path.exists():
        data = json.loads(path.read_text())
        return DrawsRow(
            data["eps"], tuple(SweepRow(**d) for d in data["draws"]), tuple(data["seeds"])
        )
    row = reconstruct_draws(
        shape, [eps], quality, 0, REPEATS, MhatOptions(compare_sheets=True)
    ).rows[0]
    if path is not None:
        data = {"eps": row.eps, "draws": [vars(d) for d in row.draws], "seeds": row.seeds}
        path.write_text(json.dumps(data))
    return row


def surface_draws(shape, values, quality, marks, cache=None) -> ReconstructDraws:
    rows = [cell(shape, eps, quality, cache) for eps, _ in values]
    return ReconstructDraws(
        shape.name, quality, 0, REPEATS, shape.expected_topology, rows, list(marks)
    )


def render(cache: Path | None = None) -> str:
    quality = QualityParams()
    marks = bound_marks(quality)
    values = eps_values()
    first, sweeps = [], []
    for shape in SURFACES:
        draws = surface_draws(shape, values, quality, marks, cache)
        sweeps.append(draws)
        for (_, label), row in zip(values, draws.rows, strict=True):
            first.append(row_text(shape, label, row))
    second = [marks_line(m, [verdict_at(m.eps_star, d.rows) for d in sweeps]) for m in marks]
    band = [band_text(d) for d in sweeps]
    return (
        FIRST_HEADER
        + "".join(first)
        + "\n"
        + BAND_HEADER
        + "".join(band)
        + "\n"
        + SECOND_HEADER
        + "".join(second)
    )


def quick_check(block: str) -> None:
    """One cell (8 draws) and the ε* column, recomputed."""
    quality = QualityParams()
    index, eps = QUICK
    shape = SURFACES[index]
    row = cell(shape, eps, quality, None)
    assert len(row.draws) == REPEATS
    line = row_text(shape, f"{eps:g}", row)
    assert line in block, line
    for m in bound_marks(quality):
        assert f"| {m.label} | {m.target} | {m.claim} | {format_down(m.eps_star)} | " in block, m


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cache", type=Path, help="folder keeping each (surface, ε) cell")
    parser.add_argument("--surface", type=int, help="compute this surface's cells only")
    args = parser.parse_args()
    if args.cache is not None:
        args.cache.mkdir(parents=True, exist_ok=True)
    if args.surface is not None:
        quality = QualityParams()
        marks = bound_marks(quality)
        surface_draws(SURFACES[args.surface], eps_values(), quality, marks, args.cache)
    else:
        print(render(args.cache))
