"""Scale tables of ``benchmarks/bench_lfs.py --scale`` (and ``--big``): time and memory of the
local-feature-size estimate on large meshes, each measured in a process of its own.

* End to end at 10⁵ faces: ``vorobound lfs PART -o L.csv`` and ``vorobound advise --mesh
  PART`` on a finely meshed L-bracket with a bore (the CAD test part of
  ``vorobound.sampling.surfaces.cad_meshes``, 105 408 faces), written as a VTU file; wall and
  CPU seconds (all threads) and the peak resident memory of each command. Targets of issue 20:
  ``lfs`` ≤ 60 s and ``advise --mesh`` ≤ 90 s wall on 2 cores.
* Growth: ``estimate_lfs`` on brackets of three sizes and on torus grids of three sizes (four
  with ``--big``, which adds the 10⁶-vertex torus 2000 × 500: target ≤ 10 min and ≤ 8 GB),
  with the split of its time into stages (from its progress reports) and the exponent p of
  time ∝ size^p (least squares over the sizes, and between the two largest).

The machine is shared: every row gives the CPU seconds beside the wall seconds, and the load
average is printed before and after.
"""

from __future__ import annotations

import json
import os
import resource
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
BENCH = Path(__file__).resolve().parent / "bench_lfs.py"
LFS_SECONDS, ADVISE_SECONDS, BIG_SECONDS, BIG_GB = 60.0, 90.0, 600.0, 8.0
BRACKETS = ((0.2, 8, 16), (0.1, 24, 32), (0.05, 60, 64))
"""(spacing, bore rings, bore segments) of the L-brackets; the last has 105 408 faces."""
TORI = ((256, 64), (512, 128), (1024, 256))
BIG_TORUS = (2000, 500)
TINY_BRACKETS = ((0.8, 2, 8),)
TINY_TORI = ((24, 8), (32, 12))
"""--tiny: the bracket of the end-to-end runs (no bracket growth) and two small tori."""
"""Torus grid (around, along the tube) of 10⁶ vertices."""
ROUND_STAGES = (
    "face sites",
    "pole distances",
    "rays",
    "feature sizes",
    "tangent balls",
    "Lipschitz repair",
    "site radii",
    "L at the vertices",
)


