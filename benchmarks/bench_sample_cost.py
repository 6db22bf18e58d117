"""Measure what ``vorobound sample --mesh`` costs per lattice candidate (issue 32).

Runs the sampler on the CAD cube (cad_meshes.cube(), side 2) at three ε in fresh processes,
reads peak RSS and CPU seconds (``resource.getrusage`` of the child), and fits
base + slope × candidates. The constants of vorobound/sampling/sampler/cost.py come from this.

    python benchmarks/bench_sample_cost.py
"""

from __future__ import annotations

import json
import resource
import subprocess
import sys
import tempfile
from pathlib import Path

import meshio
import numpy as np

from vorobound.sampling.surfaces import cad_meshes

EPS = (0.05, 0.025, 0.0125)


def run(mesh: Path, eps: float, out: Path) -> tuple[int, float, float]:
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    done = subprocess.run(
        [sys.executable, "-m", "vorobound", "sample", "--mesh", str(mesh), "--eps", repr(eps)]
        + ["-o", str(out), "--json"],
        capture_output=True,
        text=True,
        check=True,
    )
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return json.loads(done.stdout)["n_candidates"], cpu, after.ru_maxrss * 1024.0


def main() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        mesh = Path(tmp) / "cube.stl"
        part = cad_meshes.cube()
        meshio.write_points_cells(mesh, part.points, [("triangle", part.triangles)])
        rows = [run(mesh, eps, Path(tmp) / "s.npz") for eps in EPS]
    print("| ε | candidates | CPU s | peak RSS MB |")
    print("|---|---|---|---|")
    for eps, (count, cpu, rss) in zip(EPS, rows, strict=True):
        print(f"| {eps} | {count:,} | {cpu:.2f} | {rss / 1e6:.0f} |")
    count, cpu, rss = (np.array(c, dtype=float) for c in zip(*rows, strict=True))
    cpu_slope, cpu_base = np.polyfit(count, cpu, 1)
    rss_slope, rss_base = np.polyfit(count, rss, 1)
    print(f"CPU: {cpu_base:.2f} s + {cpu_slope * 1e6:.2f} µs per candidate")
    print(f"memory: {rss_base / 1e6:.0f} MB + {rss_slope:.0f} bytes per candidate")


if __name__ == "__main__":
    main()
