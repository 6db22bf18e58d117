"""Cost of ``estimate_lfs`` on CAD and smooth meshes, beside a plain pole baseline (issue 35).

Run: ``python benchmarks/bench_lfs_gear.py [--gear 20000 100000] [--torus 512x128 2000x500]
[--timeout 600] [--max-gb 6] [--profile]``.

Each measurement is a process of its own, watched by this one: it is killed when its resident
memory passes ``--max-gb`` or its wall time ``--timeout`` (the row then says so). Per mesh, two
rows:

* ``lfs``: :func:`vorobound.sampling.lfs.estimate.estimate_lfs` with the defaults (what
  ``vorobound lfs`` runs);
* ``baseline``: the plain pole estimate of Amenta and Bern on the same vertices: scipy's
  (qhull) Delaunay triangulation of the jittered vertices, the two poles of each vertex (the
  farthest circumcentre of its tetrahedra, and the farthest on the other side), and the
  distance from each vertex to the nearest pole of another vertex through a k-d tree. No
  feature, thickness or emptiness test: the engine cost that ``lfs`` is measured against.

CPU seconds (all threads, ``time.process_time`` around the call), wall seconds and the peak
resident memory of the process; the meshes are built in the child before the clock starts.
Targets of issue 35: the 10⁵-face gear ≤ 120 CPU-s and ≤ 2 GB, the 10⁶-vertex torus ≤ 300
CPU-s, each within 3× its baseline. The machine is shared: the load average is printed.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
TARGET_CPU = {"gear": 120.0, "torus": 300.0}
TARGET_GB = {"gear": 2.0}
TARGET_RATIO = 3.0


def make_mesh(spec: str):
    """``gear:FACES`` or ``torus:AROUNDxTUBE`` (torus R = 3, r = 1, jittered by 0.2 steps)."""
    from vorobound.sampling.surfaces.cad_meshes import gear
    from vorobound.sampling.surfaces.demo_meshes import torus_mesh

    kind, size = spec.split(":")
    if kind == "gear":
        return gear(faces=int(size))
    around, tube = (int(v) for v in size.split("x"))
    return torus_mesh(3.0, 1.0, around, tube, jitter=0.2, seed=1)


def pole_baseline(points: np.ndarray) -> np.ndarray:
    """Distance from each vertex to the nearest pole of another vertex (module docstring)."""
    from scipy.spatial import Delaunay, cKDTree

    random = np.random.default_rng(0)
    scale = np.ptp(points, axis=0).max()
    moved = points + 1e-6 * scale * random.standard_normal(points.shape)
    tets = Delaunay(moved).simplices
    corners = points[tets]
    a = corners[:, 1:] - corners[:, :1]
    rhs = 0.5 * (a * a).sum(axis=2)
    # Flat tetrahedra (coplanar vertices of a CAD part's caps) have no circumcentre.
    centre = np.full((len(tets), 3), np.nan)
    solid = np.abs(np.linalg.det(a)) > 1e-12 * scale**3
    with np.errstate(all="ignore"):
        centre[solid] = corners[solid, 0] + np.linalg.solve(a[solid], rhs[solid][..., None])[..., 0]
    good = np.isfinite(centre).all(axis=1)
    owner = tets[good].reshape(-1)
    centres = np.repeat(centre[good], 4, axis=0)
    offset = centres - points[owner]
    distance = np.linalg.norm(offset, axis=1)
    order = np.lexsort((-distance, owner))
    first = order[np.r_[True, owner[order][1:] != owner[order][:-1]]]
    pole = np.full((len(points), 3), np.nan)
    pole[owner[first]] = centres[first]
    # The second pole: the farthest circumcentre on the other side of the first.
    side = (offset * (pole[owner] - points[owner])).sum(axis=1) < 0
    other = np.flatnonzero(side)
    order = other[np.lexsort((-distance[other], owner[other]))]
    first = order[np.r_[True, owner[order][1:] != owner[order][:-1]]] if len(order) else order
    second = np.full((len(points), 3), np.nan)
    second[owner[first]] = centres[first]
    poles = np.vstack([pole, second])
    poles = poles[np.isfinite(poles).all(axis=1)]
    return cKDTree(poles).query(points)[0]


def tangent_ball_queries(mesh, count: int = 50_000, cap: float = 0.02, seed: int = 0):
    """The inputs of the tangent-ball stage alone (where issue 35's profile put 88 % of the
    time): ``count`` points uniform by area on the prepared mesh, each with its face's inward
    normal and patch, the limit ``cap`` (in the prepared mesh's units, diagonal 1), and the
    faces of the other non-adjacent patches as :func:`estimate_lfs` passes them."""
    from vorobound.sampling.lfs.estimate import SHARP_ANGLE
    from vorobound.sampling.lfs.mesh_quality import prepare_mesh
    from vorobound.sampling.lfs.patches import find_patches
    from vorobound.sampling.lfs.tangent_ball import TangentBalls

    prepared = prepare_mesh(mesh)
    patches = find_patches(prepared, SHARP_ANGLE)
    corners = prepared.points[prepared.triangles]
    random = np.random.default_rng(seed)
    area = np.linalg.norm(
        np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1
    )
    face = random.choice(len(corners), count, p=area / area.sum())
    weights = random.dirichlet(np.ones(3), count)
    points = np.einsum("nc,ncd->nd", weights, corners[face])
    normal = np.cross(corners[face, 1] - corners[face, 0], corners[face, 2] - corners[face, 0])
    inward = -normal / np.linalg.norm(normal, axis=1)[:, None]
    other = ~patches.adjacent & ~np.eye(patches.count, dtype=bool)
    balls = TangentBalls(corners, patches.face_patch, other)
    return balls, (points, inward, patches.face_patch[face], np.full(count, cap))


def child(kind: str, spec: str, profile: bool) -> None:
    """Build the mesh, then time one estimate; print a JSON line."""
    from vorobound.errors import VoroboundWarning
    from vorobound.sampling.lfs.estimate import estimate_lfs

    mesh = make_mesh(spec)
    if kind == "balls":
        balls, queries = tangent_ball_queries(mesh)
    if profile:
        import cProfile
        import pstats

        profiler = cProfile.Profile(time.process_time)  # CPU seconds of all threads
        profiler.enable()
    stages: dict[str, float] = {}
    began = [0.0]

    def progress(task: str, done: int, total) -> None:
        """CPU seconds per stage, summed over the rounds; each finished step is written to
        stderr at once, so that a run stopped by the watcher still tells how far it got."""
        now = time.process_time()
        if done == 0:
            began[0] = now
            stages.setdefault(task, 0.0)
            return
        stages[task] = stages.get(task, 0.0) + now - began[0]
        began[0] = now
        peak_now = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20
        print(f"STAGE {task}\t{now - start[1]:.1f}\t{peak_now:.2f}", file=sys.stderr, flush=True)

    start = (time.perf_counter(), time.process_time())
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", VoroboundWarning)
        if kind == "lfs":
            values = estimate_lfs(mesh, progress=progress).lfs
        elif kind == "balls":
            values = balls(*queries)
        else:
            values = pole_baseline(mesh.points)
    wall, cpu = time.perf_counter() - start[0], time.process_time() - start[1]
    if profile:
        profiler.disable()
        pstats.Stats(profiler, stream=sys.stderr).sort_stats("cumulative").print_stats(40)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20
    report = {
        "vertices": len(mesh.points),
        "faces": len(mesh.triangles),
        "cpu": cpu,
        "wall": wall,
        "peak_gb": peak,
        "median_lfs": float(np.median(values)),
        "stages": {name: round(value, 1) for name, value in stages.items() if value >= 0.05},
    }
    print(json.dumps(report))


def run(kind: str, spec: str, timeout: float, max_gb: float, profile: bool) -> dict:
    """The child's report, or why it was stopped."""
    import psutil

    env = dict(
        os.environ,
        PYTHONPATH=os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")])),
    )
    command = [sys.executable, __file__, "--child", kind, spec] + (["--profile"] if profile else [])
    start = time.perf_counter()
    process = subprocess.Popen(
        command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env, text=True
    )
    watched, peak, stopped = psutil.Process(process.pid), 0.0, None
    while process.poll() is None:
        try:
            peak = max(peak, watched.memory_info().rss / 2**30)
        except psutil.NoSuchProcess:
            break
        if peak > max_gb:
            stopped = f"killed at {peak:.2f} GB"
        elif time.perf_counter() - start > timeout:
            stopped = f"killed after {timeout:.0f} s wall"
        if stopped:
            process.kill()
            break
        time.sleep(0.25)
    out, err = process.communicate()
    if profile:
        sys.stderr.write("".join(x for x in err[-12000:].splitlines(True) if "STAGE " not in x))
    if stopped or process.returncode:
        reached = [line.split("\t") for line in err.splitlines() if line.startswith("STAGE ")]
        if reached:  # how far it got: the last finished step, its CPU seconds and peak memory
            name, cpu, gb = reached[-1]
            stopped = f"{stopped or 'failed'} (last step: {name[6:]} at {cpu} CPU-s, {gb} GB)"
        return {"stopped": stopped or f"failed: {err.strip().splitlines()[-1:]}"}
    return json.loads(out.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--gear", type=int, nargs="*", default=[20_000, 100_000], help="faces")
    parser.add_argument("--torus", nargs="*", default=["512x128"], help="AROUNDxTUBE grids")
    parser.add_argument("--timeout", type=float, default=600.0, help="wall seconds per run")
    parser.add_argument("--max-gb", type=float, default=6.0, help="resident memory per run")
    parser.add_argument(
        "--profile", action="store_true", help="cProfile of each lfs run (CPU seconds)"
    )
    parser.add_argument(
        "--balls", action="store_true", help="time the tangent-ball stage alone instead"
    )
    parser.add_argument("--no-baseline", action="store_true", help="leave out the baseline")
    parser.add_argument(
        "--tiny",
        action="store_true",
        help="CI: a 48x16 torus only (even a small gear takes tens of CPU seconds); exit 1 if "
        "a run stops",
    )
    args = parser.parse_args()
    if args.tiny:
        args.gear, args.torus, args.timeout = [], ["48x16"], 300.0
    stopped = False
    print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores (shared machine)")
    print(
        f"{'mesh':20s} {'vertices':>9s} {'faces':>9s} | {'lfs CPU':>8s} {'wall':>7s} {'GB':>5s} |"
        f" {'base CPU':>8s} {'wall':>7s} {'GB':>5s} | {'ratio':>5s}  targets"
    )
    specs = [f"gear:{f}" for f in args.gear] + [f"torus:{t}" for t in args.torus]
    for spec in specs:
        found = run("balls" if args.balls else "lfs", spec, args.timeout, args.max_gb, args.profile)
        base = {} if args.no_baseline else run("base", spec, args.timeout, args.max_gb, False)
        kind = spec.split(":")[0]
        if "stopped" in found:
            print(f"{spec:20s} lfs {found['stopped']}", flush=True)
            stopped = True
            continue
        cells = f"{found['cpu']:7.1f}s {found['wall']:6.1f}s {found['peak_gb']:5.2f}"
        if base and "stopped" not in base:
            ratio = found["cpu"] / base["cpu"]
            cells += (
                f" | {base['cpu']:7.1f}s {base['wall']:6.1f}s {base['peak_gb']:5.2f} | {ratio:5.2f}"
            )
        else:
            ratio = None
            cells += f" | {base.get('stopped', 'not run'):>22s} |   —  "
        checks = []
        big = found["faces"] >= 90_000 if kind == "gear" else found["vertices"] >= 900_000
        if big:
            cpu_ok = found["cpu"] <= TARGET_CPU[kind]
            checks.append(f"CPU ≤ {TARGET_CPU[kind]:g}: {'met' if cpu_ok else 'missed'}")
            if kind in TARGET_GB:
                gb = found["peak_gb"] <= TARGET_GB[kind]
                checks.append(f"≤ {TARGET_GB[kind]:g} GB: {'met' if gb else 'missed'}")
        if ratio is not None:
            checks.append(
                f"≤ {TARGET_RATIO:g}× base: {'met' if ratio <= TARGET_RATIO else 'missed'}"
            )
        print(
            f"{spec:20s} {found['vertices']:9,d} {found['faces']:9,d} | {cells}  "
            + "; ".join(checks),
            flush=True,
        )
        if found.get("stages"):
            split = ", ".join(f"{name} {value:.1f}" for name, value in found["stages"].items())
            print(f"{'':20s} stages (CPU s): {split}", flush=True)
    print(f"load average {os.getloadavg()[0]:.2f}")
    if args.tiny and stopped:
        sys.exit(1)


if __name__ == "__main__":
    if sys.argv[1:2] == ["--child"]:
        child(sys.argv[2], sys.argv[3], "--profile" in sys.argv[4:])
    else:
        main()
