"""docs/lfs.md: the CAD meshes of the issue, true range of L against `vorobound lfs`."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))
from benchmarks.bench_lfs import issue_meshes, issue_row  # noqa: E402

HEADER = (
    "| mesh | true L | `vorobound lfs` at the vertices | largest at 20 000 surface points |\n"
    "|---|---|---|---|\n"
)
QUICK = 3
"""The first rows (the cylinders and the bar take under a second each) are checked by the
test suite; the plate and the 200-ring cylinder take longer."""


def row(label, mesh, truth) -> str:
    low, high, surface, _ = issue_row(mesh)
    return f"| {label} | {truth} | {low:.6g} – {high:.6g} | {surface:.6g} |\n"


ADVICE_HEADER = (
    "\n| cylinder (issue rows 1 and 5) | recommended ε | ball radius δL_min | samples (low – high) "
    "| of which on the rims | lattice candidates of `sample` |\n|---|---|---|---|---|---|\n"
)


def advice_rows() -> str:
    """`advise --mesh` for the 2-ring and 200-ring copies of the cylinder (defaults)."""
    import warnings

    from vorobound.bounds.params import QualityParams
    from vorobound.errors import VoroboundWarning
    from vorobound.reports.advisor import advise
    from vorobound.sampling.lfs.estimate import estimate_lfs

    meshes = issue_meshes()
    out = ""
    for label, mesh in (("2 rings", meshes[0][1]), ("200 rings", meshes[4][1])):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", VoroboundWarning)
            surface = estimate_lfs(mesh).surface()
        rec = advise(QualityParams(0.75, 2.0, 1.38), surface, ["rigorous", "tight"]).recommendation
        low, high = rec.feature_samples
        out += (
            f"| {label} | {rec.eps:.5g} | {rec.ball_radius:.5g} | {rec.samples_low:,.0f} – "
            f"{rec.samples_high:,.0f} | {low:,.0f} – {high:,.0f} | {rec.lattice_candidates:.3g} |\n"
        ).replace(",", " ")
    return out


def render() -> str:
    table = "".join(row(label, mesh, truth) for label, mesh, truth, _ in issue_meshes())
    return HEADER + table + ADVICE_HEADER + advice_rows()


def quick_check(block: str) -> None:
    assert block.startswith(HEADER)
    stale = "docs/lfs.md is stale: run python scripts/update_docs.py"
    for label, mesh, truth, _ in issue_meshes()[:QUICK]:
        assert row(label, mesh, truth) in block, stale


if __name__ == "__main__":
    print(render(), end="")
