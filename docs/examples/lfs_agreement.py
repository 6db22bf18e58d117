"""docs/lfs.md: L of a coarse and a fine triangulation of each CAD test part, compared."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))
from benchmarks.bench_lfs import agreement  # noqa: E402
from vorobound.sampling.surfaces.cad_meshes import coarse_and_fine  # noqa: E402

HEADER = (
    "| part | vertices coarse / fine | median | 99th percentile | largest | share above 5 % "
    "| ∫dA/L² coarse / fine | ∫ds/L coarse / fine |\n|---|---|---|---|---|---|---|---|\n"
)
QUICK = ("bar", "cube")
"""Parts the test suite recomputes (under a second each)."""


def row(name, coarse, fine) -> str:
    a = agreement(name, coarse, fine)
    return (
        f"| {name} | {a.vertices[0]} / {a.vertices[1]} | {a.median:.2g} | {a.p99:.2g} | "
        f"{a.largest:.2g} | {100 * a.over_target:.1f} % | {a.integral_ratio:.4f} | "
        f"{a.feature_ratio:.4f} |\n"
    )


def render() -> str:
    return HEADER + "".join(row(name, *pair) for name, pair in coarse_and_fine().items())


def quick_check(block: str) -> None:
    assert block.startswith(HEADER)
    stale = "docs/lfs.md is stale: run python scripts/update_docs.py"
    for name, pair in coarse_and_fine().items():
        if name in QUICK:
            assert row(name, *pair) in block, stale


if __name__ == "__main__":
    print(render(), end="")
