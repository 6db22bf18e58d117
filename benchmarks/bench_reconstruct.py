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

With ``--slabs CASE`` it builds M̂ of the case's seeds with the whole set triangulated at once
and in 3 overlapping slabs (vorobound/sampling/reconstruct/slabs.py), each in its own process,
and says whether the polygons are equal.

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
    "cube-0.038": ("cube", (), 0.037991),
    "cube-0.019": ("cube", (), 0.018995),
    "cube-0.0095": ("cube", (), 0.0094977),
}
"""name ↦ (surface, dimensions, ε). The cube is the CAD cube [−1, 1]³ of issue 32
(``cad_meshes.cube()`` written as STL, L estimated from the mesh as ``vorobound reconstruct
--mesh cube.stl`` does), at the issue's ε = 0.0094977 (advised: 0.0094976) and at 2 and 4
times it."""
CUBE_CASES = "cube-0.038,cube-0.019,cube-0.0095"
"""The cases of ``--cube`` (issue 32: reconstruct ≤ 60 CPU-s and ≤ 2.5 GB at ε = 0.0094977)."""
CUBE_TARGET_CPU = 60.0
CUBE_TARGET_GB = 2.5
STAGE_OF = {
    "lattice": "sample (lattice, sampling)",
    "sampling": "sample (lattice, sampling)",
    "sampling (slabs)": "sample (lattice, sampling)",
    "regular triangulation": "guide triangles, seeds, labels",
    "seeds": "guide triangles, seeds, labels",
    "Delaunay": "M̂: Delaunay (geogram), neighbours",
    "in/out facets": "M̂: facets; topology, quality",
    "distances to the surface": "distances to the surface",
}
"""Progress tasks grouped into the stages printed (the tasks before the lattice estimate L of
a mesh)."""
TINY_CASES = "torus-0.3,torus-0.2"
"""The cases of a --tiny run (that the code runs; the numbers mean nothing)."""
VORONOI_EPS = 0.03
"""ε of the torus (3, 1) whose seeds --voronoi triangulates (--tiny: the largest tiny case's)."""
SLAB_COUNT = 3
"""Slabs of ``--slabs`` (what ``slabs.slab_count`` gives the cube's 1.08·10⁶ seeds at
ε = 0.0094977)."""
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
    marks: list[tuple[str, float, float, float]] = []

    def progress(task: str, done: int, total: int | None) -> None:
        stage = STAGE_OF.get(task, "L of the mesh" if kind == "cube" else task)
        if not marks or marks[-1][0] != stage:
            marks.append((stage, time.perf_counter(), _cpu_seconds(), _peak_gb()))

    load_before = os.getloadavg()
    cpu0, start = _cpu_seconds(), time.perf_counter()
    if kind == "cube":
        report = _reconstruct_cube(eps, progress)
    else:
        shape = TorusShape(*dims) if kind == "torus" else SphereShape(*dims)
        report = reconstruct_surface(shape, eps, QualityParams(), seed=0, progress=progress)
    total, cpu = time.perf_counter() - start, _cpu_seconds() - cpu0
    ends = [mark[1:] for mark in marks[1:]] + [(start + total, cpu0 + cpu, _peak_gb())]
    stages: dict[str, list[float]] = {}
    for (stage, wall0, cpu_at, _), (wall1, cpu1, peak) in zip(marks, ends, strict=True):
        seen = stages.setdefault(stage, [0.0, 0.0, 0.0])
        seen[0] += wall1 - wall0
        seen[1] += cpu1 - cpu_at
        seen[2] = max(seen[2], peak)
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
        "slabs": report.facets.slabs,
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


