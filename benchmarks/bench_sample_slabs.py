"""The slab sampler on the issue-32 parts at the advised ε (CPU seconds, peak RSS).

Writes the 2-ring CAD cylinder (r = 1, length 100) and the bar of
vorobound.sampling.surfaces.cad_meshes as STL, runs ``vorobound sample --mesh PART --eps E
-o FILE --json`` in a fresh process for each, and prints samples, candidates, coverage_max,
sparsity_min, CPU seconds (user + system of the child and its workers), the largest peak RSS
of one process and (with psutil) the peak of the summed RSS of the process and its workers,
polled every 0.2 s.

    python benchmarks/bench_sample_slabs.py [--eps 0.0094977] [--parts cylinder,bar] [--workers N]
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


def _tree_rss(pid: int) -> float:
    """Summed RSS (bytes) of a process and its descendants (0 without psutil)."""
    try:
        import psutil
    except ImportError:
        return 0.0
    try:
        root = psutil.Process(pid)
        return float(sum(p.memory_info().rss for p in [root, *root.children(recursive=True)]))
    except psutil.Error:
        return 0.0


def run(mesh: Path, eps: float, out: Path, workers: int = 1) -> dict:
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    command = [sys.executable, "-m", "vorobound", "sample", "--mesh", str(mesh), "--eps"]
    command += [repr(eps), "-o", str(out), "--json", "--workers", str(workers)]
    child = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    tree_peak = 0.0
    while child.poll() is None:
        tree_peak = max(tree_peak, _tree_rss(child.pid))
        time.sleep(0.2)
    stdout, stderr = child.communicate()
    done = subprocess.CompletedProcess(command, child.returncode, stdout, stderr)
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
        "peak_tree_rss_mb": tree_peak / 2**20,
        "file_mb": out.stat().st_size / 1e6,
    }


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--eps", type=float, default=0.0094977)
    parser.add_argument("--parts", default="cylinder,bar")
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--tiny", action="store_true", help="CI: the cylinder at ε = 0.2")
    args = parser.parse_args()
    if args.tiny:
        args.eps, args.parts = 0.2, "cylinder"
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.parts.split(","):
            part = PARTS[name]()
            mesh = Path(tmp) / f"{name}.stl"
            meshio.write_points_cells(mesh, part.points, [("triangle", part.triangles)])
            row = run(mesh, args.eps, Path(tmp) / f"{name}.npz", args.workers)
            print(json.dumps({"part": name, "eps": args.eps, "workers": args.workers, **row}))


if __name__ == "__main__":
    main()
