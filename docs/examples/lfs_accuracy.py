"""docs/lfs.md: error of the estimated L at the vertices of generated meshes, from the vertices
only and with the default sample, meshes up to 12 288 vertices (``python
benchmarks/bench_lfs.py --quick`` prints the same; about 10 minutes; without ``--quick`` it
adds the 49 152-vertex tori and a 40 962-vertex sphere).

The test recomputes the rows of the 3 072-vertex torus (3, 1), without their times
(``quick_check``).
"""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))
from benchmarks.bench_lfs import accuracy, accuracy_cases, torus_case  # noqa: E402

HEADER = (
    "| mesh | vertices | vertices only: median | largest | default: sample | median | largest "
    "| largest over | targets met | time (vertices only / default) |\n"
    "|---|---|---|---|---|---|---|---|---|---|\n"
)


def count(value: int) -> str:
    return f"{value:,}".replace(",", " ")


def row(case) -> tuple[str, str]:
    """The row without its time column, and the time column."""
    alone, default = accuracy(case)
    values = (
        f"| {case.label} | {count(len(case.mesh.points))} | {alone.median:.1e} "
        f"| {alone.largest:.1e} | {count(default.samples)} | {default.median:.1e} "
        f"| {default.largest:.1e} | {default.over:.1e} "
        f"| {'yes' if default.meets_targets else '**no**'} |"
    )
    return values, f" {alone.seconds:.2f} s / {default.seconds:.2f} s |\n"


def render() -> str:
    return HEADER + "".join("".join(row(case)) for case in accuracy_cases(quick=True))


def quick_check(block: str) -> None:
    assert block.startswith(HEADER)
    stale = "docs/lfs.md is stale: run python scripts/update_docs.py"
    for jitter in (0.0, 0.2):
        assert row(torus_case(3.0, 1.0, 96, 32, jitter))[0] in block, stale


if __name__ == "__main__":
    print(render(), end="")
