"""Wall time, CPU time and peak memory of ``vorobound check`` on real samples, per stage.

Run: ``python benchmarks/bench_check.py [--cases torus-0.03,torus-1e6,sphere-1e6]``. Each case
runs in its own process (so its peak resident memory is its own) and does what
``vorobound check --torus 3,1 --eps 0.03`` does: sample the surface, find the guide triangles,
measure them. Stage boundaries come from the library's progress callback. Printed per case:

* stage wall times (lattice, sampling, regular triangulation, seeds, bounds, measure,
  conditions), the total against its target, the process CPU time, the peak memory against
  8 GB, and the machine's load average before and after (the machine is shared);
* the geometry kernel: ``weighted_triangles`` on the candidate triples of the sample against
  the same number of random triangles in the same run (the kernel's own throughput), in
  triangles per second.

With ``--filler`` it times the GUDHI stage with and without its filler points. (The findings
tables of docs/samples.md come from ``docs/examples/samples_table.py``.)

With ``--scale [--sizes 1e5,1e6,1e7]`` it measures the tiled check (docs/scale.md) on row samples
of the torus (3, 1) (:mod:`vorobound.sampling.sampler.torus_rows`, written to Parquet once, in
``--data``): ``vorobound check --balls F --eps E --workers K --json`` in a fresh process, with
and without ``--out`` (Parquet rows, decimated VTU, figure), on 1 and 2 workers and on a dask
LocalCluster, printing wall and CPU seconds (the command and its worker processes), peak
memory of the driver and of each worker, the load average, and a Markdown table; then the
growth exponent of CPU time with N and the extrapolation to 10⁸ balls on 64 workers from the
measured per-ball costs. ``--tile-engines`` times, on one tile of 1.5·10⁵ balls, GUDHI's
regular triangulation (``DelaunayComplex``, the engine) against the weighted alpha complex
pruned at alpha² ≤ 10⁻⁶·r_max² (the previous engine), with the guide triangles of each.
``--speedup N`` runs 1 and 2 workers on the same 10⁶ balls, paired and alternated (which goes
first alternates too), N times: wall and CPU seconds of each, tiles, halo share and the load
average around each run (the second core is often taken by other jobs on the shared machine),
the speed-up as measured and the CPU the second worker costs; the summaries must be identical
but for the timings and the tiles (issue 35: < 5 % extra CPU for 2 workers).

Scale targets (issue 23): 10⁶ balls ≤ 60 CPU-s end to end, outputs ≤ 15 % extra; 2 workers
≥ 1.7× faster than 1 at 10⁶; 10⁷ balls complete with peak ≤ 6 GB; CPU growth exponent from
10⁵ to 10⁷ ≤ 1.1.

Targets (the issue): torus (3, 1) at ε = 0.03 in ≤ 30 s; about 10⁶ samples (torus (3, 1) at
ε = 0.0113, sphere R = 1 at ε = 0.004) in ≤ 5 min and ≤ 8 GB, on 2 cores. ``torus-limit`` is
the largest lattice the sampler accepts (close to ``MAX_CANDIDATES``), for the memory limit.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import resource
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))

CASES = {
    "torus-0.03": ("torus", (3.0, 1.0), 0.03, 30.0),
    "torus-1e6": ("torus", (3.0, 1.0), 0.0113, 300.0),
    "sphere-1e6": ("sphere", (1.0,), 0.004, 300.0),
    "torus-limit": ("torus", (3.0, 1.0), 0.0075, 300.0),
    "torus-tiny": ("torus", (3.0, 1.0), 0.3, 30.0),
}
"""name ↦ (surface, dimensions, ε, target seconds)."""
MEMORY_TARGET_GB = 8.0


def _cpu_seconds() -> float:
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def run_case(name: str) -> dict:
    """One case in this process; returns the measurements as a dict."""
    from vorobound.bounds.params import QualityParams
    from vorobound.reports.check import check_surface
    from vorobound.sampling.surfaces.analytic import SphereShape, TorusShape

    kind, dims, eps, _ = CASES[name]
    shape = TorusShape(*dims) if kind == "torus" else SphereShape(*dims)
    marks: dict[str, float] = {}

    def progress(task: str, done: int, total: int | None) -> None:
        marks.setdefault(task, time.perf_counter())

    load_before = os.getloadavg()
    cpu0, start = _cpu_seconds(), time.perf_counter()
    report = check_surface(shape, eps, QualityParams(), seed=0, progress=progress)
    total = time.perf_counter() - start
    cpu = _cpu_seconds() - cpu0
    order = sorted(marks.items(), key=lambda item: item[1])
    ends = [t for _, t in order[1:]] + [start + total]
    stages = {task: end - begin for (task, begin), end in zip(order, ends, strict=True)}
    kernel = kernel_throughput(report)
    return {
        "case": name,
        "eps": eps,
        "n_samples": len(report.balls),
        "n_guide_triangles": len(report.guides),
        "n_candidate_triples": report.proposed,
        "engine": report.engine,
        "stages": stages,
        "total": total,
        "cpu": cpu,
        "peak_gb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6,
        "load_before": load_before[0],
        "load_after": os.getloadavg()[0],
        "kernel": kernel,
    }


def filler_effect() -> dict:
    """GUDHI on the torus (3, 1) sample at ε = 0.03 with and without the filler points."""
    from unittest import mock

    import numpy as np

    from vorobound.sampling.balls import make_balls
    from vorobound.sampling.guides import triangles as guide
    from vorobound.sampling.guides.seeds import classify
    from vorobound.sampling.sampler.maximal import sample_surface
    from vorobound.sampling.surfaces.analytic import TorusShape

    sample = sample_surface(TorusShape(3.0, 1.0), 0.03, 0.75, seed=0)
    balls = make_balls(sample.points, 0.06 * sample.lfs)
    out = {"n_samples": len(balls)}
    found = {}
    without = mock.patch.object(guide, "filler_points", return_value=np.empty((0, 3)))
    for label, context in (("with", contextlib.nullcontext()), ("without", without)):
        with context:
            cpu0, start = _cpu_seconds(), time.perf_counter()
            found[label] = guide.slab_triples(balls)
            out[label] = {"wall": time.perf_counter() - start, "cpu": _cpu_seconds() - cpu0}
    out["same_candidates"] = bool(np.array_equal(found["with"], found["without"]))
    guides = {}
    for label, triples in found.items():
        seeded = classify(balls, triples)
        guides[label] = seeded.triples[seeded.guide]
        out[label]["candidates"] = len(triples)
    out["same_guides"] = bool(np.array_equal(guides["with"], guides["without"]))
    return out


def kernel_throughput(report) -> dict:
    """weighted_triangles on the guide triangles vs on as many random triangles (same run)."""
    import numpy as np

    from vorobound.geometry import weighted_triangles

    triples = report.guides.triples
    points = report.balls.centers[triples]
    weights = report.balls.weights[triples]
    start = time.perf_counter()
    weighted_triangles(points, weights)
    real = time.perf_counter() - start
    rng = np.random.default_rng(0)
    random_points = rng.random(points.shape)
    random_weights = 0.01 * rng.random(weights.shape)
    start = time.perf_counter()
    weighted_triangles(random_points, random_weights)
    baseline = time.perf_counter() - start
    return {
        "rows": len(triples),
        "real_per_s": len(triples) / real,
        "random_per_s": len(triples) / baseline,
    }


SPEEDUP_VARIES = {"timings", "tiles"}
"""Summary fields that may differ between 1 and 2 workers (every other one must not, but for
the worker count among the parameters)."""


def speedup(data: str, repeats: int, count: int = 10**6) -> None:
    """1 and 2 workers on the same 10⁶-ball file, paired and alternated (which goes first
    alternates too), ``repeats`` times: wall and CPU seconds of each (worker processes
    included), tiles and halo, load before → after, the speed-up as measured (wall) and the
    CPU ratio; the JSON summaries must be identical but for the timings and the tiles."""
    import bench_scale

    path, eps = bench_scale.sample_file(data, count)
    speed, cost = [], []
    for repeat in range(repeats):
        order = (1, 2) if repeat % 2 == 0 else (2, 1)
        got = {k: bench_scale.run(path, eps, "--workers", str(k)) for k in order}
        one, two = got[1], got[2]
        a, b = one["summary"], two["summary"]
        same = all(a[k] == b[k] for k in set(a) - SPEEDUP_VARIES - {"params"}) and set(a) == set(b)
        same &= {**a["params"], "workers": 2} == b["params"]
        if not same:
            differ = sorted(k for k in set(a) | set(b) if a.get(k) != b.get(k))
            raise SystemExit(f"1 and 2 workers gave different summaries: {', '.join(differ)}")
        speed.append(one["wall"] / two["wall"])
        cost.append(two["cpu"] / one["cpu"])
        for k in order:
            run, tiles = got[k], got[k]["summary"]["tiles"]
            print(
                f"run {repeat + 1}, {k} worker{'s' if k > 1 else ''}: {run['wall']:.1f} s wall, "
                f"{run['cpu']:.1f} CPU-s, {tiles['count']} tiles, halo "
                f"{100 * tiles['halo_share']:.1f} %, load {run['load'][0]:.2f} → "
                f"{run['load'][1]:.2f}",
                flush=True,
            )
        print(
            f"run {repeat + 1}: 2 workers {speed[-1]:.2f}x as fast (wall), CPU "
            f"{100 * (cost[-1] - 1):+.1f} %; the same summary: {same}",
            flush=True,
        )
    print(
        f"speed-up (wall) {min(speed):.2f}–{max(speed):.2f}x, median "
        f"{sorted(speed)[len(speed) // 2]:.2f}x; CPU of 2 workers against 1: "
        f"{100 * (min(cost) - 1):+.1f} % to {100 * (max(cost) - 1):+.1f} %"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--cases", default=",".join(CASES), help="comma list of " + ", ".join(CASES)
    )
    parser.add_argument("--child", help=argparse.SUPPRESS)
    parser.add_argument(
        "--filler", action="store_true", help="GUDHI with and without filler points (one case)"
    )
    parser.add_argument("--scale", action="store_true", help="the tiled check (issue 23)")
    parser.add_argument("--sizes", default="1e5,1e6,1e7", help="--scale: ball counts")
    parser.add_argument(
        "--data",
        default=os.path.join(tempfile.gettempdir(), "vorobound-bench"),
        help="--scale: folder for the input files (made once)",
    )
    parser.add_argument("--tile-engines", action="store_true", help="engines inside one tile")
    parser.add_argument(
        "--speedup", type=int, default=0, help="--scale: 1 and 2 workers at 10⁶, N times"
    )
    parser.add_argument(
        "--tiny",
        action="store_true",
        help="every path at a tiny size, in a temporary --data folder (CI: nothing rots)",
    )
    args = parser.parse_args()
    if args.tiny:
        _tiny()
        return
    if args.scale or args.tile_engines or args.speedup:
        import bench_scale

        if args.tile_engines:
            bench_scale.tile_engines(args.data)
        if args.speedup:
            speedup(args.data, args.speedup)
        if args.scale:
            bench_scale.scale(args.data, [int(float(n)) for n in args.sizes.split(",")])
        return
    if args.child:
        result = filler_effect() if args.child == "filler" else run_case(args.child)
        print(json.dumps(result))
        return
    if args.filler:
        done = subprocess.run(
            [sys.executable, __file__, "--child", "filler"],
            capture_output=True,
            text=True,
            check=True,
        )
        r = json.loads(done.stdout.strip().splitlines()[-1])
        w, wo = r["with"], r["without"]
        print(
            f"GUDHI on the torus (3, 1) at ε = 0.03 ({r['n_samples']:,} balls): "
            f"with filler points {w['wall']:.1f} s wall / {w['cpu']:.1f} s CPU, without "
            f"{wo['wall']:.1f} s / {wo['cpu']:.1f} s (CPU ratio {wo['cpu'] / w['cpu']:.2f}); "
            f"candidates {w['candidates']:,} and {wo['candidates']:,} (the same: "
            f"{r['same_candidates']}); the same guide triangles: {r['same_guides']}"
        )
        return
    for name in args.cases.split(","):
        if name not in CASES:
            parser.error(f"unknown case {name!r}")
    cases(args.cases.split(","))


def _tiny() -> None:
    """A tiny case, the tile engines and the tiled check at a few thousand balls (that the
    code runs; the numbers mean nothing)."""
    import bench_scale

    cases(["torus-tiny"])
    with tempfile.TemporaryDirectory() as data:
        bench_scale.tile_engines(data, bench_scale.TINY_BALLS, bench_scale.TINY_TILE_BALLS)
        bench_scale.scale(data, [bench_scale.TINY_BALLS])
        speedup(data, 1, bench_scale.TINY_BALLS)


def cases(names: list[str]) -> None:
    """Each case in its own process, its stages and totals printed."""
    print(f"{os.cpu_count()} cores; each case in its own process")
    for name in names:
        done = subprocess.run(
            [sys.executable, __file__, "--child", name], capture_output=True, text=True, check=False
        )
        if done.returncode:
            print(f"{name}: failed\n{done.stderr}")
            continue
        r = json.loads(done.stdout.strip().splitlines()[-1])
        target = CASES[name][3]
        verdict = "ok" if r["total"] <= target else "SLOW"
        memory = "ok" if r["peak_gb"] <= MEMORY_TARGET_GB else "OVER"
        print(
            f"\n{name}: {r['n_samples']:,} samples, {r['n_guide_triangles']:,} guide triangles "
            f"({r['n_candidate_triples']:,} candidates, engine {r['engine']}), ε = {r['eps']}"
        )
        for stage, seconds in r["stages"].items():
            print(f"  {stage:24s} {seconds:8.2f} s  {100 * seconds / r['total']:5.1f} %")
        print(
            f"  total {r['total']:.1f} s [{verdict} ≤ {target:.0f} s], CPU {r['cpu']:.1f} s, "
            f"peak {r['peak_gb']:.2f} GB [{memory} ≤ {MEMORY_TARGET_GB:.0f} GB], "
            f"load average {r['load_before']:.2f} → {r['load_after']:.2f}"
        )
        seeds = r["stages"].get("seeds")
        if seeds:
            rate = r["n_candidate_triples"] / seeds
            print(f"  seeds stage: {rate:,.0f} candidate triangles/s (kernel + coverage queries)")
        k = r["kernel"]
        print(
            f"  geometry kernel: {k['real_per_s']:,.0f} triangles/s on the guide triangles, "
            f"{k['random_per_s']:,.0f}/s on as many random ones "
            f"(ratio {k['real_per_s'] / k['random_per_s']:.2f})"
        )


if __name__ == "__main__":
    main()
