"""The tiled ``check`` at scale (issue 23): run by ``python benchmarks/bench_check.py --scale``.

Inputs are row samples of the torus (3, 1) (σ-sparse ε-samples made chunk by chunk,
:mod:`vorobound.sampling.sampler.torus_rows`) written once to Parquet. Each measurement runs
``vorobound check --balls F --eps E ... --json`` in a fresh process; CPU seconds are those of
that process and every process it waited for (its pool workers), from ``RUSAGE_CHILDREN``.
"""

from __future__ import annotations

import json
import math
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))

MAJOR, MINOR = 3.0, 1.0
AREA = 4 * math.pi**2 * MAJOR * MINOR
"""Area of the torus (3, 1); a row sample has about AREA/ε² points."""
EXTRAPOLATE_BALLS = 10**8
EXTRAPOLATE_WORKERS = 64


def eps_for(count: int) -> float:
    """ε of the row sample with about ``count`` balls (rounded to 4 significant digits)."""
    return float(f"{math.sqrt(AREA / count):.4g}")


def sample_file(data: str | Path, count: int) -> tuple[Path, float]:
    """The Parquet row sample with about ``count`` balls (made once) and its ε."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    from vorobound.sampling.sampler.torus_rows import torus_rows

    eps = eps_for(count)
    path = Path(data) / f"torus-rows-{eps}.parquet"
    if path.exists():
        return path, eps
    path.parent.mkdir(parents=True, exist_ok=True)
    temp = path.with_suffix(".partial")
    schema = pa.schema([(name, pa.float64()) for name in ("x", "y", "z", "r")])
    start = time.perf_counter()
    with pq.ParquetWriter(temp, schema) as writer:
        for centers, radii in torus_rows(MAJOR, MINOR, eps, 2.0, seed=0):
            columns = {"x": centers[:, 0], "y": centers[:, 1], "z": centers[:, 2], "r": radii}
            writer.write_table(pa.table(columns, schema=schema))
    os.replace(temp, path)
    rows = pq.ParquetFile(path).metadata.num_rows
    print(f"made {path} ({rows:,} balls, {time.perf_counter() - start:.1f} s)")
    return path, eps


def run(path: Path, eps: float, *options: str) -> dict:
    """``vorobound check`` in a fresh process: its summary, wall and CPU seconds (with the
    worker processes), the peak memory of the largest process and the load average."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    load = os.getloadavg()[0]
    start = time.perf_counter()
    done = subprocess.run(
        [sys.executable, "-m", "vorobound", "check", "--balls", str(path), "--eps", str(eps)]
        + list(options)
        + ["--json"],
        capture_output=True,
        text=True,
        check=False,
    )
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode:
        raise SystemExit(f"check failed: {done.stderr}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return {
        "summary": json.loads(done.stdout),
        "wall": wall,
        "cpu": cpu,
        "max_rss_gb": after.ru_maxrss / 1e6,
        "load": (load, os.getloadavg()[0]),
        "options": " ".join(options),
    }


def _row(name: str, count: int, r: dict) -> str:
    s = r["summary"]
    t = s["tiles"]
    return (
        f"| {name} | {count:,} | {r['options']} | {s['n_guide_triangles']:,} | {t['count']} "
        f"| {100 * t['halo_share']:.0f} % | {r['wall']:.1f} | {r['cpu']:.1f} "
        f"| {t['driver_peak_gb']:.2f} | {t['worker_peak_gb']:.2f} | "
        f"{t['processes_peak_gb_total']:.2f} "
        f"| {r['load'][0]:.1f} → {r['load'][1]:.1f} |"
    )


