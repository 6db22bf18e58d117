"""docs/lfs.md: time of the L estimate against the sample size and the vertex count (about
4 minutes; the times depend on the machine and its load).

Times cannot be checked; the test recomputes the sample sizes and errors of the growth table's
first mesh at N = 2 × (vertices) and the sample size of the speed table's first mesh
(``quick_check``).
"""

import os
import re
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))
from benchmarks.bench_lfs import (  # noqa: E402
    growth,
    growth_cases,
    speed_meshes,
    speed_row,
    timed,
)

GROWTH_HEADER = (
    "| mesh | vertices | sample N | median error | largest error | time |\n"
    "|---|---|---|---|---|---|\n"
)
SPEED_HEADER = (
    "| mesh | vertices | vertices only | Delaunay alone | ratio | default sample | default |\n"
    "|---|---|---|---|---|---|---|\n"
)


def count(value: int) -> str:
    return f"{value:,}".replace(",", " ")


def growth_row(case, multiple: int) -> tuple[str, str]:
    found = growth(case, multiple)
    values = (
        f"| {case.label} | {count(len(case.mesh.points))} | {count(found.samples)} "
        f"| {found.median:.1e} | {found.largest:.1e} |"
    )
    return values, f" {found.seconds:.2f} s |\n"


def speed_line(mesh) -> str:
    vertices, alone, base, samples, seconds = speed_row(mesh)
    return (
        f"| {mesh.name} | {count(vertices)} | {alone:.2f} s | {base:.2f} s | {alone / base:.2f} "
        f"| {count(samples)} | {seconds:.2f} s |\n"
    )


def render() -> str:
    rows = [
        "".join(growth_row(case, multiple))
        for case, multiples in growth_cases(quick=True)
        for multiple in multiples
    ]
    speed = "".join(speed_line(mesh) for mesh in speed_meshes(quick=True))
    load = f"\nLoad average during the run: {os.getloadavg()[0]:.1f} (2 cores, shared).\n"
    return GROWTH_HEADER + "".join(rows) + "\n" + SPEED_HEADER + speed + load


def quick_check(block: str) -> None:
    assert block.startswith(GROWTH_HEADER) and SPEED_HEADER in block
    stale = "docs/lfs.md is stale: run python scripts/update_docs.py"
    case, _ = growth_cases()[0]
    assert growth_row(case, 2)[0] in block, stale
    mesh = speed_meshes(quick=True)[0]
    estimate, _ = timed(mesh)
    pattern = (
        rf"\| {re.escape(mesh.name)} \| {count(len(mesh.points))} \| [^\n]* "
        rf"\| {count(estimate.sample_count)} \| [0-9.]+ s \|\n"
    )
    assert re.search(pattern, block), stale


if __name__ == "__main__":
    print(render(), end="")
