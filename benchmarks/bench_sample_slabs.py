"""The slab sampler on the issue-32 parts at the advised ε (CPU seconds, peak RSS).

Writes the 2-ring CAD cylinder (r = 1, length 100) and the bar of
vorobound.sampling.surfaces.cad_meshes as STL, runs ``vorobound sample --mesh PART --eps E
-o FILE --json`` in a fresh process for each, and prints samples, candidates, coverage_max,
sparsity_min, CPU seconds (user + system of the child) and its peak RSS.

    python benchmarks/bench_sample_slabs.py [--eps 0.0094977] [--parts cylinder,bar]
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import meshio

from vorobound.sampling.surfaces import cad_meshes

PARTS = {"cylinder": cad_meshes.capped_cylinder, "bar": cad_meshes.bar}


def run(mesh: Path, eps: float, out: Path) -> dict:
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run(
        [sys.executable, "-m", "vorobound", "sample", "--mesh", str(mesh), "--eps", repr(eps)]
        + ["-o", str(out), "--json"],
        capture_output=True,
        text=True,
    )
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode not in (0, 1):
        return {"exit": done.returncode, "error": done.stderr.strip().splitlines()[-1]}
    data = json.loads(done.stdout)
    return {
        "exit": done.returncode,
        "samples": data["n_samples"],
        "candidates": data["n_candidates"],
        "coverage_max": data["coverage_max"],
        "coverage_probes": data["coverage_probes"],
        "sparsity_min": data["sparsity_min"],
        "sparsity_violations": data["sparsity_violations"],
        "cpu_s": (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime),
        "wall_s": wall,
        "peak_rss_mb": after.ru_maxrss / 1024.0,
        "file_mb": out.stat().st_size / 1e6,
    }


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--eps", type=float, default=0.0094977)
    parser.add_argument("--parts", default="cylinder,bar")
    parser.add_argument("--tiny", action="store_true", help="CI: the cylinder at ε = 0.2")
    args = parser.parse_args()
    if args.tiny:
        args.eps, args.parts = 0.2, "cylinder"
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.parts.split(","):
            part = PARTS[name]()
            mesh = Path(tmp) / f"{name}.stl"
            meshio.write_points_cells(mesh, part.points, [("triangle", part.triangles)])
            row = run(mesh, args.eps, Path(tmp) / f"{name}.npz")
            print(json.dumps({"part": name, "eps": args.eps, **row}), flush=True)


if __name__ == "__main__":
    main()