def scale(data: str | Path, sizes: list[int]) -> None:
    """The measured table of docs/performance.md (module docstring)."""
    data = Path(data)
    print(f"{os.cpu_count()} cores; load average {os.getloadavg()[0]:.2f}")
    header = (
        "| case | balls | options | guide triangles | tiles | halo | wall s | CPU s "
        "| driver GB | worker GB | total GB | load |\n" + "|---" * 12 + "|"
    )
    rows, by_size = [], {}
    for count in sizes:
        path, eps = sample_file(data, count)
        one = run(path, eps, "--workers", "1")
        by_size[count] = one
        rows.append(_row("1 worker", count, one))
        print(rows[-1], flush=True)
        if count == 10**6:
            with tempfile.TemporaryDirectory() as out:
                written = run(path, eps, "--workers", "1", "--out", out)
            rows.append(_row("1 worker, outputs", count, written))
            print(rows[-1], flush=True)
            extra, slower = written["cpu"] / one["cpu"] - 1, written["wall"] / one["wall"] - 1
            print(f"outputs: {extra:+.1%} CPU, {slower:+.1%} wall")
        if count >= 10**6:
            two = run(path, eps, "--workers", "2")
            rows.append(_row("2 workers", count, two))
            print(rows[-1], flush=True)
            print(f"2 workers: {one['wall'] / two['wall']:.2f}x faster (wall)")
            print(f"2 workers on an idle machine (model): {idle_speedup(one, two):.2f}x faster")
            for key in ("n_guide_triangles", "n_half_covered", "gap_ratio_max"):
                assert two["summary"][key] == one["summary"][key], key
        if count == 10**6:
            remote = dask_run(path, eps)
            if remote is not None:
                rows.append(_row("dask LocalCluster (2 processes)", count, remote))
                print(rows[-1], flush=True)
                for key in ("n_guide_triangles", "n_half_covered", "gap_ratio_max"):
                    assert remote["summary"][key] == one["summary"][key], key
    print("\n" + header + "\n" + "\n".join(rows))
    saved = data / f"results-{time.strftime('%Y%m%d-%H%M%S')}.json"
    saved.write_text(json.dumps({str(k): v for k, v in by_size.items()}, indent=1))
    print(f"summaries of the 1-worker runs: {saved}")
    small, large = min(by_size), max(by_size)
    if large > small:
        exponent = math.log(by_size[large]["cpu"] / by_size[small]["cpu"]) / math.log(large / small)
        print(f"\nCPU growth exponent {small:.0e} → {large:.0e}: {exponent:.3f}")
    extrapolate(by_size[large], large)


def speedup(data: str | Path, repeats: int, count: int = 10**6) -> None:
    """1 and 2 workers alternately on the 10⁶-ball sample, ``repeats`` times."""
    path, eps = sample_file(data, count)
    for repeat in range(repeats):
        one = run(path, eps, "--workers", "1")
        two = run(path, eps, "--workers", "2")
        print(
            f"run {repeat + 1}: 1 worker {one['wall']:.1f} s wall, {one['cpu']:.1f} CPU-s "
            f"(load {one['load'][0]:.2f} → {one['load'][1]:.2f}); 2 workers {two['wall']:.1f} s "
            f"wall, {two['cpu']:.1f} CPU-s (load {two['load'][0]:.2f} → {two['load'][1]:.2f}): "
            f"{one['wall'] / two['wall']:.2f}x faster; idle-machine model "
            f"{idle_speedup(one, two):.2f}x",
            flush=True,
        )


def idle_speedup(one: dict, two: dict) -> float:
    """What 2 workers would gain on an idle 2-core machine, from CPU times (which the shared
    machine's load does not inflate much): the 1-worker run takes its CPU time; the 2-worker run
    takes the 1-worker run's serial part (everything but tile work: start, read, plan, route,
    merge, outputs), a worker's start-up (measured), and the busiest worker's tile work."""
    serial = one["cpu"] - sum(one["summary"]["tiles"]["cpu_seconds"].values())
    busiest = two["summary"]["tiles"]["busiest_worker_cpu_seconds"]
    return one["cpu"] / (serial + worker_start() + busiest)