def _environment() -> dict:
    """The children's environment: this checkout first on the import path."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), env.get("PYTHONPATH")]))
    return env


def measure(command: list[str]) -> dict:
    """Wall and CPU seconds and peak memory of ``command``, run by a process of its own."""
    wrapper = [sys.executable, str(BENCH), "--measure", *command]
    done = subprocess.run(wrapper, capture_output=True, text=True, env=_environment())
    # advise exits 1 when `sample` cannot build its recommendation (it still advises, and its
    # cost is what is measured); any other non-zero code is a failure.
    allowed = {0, 1} if "advise" in command else {0}
    if done.returncode not in allowed:
        raise RuntimeError(f"{' '.join(command)} failed:\n{done.stderr[-2000:]}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def measure_child(command: list[str]) -> None:
    """``--measure COMMAND...``: run it and print its rusage as one JSON line (this process
    has no other child, so the children's rusage is the command's)."""
    start = time.perf_counter()
    done = subprocess.run(command, capture_output=True, text=True)
    wall = time.perf_counter() - start
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    report = {
        "wall": wall,
        "cpu": usage.ru_utime + usage.ru_stime,
        "peak_gb": usage.ru_maxrss / 2**20,  # kilobytes on Linux
        "returncode": done.returncode,
        "stdout": done.stdout[-20000:],
        "stderr": done.stderr[-2000:],
    }
    print(json.dumps(report))
    sys.exit(done.returncode)


class StageTimer:
    """A progress callback that adds the wall and CPU seconds between two reports to the stage
    that made the earlier one."""

    def __init__(self):
        self.wall: dict[str, float] = {}
        self.cpu: dict[str, float] = {}
        self.task = None
        self.since = (time.perf_counter(), time.process_time())

    def __call__(self, task: str, done=None, total=None) -> None:
        now = (time.perf_counter(), time.process_time())
        if self.task is not None:
            self.wall[self.task] = self.wall.get(self.task, 0.0) + now[0] - self.since[0]
            self.cpu[self.task] = self.cpu.get(self.task, 0.0) + now[1] - self.since[1]
        self.task, self.since = task, now


def child(argv: list[str]) -> None:
    """``--child PATH``: the estimate of one mesh file with its stage split, as a JSON line."""
    from vorobound.errors import VoroboundWarning
    from vorobound.sampling.io.meshes import read_triangle_mesh
    from vorobound.sampling.lfs.estimate import estimate_lfs

    mesh = read_triangle_mesh(argv[0])
    timer = StageTimer()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", VoroboundWarning)
        estimate = estimate_lfs(mesh, progress=timer)
    timer("end")
    print(
        json.dumps(
            {
                "vertices": len(mesh.points),
                "faces": len(mesh.triangles),
                "sites": len(estimate.sites.points),
                "rounds": estimate.rounds,
                "stage_wall": timer.wall,
                "stage_cpu": timer.cpu,
            }
        )
    )


def _write(mesh, folder: Path, name: str) -> Path:
    """The mesh as a VTU file (double precision, as the estimate sees it in memory)."""
    import meshio

    path = folder / f"{name}.vtu"
    meshio.write(path, meshio.Mesh(mesh.points, [("triangle", mesh.triangles)]))
    return path


def _estimate_row(path: Path) -> dict:
    measured = measure([sys.executable, str(BENCH), "--child", str(path)])
    return measured | json.loads(measured["stdout"].strip().splitlines()[-1])


def _split(row: dict) -> str:
    """The stage split: the stages before the rounds, each round stage summed over the rounds,
    and the result, in wall seconds (stages under 0.05 s left out)."""
    wall = row["stage_wall"]
    before = [name for name in wall if name not in ROUND_STAGES and name != "result"]
    names = before + [name for name in ROUND_STAGES if name in wall] + ["result"]
    parts = [(name, wall[name]) for name in names if name in wall]
    return ", ".join(f"{name} {seconds:.1f}" for name, seconds in parts if seconds >= 0.05)


def _exponent(sizes, seconds) -> tuple[float, float]:
    """Slope of log(seconds) against log(size): least squares over all, and the last pair."""
    x, y = np.log(np.asarray(sizes, float)), np.log(np.asarray(seconds, float))
    fit = float(np.polyfit(x, y, 1)[0])
    return fit, float((y[-1] - y[-2]) / (x[-1] - x[-2]))


def _load() -> str:
    return f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores (shared machine)"


def tables(big: bool, tiny: bool = False) -> None:
    """Print the scale tables (see the module docstring); ``tiny``: two small brackets and
    tori, that every step runs (the numbers mean nothing)."""
    from vorobound.sampling.surfaces import cad_meshes
    from vorobound.sampling.surfaces.demo_meshes import torus_mesh

    print(f"\n## Scale ({_load()})")
    shapes = (
        (TINY_BRACKETS, TINY_TORI) if tiny else (BRACKETS, TORI + ((BIG_TORUS,) if big else ()))
    )
    brackets = [cad_meshes.l_bracket(spacing=h, rings=r, segments=s) for h, r, s in shapes[0]]
    tori = [torus_mesh(3.0, 1.0, a, t) for a, t in shapes[1]]
    with tempfile.TemporaryDirectory() as folder:
        folder = Path(folder)
        part = _write(brackets[-1], folder, "bracket")
        print(f"\n### End to end: {len(brackets[-1].triangles):,} faces ({brackets[-1].name})")
        cli = [sys.executable, "-m", "vorobound"]
        for label, command, target in (
            ("vorobound lfs", [*cli, "lfs", str(part), "-o", str(folder / "L.csv")], LFS_SECONDS),
            ("vorobound advise --mesh", [*cli, "advise", "--mesh", str(part)], ADVISE_SECONDS),
        ):
            row = measure(command)
            verdict = "met" if row["wall"] <= target else "missed"
            print(
                f"{label:24s} {row['wall']:7.1f} s wall {row['cpu']:7.1f} s CPU "
                f"{row['peak_gb']:5.2f} GB peak   target ≤ {target:g} s wall: {verdict}"
            )
        growth = [
            ("L-brackets (size: faces)", brackets, "faces"),
            ("torus grids (size: vertices)", tori, "vertices"),
        ]
        for title, meshes, size_of in growth[1:] if tiny else growth:
            print(f"\n### Growth, {title}: estimate_lfs in a process of its own")
            rows = []
            for index, mesh in enumerate(meshes):
                path = _write(mesh, folder, f"mesh{index}")
                row = _estimate_row(path)
                path.unlink()
                rows.append(row)
                print(
                    f"{row['vertices']:>9,} vertices {row['faces']:>9,} faces "
                    f"{row['sites']:>10,} sites {row['rounds']} rounds: {row['wall']:7.1f} s wall "
                    f"{row['cpu']:7.1f} s CPU {row['peak_gb']:5.2f} GB peak\n"
                    f"    stages (wall s): {_split(row)}",
                    flush=True,
                )
            sizes = [row[size_of] for row in rows]
            fit, last = _exponent(sizes, [row["cpu"] for row in rows])
            print(f"growth exponent of CPU seconds: {fit:.2f} (fit), {last:.2f} (two largest)")
            if big and meshes is tori:
                row = rows[-1]
                time_ok = row["wall"] <= BIG_SECONDS
                memory_ok = row["peak_gb"] <= BIG_GB
                print(
                    f"10^6-vertex torus: {row['wall']:.0f} s wall (target ≤ {BIG_SECONDS:.0f} s: "
                    f"{'met' if time_ok else 'missed'}), {row['peak_gb']:.2f} GB peak (target "
                    f"≤ {BIG_GB:g} GB: {'met' if memory_ok else 'missed'})"
                )
    print(f"\n{_load()}")
