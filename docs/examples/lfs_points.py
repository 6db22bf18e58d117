"""docs/lfs.md: one point added on every edge of a 3 072-vertex torus (1.5, 1), placed in
different ways, and the error of L at the vertices that results (about 15 s).

The test recomputes the table of the grid torus (``quick_check``).
"""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))
from benchmarks.bench_lfs import added_point_rows, torus_case  # noqa: E402

HEADER = (
    "| mesh | added points | distance to the surface / edge length (median) "
    "| error of L: median | largest |\n"
    "|---|---|---|---|---|\n"
)
CASES = ((0.0, "grid"), (0.2, "jitter 0.2"))


def rows(jitter: float, name: str) -> str:
    case = torus_case(1.5, 1.0, 96, 32, jitter)
    lines = []
    for placement, distance, errors in added_point_rows(case.mesh, case.shape):
        shown = "0" if distance < 1e-12 else f"{distance:.1e}"
        lines.append(
            f"| {name} | {placement} | {shown} | {errors.median:.1e} | {errors.largest:.1e} |\n"
        )
    return "".join(lines)


def render() -> str:
    return HEADER + "".join(rows(jitter, name) for jitter, name in CASES)


def quick_check(block: str) -> None:
    assert block.startswith(HEADER)
    assert rows(*CASES[0]) in block, "docs/lfs.md is stale: run python scripts/update_docs.py"


if __name__ == "__main__":
    print(render(), end="")