def _peak_gb() -> float:
    """Peak resident memory of this process so far, GB."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6


def _cube_file(folder: str) -> str:
    """The CAD cube [−1, 1]³ written as STL into ``folder``."""
    import meshio

    from vorobound.sampling.surfaces import cad_meshes

    path = os.path.join(folder, "cube.stl")
    part = cad_meshes.cube()
    meshio.write_points_cells(path, part.points, [("triangle", part.triangles)])
    return path


def _reconstruct_cube(eps: float, progress):
    """``vorobound reconstruct --mesh cube.stl --eps E`` without files; its report."""
    import tempfile
    import warnings

    from vorobound.api.reconstruct import reconstruct

    with tempfile.TemporaryDirectory() as folder, warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the cube's sharp edges are warned about
        return reconstruct(mesh=_cube_file(folder), eps=eps, progress=progress).report


def run_sample(name: str) -> dict:
    """``vorobound sample --mesh cube.stl --eps E -o s.npz`` in a child process."""
    import tempfile

    eps = CASES[name][2]
    with tempfile.TemporaryDirectory() as folder:
        mesh = _cube_file(folder)
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        start = time.perf_counter()
        done = subprocess.run(
            [sys.executable, "-m", "vorobound", "sample", "--mesh", mesh, "--eps", repr(eps)]
            + ["-o", os.path.join(folder, "s.npz"), "--json"],
            capture_output=True,
            text=True,
            check=True,
        )
        wall = time.perf_counter() - start
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    summary = json.loads(done.stdout)
    return {"case": name, "eps": eps, "n_samples": summary["n_samples"], "cpu": cpu,
            "wall": wall, "peak_gb": after.ru_maxrss / 1e6}  # fmt: skip


def _case_seeds(name: str):
    """The labelled seeds of a case (reconstructed in this process)."""
    from vorobound.bounds.params import QualityParams
    from vorobound.reports.reconstruct import reconstruct_surface
    from vorobound.sampling.surfaces.analytic import SphereShape, TorusShape

    kind, dims, eps = CASES[name]
    if kind == "cube":
        return _reconstruct_cube(eps, None).seeds
    shape = TorusShape(*dims) if kind == "torus" else SphereShape(*dims)
    return reconstruct_surface(shape, eps, QualityParams(), seed=0).seeds


def run_mhat(slabs: int, path: str) -> dict:
    """M̂ of the seeds saved at ``path`` in ``slabs`` slabs (1: the whole set), timed alone;
    the polygons saved next to them."""
    import numpy as np

    from vorobound.sampling.reconstruct.facets import inout_facets

    saved = np.load(path)
    cpu0 = _cpu_seconds()
    facets = inout_facets(saved["points"], saved["inside"], slabs=slabs)
    cpu = _cpu_seconds() - cpu0
    surface = facets.surface
    np.savez(f"{path}.{slabs}.npz", corners=surface.corners, offsets=surface.offsets,
             pairs=surface.seed_pairs, vertices=surface.vertices)  # fmt: skip
    return {"slabs": slabs, "cpu": cpu, "peak_gb": _peak_gb(), "facets": surface.n_facets,
            "collapsed": facets.collapsed, "edges": facets.delaunay_edges}  # fmt: skip


def compare_slabs(name: str, slabs: int) -> None:
    """M̂ of a case's seeds with the whole set triangulated at once and in ``slabs`` slabs,
    each in its own process: CPU seconds, peak memory, and whether the polygons are equal."""
    import tempfile

    import numpy as np

    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "seeds.npz")
        subprocess.run([sys.executable, __file__, "--child", f"seeds-{name}@{path}"], check=True)
        rows = []
        for count in (1, slabs):
            done = subprocess.run(
                [sys.executable, __file__, "--child", f"mhat-{count}@{path}"],
                capture_output=True,
                text=True,
                check=True,
            )
            rows.append(json.loads(done.stdout.strip().splitlines()[-1]))
        whole, split = (np.load(f"{path}.{r['slabs']}.npz") for r in rows)
        same = all(np.array_equal(whole[k], split[k]) for k in whole.files)
        seeds = len(np.load(path)["points"])
    print(f"M̂ of the {seeds:,} seeds of {name}:")
    for r in rows:
        print(
            f"  {r['slabs']} slab(s): {r['cpu']:.1f} s CPU, peak {r['peak_gb']:.2f} GB, "
            f"{r['facets']:,} facets, {r['edges']:,} in/out edges, {r['collapsed']:,} collapsed"
        )
    print(f"  polygons, vertices and seed pairs {'equal' if same else 'DIFFERENT'}")


def run_degeneracy(name: str = "cube-0.038") -> dict:
    """CGAL's build (GUDHI ``DelaunayComplex``) on the seeds of a cube case, on the same seeds
    moved by 10⁻⁹ at random, and on as many uniform random points, CPU seconds each."""
    import gudhi
    import numpy as np

    seeds = _reconstruct_cube(CASES[name][2], None).seeds.points
    rng = np.random.default_rng(0)
    sets = {
        "seeds": seeds,
        "seeds moved by 1e-9": seeds + 1e-9 * rng.standard_normal(seeds.shape),
        "random points": rng.uniform(-1, 1, seeds.shape),
    }
    out = {"case": name, "count": len(seeds)}
    for label, points in sets.items():
        cpu0 = _cpu_seconds()
        gudhi.DelaunayComplex(points=np.ascontiguousarray(points), precision="fast")
        out[label] = _cpu_seconds() - cpu0
    return out


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
    parser.add_argument(
        "--cube", action="store_true", help=f"--cases {CUBE_CASES} --sample (issue 32)"
    )
    parser.add_argument(
        "--sample",
        action="store_true",
        help="also time `vorobound sample --mesh cube.stl` at each (cube) case",
    )
    parser.add_argument(
        "--degeneracy",
        action="store_true",
        help="CGAL on the cube's seeds against the same seeds moved by 1e-9 and random points",
    )
    parser.add_argument(
        "--slabs",
        metavar="CASE",
        help="M̂ of CASE's seeds, the whole set at once against 3 slabs (polygons compared)",
    )
    args = parser.parse_args()
    if args.slabs and not args.child:
        if args.slabs not in CASES:
            parser.error(f"unknown case {args.slabs!r}")
        compare_slabs(args.slabs, SLAB_COUNT)
        return
    if args.degeneracy and not args.child:
        done = subprocess.run(
            [sys.executable, __file__, "--child", "degeneracy"],
            capture_output=True,
            text=True,
            check=True,
        )
        r = json.loads(done.stdout.strip().splitlines()[-1])
        print(f"CGAL's Delaunay of {r['count']:,} points ({r['case']}), CPU seconds:")
        for label in ("seeds", "seeds moved by 1e-9", "random points"):
            print(f"  {label:22s} {r[label]:6.2f}")
        return
    if args.cube:
        args.cases, args.sample = CUBE_CASES, True
    if args.tiny:
        args.cases = TINY_CASES
        compare_voronoi(CASES[TINY_CASES.split(",")[-1]][2])
        compare_slabs(TINY_CASES.split(",")[-1], SLAB_COUNT)
    if args.child:
        if args.child == "degeneracy":
            result = run_degeneracy()
        elif args.child.startswith("seeds-"):
            import numpy as np

            name, path = args.child.removeprefix("seeds-").split("@")
            seeds = _case_seeds(name)
            np.savez(path, points=seeds.points, inside=seeds.inside)
            return
        elif args.child.startswith("mhat-"):
            count, path = args.child.removeprefix("mhat-").split("@")
            result = run_mhat(int(count), path)
        elif args.child.startswith("sample-"):
            result = run_sample(args.child.removeprefix("sample-"))
        elif args.child.startswith("qhull-"):
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
            f"{r['tetrahedra']:,} tetrahedra ({r.get('slabs', 1)} slab(s)), "
            f"{r['n_facets']:,} facets of M̂, ε = {r['eps']}, "
            f"topology {'right' if r['topology_correct'] else 'WRONG'}"
        )
        print(
            f"  {r['delaunay_edges']:,} in/out Delaunay edges, {r['collapsed']:,} of them "
            f"without area; {r['guide_facets']:,} facets are the two seeds of one guide "
            f"triangle ({100 * r['guide_facets'] / r['n_facets']:.1f} %)"
        )
        for stage, (wall, cpu, peak) in r["stages"].items():
            share = 100 * cpu / r["cpu"]
            print(
                f"  {stage:36s} {wall:8.2f} s wall {cpu:8.2f} s CPU {share:5.1f} %  "
                f"peak so far {peak:.2f} GB"
            )
        if r["case"].startswith("cube"):
            verdict = "ok" if r["cpu"] <= CUBE_TARGET_CPU else "SLOW"
            memory = "ok" if r["peak_gb"] <= CUBE_TARGET_GB else "OVER"
            target, memory_target = f"{CUBE_TARGET_CPU:.0f} CPU-s", CUBE_TARGET_GB
        else:
            target, memory_target = f"{TARGET_SECONDS:.0f} s wall", MEMORY_TARGET_GB
        print(
            f"  total {r['total']:.1f} s wall, CPU {r['cpu']:.1f} s [{verdict} ≤ {target}], "
            f"peak {r['peak_gb']:.2f} GB [{memory} ≤ {memory_target:.1f} GB], load average "
            f"{r['load_before']:.2f} → {r['load_after']:.2f}"
        )
    if len(results) >= 2:
        _growth("reconstruct", results, "n_seeds", "seeds")
    if args.sample:
        rows = []
        for name in (c for c in args.cases.split(",") if CASES[c][0] == "cube"):
            # In a child of its own, so that the peak of its children is the sample's alone.
            done = subprocess.run(
                [sys.executable, __file__, "--child", f"sample-{name}"],
                capture_output=True,
                text=True,
                check=True,
            )
            r = json.loads(done.stdout.strip().splitlines()[-1])
            rows.append(r)
            print(
                f"sample {name}: {r['n_samples']:,} samples, {r['cpu']:.1f} s CPU, "
                f"{r['wall']:.1f} s wall, peak {r['peak_gb']:.2f} GB"
            )
        if len(rows) >= 2:
            _growth("sample", rows, "n_samples", "samples")


def _growth(what: str, rows: list[dict], size_key: str, unit: str) -> None:
    """The growth exponent of the CPU time between consecutive rows and over all of them
    (the least-squares slope of log CPU against log size)."""
    size = [math.log(r[size_key]) for r in rows]
    cpu = [math.log(r["cpu"]) for r in rows]
    steps = ", ".join(
        f"n^{(cpu[k + 1] - cpu[k]) / (size[k + 1] - size[k]):.2f}" for k in range(len(rows) - 1)
    )
    mean_size, mean_cpu = sum(size) / len(size), sum(cpu) / len(cpu)
    slope = sum((x - mean_size) * (y - mean_cpu) for x, y in zip(size, cpu, strict=True)) / sum(
        (x - mean_size) ** 2 for x in size
    )
    print(
        f"\ngrowth of {what} CPU time from {rows[0]['case']} to {rows[-1]['case']} "
        f"({rows[0][size_key]:,} → {rows[-1][size_key]:,} {unit}): steps {steps}; "
        f"fit n^{slope:.2f}"
    )


if __name__ == "__main__":
    main()