def worker_start() -> float:
    """CPU seconds a fresh process takes to import what a tile needs."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(
        [sys.executable, "-c", "import vorobound.tiling.job, gudhi, scipy.spatial"],
        check=True,
    )
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def dask_run(path: Path, eps: float) -> dict | None:
    """The same check on a dask LocalCluster of 2 worker processes (None without dask)."""
    try:
        from distributed import LocalCluster
    except ImportError:
        print("dask.distributed is not installed: no cluster run")
        return None
    with LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster:
        # The cluster's workers are this process's children: RUSAGE_CHILDREN sees them only
        # once they exit, so their CPU is the summary's per-stage sum, added below.
        result = run(path, eps, "--scheduler", cluster.scheduler_address)
    tiles_cpu = sum(result["summary"]["tiles"]["cpu_seconds"].values())
    result["cpu"] += tiles_cpu
    return result


def extrapolate(measured: dict, count: int) -> None:
    """10⁸ balls on 64 workers from the measured run: the tiles' CPU per ball spread over the
    workers, plus the CPU of the driver's passes (read, plan, route: one process) per ball."""
    s = measured["summary"]
    per_ball_tiles = sum(s["tiles"]["cpu_seconds"].values()) / count
    driver = sum(s["tiles"]["driver_cpu_seconds"].values()) / count
    n, k = EXTRAPOLATE_BALLS, EXTRAPOLATE_WORKERS
    tiles = per_ball_tiles * n / k
    print(
        f"\nExtrapolation to {n:.0e} balls on {k} workers (from {count:.0e}): tiles "
        f"{per_ball_tiles * 1e6:.1f} CPU-µs per ball → {tiles:.0f} s on {k} workers; driver "
        f"passes {driver * 1e6:.2f} µs per ball → {driver * n:.0f} s in one process; "
        f"total ≈ {tiles + driver * n:.0f} s wall, {per_ball_tiles * n / 3600:.1f} CPU-hours"
    )


TILE_BALLS = 150_000
"""Balls of the tile that --tile-engines times (cut from the 10⁶-ball sample)."""
TINY_BALLS = 20_000
"""Balls of the sample of a --tiny run (the fewest a row sample makes): that every path runs,
not timings."""
TINY_TILE_BALLS = 3_000


def tile_engines(data: str | Path, count: int = 10**6, tile_balls: int = TILE_BALLS) -> None:
    """GUDHI's regular triangulation (DelaunayComplex, the engine) against the weighted alpha
    complex pruned at alpha² ≤ 10⁻⁶·r_max² on one tile: time and the guide triangles found."""
    import numpy as np

    from vorobound.geometry.threads import limited_threads
    from vorobound.sampling.balls import Balls
    from vorobound.sampling.guides.seeds import classify
    from vorobound.sampling.guides.triangles import regular_triangles
    from vorobound.sampling.io.balls import read_ball_arrays

    path, eps = sample_file(data, count)
    centers, radii, _ = read_ball_arrays(path)
    tile = np.sort(np.argsort(centers[:, 0])[:tile_balls])
    balls = Balls(centers[tile], radii[tile])
    print(f"one tile of {len(balls):,} balls of {path.name}, one thread")
    found = {}
    with limited_threads(1):
        for name, engine in (("DelaunayComplex", regular_triangles), ("alpha complex", _alpha)):
            best = math.inf
            for _ in range(3):
                start = time.process_time()
                triples = np.sort(engine(balls.centers, balls.weights), axis=1)
                best = min(best, time.process_time() - start)
            seeded = classify(balls, triples)
            guide = seeded.triples[seeded.guide]
            found[name] = {tuple(t) for t in guide.tolist()}
            print(
                f"  {name:16s} {best:6.2f} CPU-s (best of 3), {len(triples):,} candidates, "
                f"{len(guide):,} guide triangles"
            )
    same = found["DelaunayComplex"] == found["alpha complex"]
    print(f"  same guide triangles: {same}")


def _alpha(centers, weights):
    """The previous engine: GUDHI's weighted alpha complex pruned at alpha² ≤ 10⁻⁶·r_max²."""
    import gudhi
    import numpy as np

    from vorobound.sampling.guides.triangles import filler_points

    filler = filler_points(centers, math.sqrt(float(weights.max())))
    complex_ = gudhi.AlphaComplex(
        points=np.vstack([centers, filler]),
        weights=np.concatenate([weights, np.zeros(len(filler))]),
        precision="fast",
    )
    tree = complex_.create_simplex_tree(max_alpha_square=1e-6 * float(weights.max()))
    tree.prune_above_dimension(2)
    flat: list[int] = []
    for simplex, _ in tree.get_skeleton(2):
        if len(simplex) == 3:
            flat.extend(simplex)
    triangles = np.array(flat, dtype=np.int64).reshape(-1, 3)
    return triangles[(triangles < len(centers)).all(axis=1)]
