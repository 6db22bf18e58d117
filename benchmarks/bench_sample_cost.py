"""Measure what ``vorobound sample --mesh`` costs per lattice candidate (issue 32).

Runs the sampler on the CAD cube (cad_meshes.cube(), side 2) at three ε in fresh processes,
reads peak RSS and CPU seconds (``resource.getrusage`` of the child), and fits
base + slope × the plain-lattice count (:func:`.mesh_lattice.expected_candidates`, the count
`advise` shows; the slab sampler makes about a quarter of it). The constants of
vorobound/sampling/sampler/cost.py come from this.

    python benchmarks/bench_sample_cost.py
"""

from __future__ import annotations

import resource
import subprocess
import sys
import tempfile
from pathlib import Path

import meshio
import numpy as np

from vorobound.sampling.surfaces import cad_meshes

EPS = (0.05, 0.025, 0.0125)


def run(mesh: Path, eps: float, out: Path) -> tuple[float, float, float]:
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(
        [sys.executable, "-m", "vorobound", "sample", "--mesh", str(mesh), "--eps", repr(eps)]
        + ["-o", str(out), "--json"],
        capture_output=True,
        text=True,
        check=True,
    )
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return plain_count(mesh, eps), cpu, after.ru_maxrss * 1024.0


def plain_count(mesh: Path, eps: float) -> float:
    """The plain-lattice count at ``eps`` (what `advise` shows as lattice candidates)."""
    from vorobound.api.surfaces import Surface
    from vorobound.sampling.sampler.mesh_lattice import expected_candidates

    shape = Surface(None, None, mesh, None, None).shape()
    return expected_candidates(shape.counts().inv_lfs_sq_integral, eps, 0.75, shape.lipschitz)


TINY_EPS = (0.3, 0.25, 0.2)
"""``--tiny`` (CI): three coarse ε, so the script runs in seconds (the fit means nothing)."""


def main() -> None:
    levels = TINY_EPS if "--tiny" in sys.argv[1:] else EPS
    with tempfile.TemporaryDirectory() as tmp:
        mesh = Path(tmp) / "cube.stl"
        part = cad_meshes.cube()
        meshio.write_points_cells(mesh, part.points, [("triangle", part.triangles)])
        rows = [run(mesh, eps, Path(tmp) / "s.npz") for eps in levels]
    print("| ε | plain-lattice candidates | CPU s | peak RSS MB |")
    print("|---|---|---|---|")
    for eps, (count, cpu, rss) in zip(levels, rows, strict=True):
        print(f"| {eps} | {count:,.0f} | {cpu:.2f} | {rss / 1e6:.0f} |")
    count, cpu, rss = (np.array(c, dtype=float) for c in zip(*rows, strict=True))
    cpu_slope, cpu_base = np.polyfit(count, cpu, 1)
    rss_slope, rss_base = np.polyfit(count, rss, 1)
    print(f"CPU: {cpu_base:.2f} s + {cpu_slope * 1e6:.2f} µs per candidate")
    print(f"memory: {rss_base / 1e6:.0f} MB + {rss_slope:.0f} bytes per candidate")


if __name__ == "__main__":
    main()
