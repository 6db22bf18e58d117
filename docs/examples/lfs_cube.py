"""docs/lfs.md: the estimated L near the sharp edges of a cube mesh, in mesh edge lengths."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))
from benchmarks.bench_lfs import cube_rows  # noqa: E402


def render() -> str:
    lines = [
        "| divisions per face side | edge length h | L on the cube's edges / h "
        "| L one step in / h | midpoints added |",
        "|---|---|---|---|---|",
    ]
    for count, h, on_edge, one_in, added in cube_rows():
        lines.append(
            f"| {count} | {h:g} | {on_edge:.3f} | {one_in:.3f} | {added:,} |".replace(",", " ")
        )
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    print(render(), end="")
