"""docs/advisor.md's budget table: for each CAD-like part (the coarse exports of
vorobound.sampling.surfaces.cad_meshes), what the advised ε costs and guarantees, the smallest
ε `vorobound sample --mesh` builds, and the best proven guarantee within 10⁶ samples.

    python docs/examples/advisor_budget.py
"""

from __future__ import annotations

import math
import tempfile
import warnings
from pathlib import Path

BUDGET = 1_000_000
COMMAND = "vorobound advise --mesh PART.stl [--max-samples 1000000]"


def _row(name: str, mesh: Path) -> str:
    import vorobound
    from vorobound.rounding import format_down

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        advice = vorobound.advise(mesh=mesh, mode="tight")
        budget = vorobound.advise(mesh=mesh, mode="tight", max_samples=BUDGET)
    rec, cheap = advice.advice.recommendation, budget.advice.recommendation
    cost = rec.cost
    back = rec.fallback
    smallest = (
        "(advised ε itself)"
        if back is None
        else f"{format_down(back.eps)} ({_rho(back.guarantee)})"
    )
    within = f"{format_down(cheap.eps)} ({_rho(cheap.guarantee)})"
    return (
        f"| {name} | {format_down(rec.eps)} | {rec.samples_low:,.0f} – {rec.samples_high:,.0f} "
        f"| {cost.candidates:.3g} | {cost.memory_bytes / 1e9:.3g} GB "
        f"| {cost.cpu_seconds / 60:.3g} min | {'yes' if rec.samplable else 'no'} "
        f"| {smallest} | {within} |"
    )


def _rho(guarantee) -> str:
    """The proven ρ_f of (54), or where (54) has none, that of (55)."""
    from vorobound.rounding import format_up

    if math.isfinite(guarantee.rho_f_ratio):
        return f"(54) with ρ_f {format_up(guarantee.rho_f_ratio)}"
    return f"no ρ_f for (54); (55) with ρ_f {format_up(guarantee.rho_f_55)}"


def _parts(folder: Path) -> dict[str, Path]:
    import meshio

    from vorobound.sampling.surfaces import cad_meshes

    out = {}
    for name, (coarse, _fine) in cad_meshes.coarse_and_fine().items():
        path = folder / f"{name}.stl"
        meshio.write_points_cells(path, coarse.points, [("triangle", coarse.triangles)])
        out[name] = path
    return out


HEAD = [
    f"`{COMMAND}` on each part (coarse export; ρ_f = 1.38, σ = 3/4, δ = 2ε; "
    "`python docs/examples/advisor_budget.py` prints this table):",
    "",
    "| part | advised ε (ratio, proven) | samples (low–high) | lattice candidates "
    "| sampler memory (est.) | sampler CPU (est.) | samplable | smallest samplable ε "
    f"(what it guarantees) | best within {BUDGET:,} samples: ε (what it guarantees) |",
    "|---|---|---|---|---|---|---|---|---|",
]


def render() -> str:
    with tempfile.TemporaryDirectory() as tmp:
        rows = [_row(name, path) for name, path in _parts(Path(tmp)).items()]
    return "\n".join(HEAD + rows) + "\n"


def quick_check(block: str) -> None:
    """The test's check: the cube's row as computed now is in the block."""
    with tempfile.TemporaryDirectory() as tmp:
        cube = _parts(Path(tmp))["cube"]
        assert _row("cube", cube) in block.splitlines()


if __name__ == "__main__":
    print(render(), end="")
