"""Wall time, CPU time and peak memory of ``vorobound reconstruct``, per stage, and its growth.

Run: ``python benchmarks/bench_reconstruct.py [--cases torus-0.06,torus-0.03]``. Each case runs
in its own process (so its peak resident memory is its own) and does what
``vorobound reconstruct --torus 3,1 --eps 0.03`` does without writing files: sample the surface,
find the guide triangles and their seeds, label the seeds, build M̂ (CGAL's Delaunay
tetrahedralization, the in/out facets, welding), its topology and quality, and its distances
to the surface. Stage boundaries come from the library's progress callback. Printed per case:
the wall and CPU seconds of each stage, the total against the target, the peak memory against
the target, and the machine's load average before and after (the machine is shared: CPU
seconds are the steadier measure). With two cases, the growth exponent
log(t₂/t₁)/log(n₂/n₁) of the total (wall and CPU) in the number of seeds.

With ``--voronoi`` it times, on the seeds of the torus (3, 1) at ε = 0.03, qhull's Delaunay
tetrahedralization (what ``reconstruct`` uses) against ``scipy.spatial.Voronoi`` (the whole
diagram, the alternative docs/reconstruct.md discusses), each in its own process.

Target (the issue): torus (3, 1) at ε = 0.03 (about 1.4·10⁵ samples, 5·10⁵ seeds) in ≤ 2 min
on 2 cores and ≤ 4 GB.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import resource
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))

CASES = {
    "torus-0.06": ("torus", (3.0, 1.0), 0.06),
    "torus-0.03": ("torus", (3.0, 1.0), 0.03),
    "sphere-0.01": ("sphere", (1.0,), 0.01),
    "torus-0.3": ("torus", (3.0, 1.0), 0.3),
    "torus-0.2": ("torus", (3.0, 1.0), 0.2),
}
"""name ↦ (surface, dimensions, ε)."""
TINY_CASES = "torus-0.3,torus-0.2"
"""The cases of a --tiny run (that the code runs; the numbers mean nothing)."""
VORONOI_EPS = 0.03
"""ε of the torus (3, 1) whose seeds --voronoi triangulates (--tiny: the largest tiny case's)."""
TARGET_SECONDS = 120.0
MEMORY_TARGET_GB = 4.0


def _cpu_seconds() -> float:
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def run_case(name: str) -> dict:
    """One case in this process; returns the measurements as a dict."""
    from vorobound.bounds.params import QualityParams
    from vorobound.reports.reconstruct import reconstruct_surface
    from vorobound.sampling.surfaces.analytic import SphereShape, TorusShape

    kind, dims, eps = CASES[name]
    shape = TorusShape(*dims) if kind == "torus" else SphereShape(*dims)
    marks: dict[str, tuple[float, float]] = {}

    def progress(task: str, done: int, total: int | None) -> None:
        if task not in marks:
            marks[task] = (time.perf_counter(), _cpu_seconds())

    load_before = os.getloadavg()
    cpu0, start = _cpu_seconds(), time.perf_counter()
    report = reconstruct_surface(shape, eps, QualityParams(), seed=0, progress=progress)
    total, cpu = time.perf_counter() - start, _cpu_seconds() - cpu0
    order = sorted(marks.items(), key=lambda item: item[1][0])
    ends = [mark for _, mark in order[1:]] + [(start + total, cpu0 + cpu)]
    stages = {
        task: (end[0] - begin[0], end[1] - begin[1])
        for (task, begin), end in zip(order, ends, strict=True)
    }
    summary = report.summary()
    pairs = report.facets.surface.seed_pairs
    triangle = report.seeds.triangle
    return {
        "case": name,
        "eps": eps,
        "n_samples": summary["n_samples"],
        "n_seeds": summary["n_seeds"],
        "n_facets": summary["n_facets"],
        "tetrahedra": report.facets.tetrahedra,
        "delaunay_edges": report.facets.delaunay_edges,
        "collapsed": report.facets.collapsed,
        "guide_facets": int((triangle[pairs[:, 0]] == triangle[pairs[:, 1]]).sum()),
        "topology_correct": summary["topology_correct"],
        "stages": stages,
        "total": total,
        "cpu": cpu,
        "peak_gb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6,
        "load_before": load_before[0],
        "load_after": os.getloadavg()[0],
    }


def run_qhull(kind: str, eps: float = VORONOI_EPS) -> dict:
    """Delaunay or Voronoi of the seeds of the torus (3, 1) at ``eps``, timed alone."""
    from scipy.spatial import Delaunay, Voronoi

    from vorobound.sampling.balls import make_balls
    from vorobound.sampling.guides.triangles import find_guide_triangles
    from vorobound.sampling.sampler.maximal import sample_surface
    from vorobound.sampling.surfaces.analytic import TorusShape

    sample = sample_surface(TorusShape(3.0, 1.0), eps, 0.75, seed=0)
    balls = make_balls(sample.points, 2 * eps * sample.lfs)
    seeded = find_guide_triangles(balls).seeded
    seeds = seeded.seeds[seeded.guide].reshape(-1, 3)
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6
    cpu0, start = _cpu_seconds(), time.perf_counter()
    if kind == "delaunay":
        parts = len(Delaunay(seeds).simplices)
    else:
        parts = len(Voronoi(seeds).ridge_points)
    return {
        "kind": kind,
        "seeds": len(seeds),
        "parts": parts,
        "wall": time.perf_counter() - start,
        "cpu": _cpu_seconds() - cpu0,
        "peak_gb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6,
        "peak_before_gb": before,
        "load": os.getloadavg()[0],
    }


def compare_voronoi(eps: float = VORONOI_EPS) -> None:
    for kind in ("delaunay", "voronoi"):
        done = subprocess.run(
            [sys.executable, __file__, "--child", f"qhull-{kind}@{eps}"],
            capture_output=True,
            text=True,
            check=True,
        )
        r = json.loads(done.stdout.strip().splitlines()[-1])
        what = "tetrahedra" if kind == "delaunay" else "facets (ridges)"
        print(
            f"{kind:9s} of {r['seeds']:,} seeds: {r['parts']:,} {what}, {r['wall']:.1f} s wall, "
            f"{r['cpu']:.1f} s CPU, peak {r['peak_gb']:.2f} GB (before: "
            f"{r['peak_before_gb']:.2f} GB), load average {r['load']:.2f}"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--cases", default="torus-0.06,torus-0.03", help="comma list of " + ", ".join(CASES)
    )
    parser.add_argument("--child", help=argparse.SUPPRESS)
    parser.add_argument(
        "--voronoi", action="store_true", help="qhull's Delaunay against scipy's Voronoi"
    )
    parser.add_argument(
        "--tiny", action="store_true", help=f"--cases {TINY_CASES} and --voronoi on them (CI)"
    )
    args = parser.parse_args()
    if args.tiny:
        args.cases = TINY_CASES
        compare_voronoi(CASES[TINY_CASES.split(",")[-1]][2])
    if args.child:
        if args.child.startswith("qhull-"):
            kind, eps = args.child.removeprefix("qhull-").split("@")
            result = run_qhull(kind, float(eps))
        else:
            result = run_case(args.child)
        print(json.dumps(result))
        return
    if args.voronoi:
        compare_voronoi()
        return
    print(f"{os.cpu_count()} cores; each case in its own process")
    results = []
    for name in args.cases.split(","):
        if name not in CASES:
            parser.error(f"unknown case {name!r}")
        done = subprocess.run(
            [sys.executable, __file__, "--child", name], capture_output=True, text=True, check=False
        )
        if done.returncode:
            print(f"{name}: failed\n{done.stderr}")
            continue
        r = json.loads(done.stdout.strip().splitlines()[-1])
        results.append(r)
        verdict = "ok" if r["total"] <= TARGET_SECONDS else "SLOW"
        memory = "ok" if r["peak_gb"] <= MEMORY_TARGET_GB else "OVER"
        print(
            f"\n{name}: {r['n_samples']:,} samples, {r['n_seeds']:,} seeds, "
            f"{r['tetrahedra']:,} tetrahedra, {r['n_facets']:,} facets of M̂, ε = {r['eps']}, "
            f"topology {'right' if r['topology_correct'] else 'WRONG'}"
        )
        print(
            f"  {r['delaunay_edges']:,} in/out Delaunay edges, {r['collapsed']:,} of them "
            f"without area; {r['guide_facets']:,} facets are the two seeds of one guide "
            f"triangle ({100 * r['guide_facets'] / r['n_facets']:.1f} %)"
        )
        for stage, (wall, cpu) in r["stages"].items():
            share = 100 * wall / r["total"]
            print(f"  {stage:32s} {wall:8.2f} s wall {cpu:8.2f} s CPU  {share:5.1f} %")
        print(
            f"  total {r['total']:.1f} s wall [{verdict} ≤ {TARGET_SECONDS:.0f} s], CPU "
            f"{r['cpu']:.1f} s, peak {r['peak_gb']:.2f} GB [{memory} ≤ {MEMORY_TARGET_GB:.0f} "
            f"GB], load average {r['load_before']:.2f} → {r['load_after']:.2f}"
        )
    if len(results) >= 2:
        small, large = results[0], results[-1]
        size = math.log(large["n_seeds"] / small["n_seeds"])
        wall = math.log(large["total"] / small["total"]) / size
        cpu = math.log(large["cpu"] / small["cpu"]) / size
        print(
            f"\ngrowth from {small['case']} to {large['case']} "
            f"({small['n_seeds']:,} → {large['n_seeds']:,} seeds): time ∝ n^{wall:.2f} (wall), "
            f"n^{cpu:.2f} (CPU)"
        )


if __name__ == "__main__":
    main()
