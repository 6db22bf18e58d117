"""The table of docs/vorocrust.md: VoroCrust runs read, inferred and reconstructed by vorobound.

    python benchmarks/bench_vorocrust.py RUNS [--upstream DATASETS]

RUNS is a folder for the run directories. Our parts (a torus and a cube made by vorobound's
code, run with vc_mesh's own test-deck settings; the same cube through advise --vorocrust) are
written there; with ``--upstream``, the Torus and Bracket of vorocrust-meshing's
tests/datasets are copied there too. A run directory without ball files is run with ``vc_mesh
-vc vc.in`` when vc_mesh is on PATH (this script does not build it; docs/vorocrust.md says
which commit was built). Prints the markdown table, with wall and CPU seconds of each side.
"""

from __future__ import annotations

import argparse
import resource
import shutil
import subprocess
import sys
import time
import warnings
from pathlib import Path


def _children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def _write_obj(mesh, path: Path) -> None:
    from vorobound.sampling.io.vorocrust import obj_writer

    obj_writer(mesh.points, mesh.triangles)(path)


def our_parts(runs: Path) -> dict[str, dict]:
    """Our torus and cube with vc_mesh's test-deck settings: the inputs of the recorded runs
    in tests/data/vorocrust (made by vorobound's code, see its README)."""
    data = Path(__file__).parents[1] / "tests" / "data" / "vorocrust"
    parts = {
        "torus R=1, r=0.4 (ours)": ("torus", {"torus": (1.0, 0.4)}),
        "cube side 2 (ours)": ("cube", {"lfs": 1.0}),
    }
    out = {}
    for label, (name, surface) in parts.items():
        folder = runs / name
        folder.mkdir(parents=True, exist_ok=True)
        for file in ("vc.in", f"{name}.obj"):
            if not (folder / file).exists():
                shutil.copy(data / name / file, folder / file)
        out[label] = {"folder": folder, "surface": surface}
    return out


def advised_part(runs: Path) -> dict[str, dict]:
    """The cube through advise --vorocrust (rho_f = 3, lambda = 1: a run of a few thousand
    balls)."""
    import vorobound
    from vorobound.sampling.surfaces import cad_meshes

    folder = runs / "cube-advised"
    source = runs / "cube-source.obj"
    _write_obj(cad_meshes.cube(), source)
    stamp = folder / "advise_seconds.txt"
    if not (folder / "vc.in").exists():
        start, cpu = time.perf_counter(), time.process_time()
        vorobound.advise(mesh=source, lfs=1.0, rho_f=3.0, lipschitz=1.0, vorocrust=folder)
        seconds = (time.perf_counter() - start, time.process_time() - cpu)
        stamp.write_text(f"{seconds[0]:.2f} {seconds[1]:.2f}\n")
    seconds = tuple(map(float, stamp.read_text().split())) if stamp.exists() else None
    return {
        "cube, advise --rho-f 3 --lipschitz 1": {
            "folder": folder,
            "surface": {"lfs": 1.0},
            "advise": seconds,
        }
    }


def upstream_parts(runs: Path, datasets: Path) -> dict[str, dict]:
    out = {}
    for name, surface in (("Torus", {"torus": (1.0, 0.5, "y")}), ("Bracket", {})):
        folder = runs / f"upstream-{name}"
        if not folder.exists():
            shutil.copytree(datasets / name, folder)
        out[f"{name} (vorocrust-meshing tests)"] = {"folder": folder, "surface": surface}
    return out


def recorded_parts(runs: Path) -> dict[str, dict]:
    """The recorded runs the tests use (tests/data/vorocrust), copied into ``runs``."""
    data = Path(__file__).resolve().parents[1] / "tests" / "data" / "vorocrust"
    out = {}
    for name in ("cube", "torus"):
        folder = runs / f"recorded-{name}"
        if not folder.exists():
            shutil.copytree(data / name, folder)
        out[f"{name} (recorded run)"] = {"folder": folder, "surface": {}}
    return out


def run_vc_mesh(folder: Path) -> tuple[float, float] | None:
    """(wall, CPU) seconds of ``vc_mesh -vc vc.in`` in ``folder``; None if it is not run."""
    if (folder / "surface_spheres.csv").exists():
        stamp = folder / "vc_mesh_seconds.txt"
        return tuple(map(float, stamp.read_text().split())) if stamp.exists() else None
    if shutil.which("vc_mesh") is None:
        return None
    cpu, start = _children_cpu(), time.perf_counter()
    subprocess.run(["vc_mesh", "-vc", "vc.in"], cwd=folder, check=True, capture_output=True)
    seconds = (time.perf_counter() - start, _children_cpu() - cpu)
    (folder / "vc_mesh_seconds.txt").write_text(f"{seconds[0]:.2f} {seconds[1]:.2f}\n")
    return seconds


def timed(call):
    start, cpu = time.perf_counter(), time.process_time()
    value = call()
    return value, (time.perf_counter() - start, time.process_time() - cpu)


def measure(label: str, part: dict) -> dict:
    import vorobound
    from vorobound.rounding import format_up

    folder, surface = part["folder"], part["surface"]
    vc = run_vc_mesh(folder)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        check, check_s = timed(lambda: vorobound.check(vorocrust=folder, **surface))
        rec, rec_s = timed(lambda: vorobound.reconstruct(vorocrust=folder, **surface))
    c, r = check.to_dict(), rec.to_dict()
    realized, guarantee, strata = c["realized"], c["guarantee"], c["strata"]
    balls = f"{strata['corner']}/{strata['edge']}/{strata['surface']}"
    # already rounded toward safety by the inference: printed as they are
    params = (
        f"{realized['eps']:.5g}, {realized['sigma']:.5g}, "
        f"{realized['delta_ratio']:.5g}, {realized['lipschitz']:.5g}"
        if realized["eps"] is not None
        else f"none ({guarantee['failed_condition']})"
    )
    rho = "none" if guarantee["rho_f"] is None else f"{guarantee['rho_f']:.5g}"
    topo = f"χ = {r['euler_characteristic']}, " + ("correct" if r["topology_correct"] else "WRONG")
    fmt = lambda s: "—" if s is None else f"{s[0]:.1f} / {s[1]:.1f}"  # noqa: E731
    return {
        "part": label,
        "balls c/e/s": balls,
        "ε from coverage": f"{realized['eps_coverage']:.5g}",
        "ε, σ, δ/ε, λ realized": params,
        "proven ρ_f (R ≤ ρ_f·R̂)": rho,
        "max R/R̂ measured": format_up(c["ratio_max"]),
        "max H3 ratio": format_up(c["h3_ratio_max"]),
        "M̂ topology": topo,
        "Hausdorff / r": format_up(r["hausdorff_over_eps_lfs"]),
        "vc_mesh s (wall/CPU)": fmt(vc),
        "advise s": fmt(part.get("advise")),
        "check s": fmt(check_s),
        "reconstruct s": fmt(rec_s),
    }


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", type=Path)
    parser.add_argument("--upstream", type=Path, help="vorocrust-meshing's tests/datasets")
    parser.add_argument("--no-advised", action="store_true", help="leave out the advised cube")
    parser.add_argument(
        "--tiny",
        action="store_true",
        help="CI: only the recorded runs of tests/data/vorocrust (no vc_mesh needed)",
    )
    args = parser.parse_args(argv)
    args.runs.mkdir(parents=True, exist_ok=True)
    if args.tiny:
        parts = recorded_parts(args.runs)
    else:
        parts = {} if args.upstream is None else upstream_parts(args.runs, args.upstream)
        parts |= our_parts(args.runs)
        if not args.no_advised:
            parts |= advised_part(args.runs)
    rows = [measure(label, part) for label, part in parts.items()]
    header = list(rows[0])
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for row in rows:
        print("| " + " | ".join(row[h] for h in header) + " |")
    print()
    print(lipschitz_for(1.38))
    return 0


def lipschitz_for(rho_f: float) -> str:
    """The radius Lipschitz constant Λ at which the realized μ* = X(2 + X)/S², X = ΛS, meets
    1 − 1/ρ_f, with vc_mesh's spacing S = β = sqrt(1 − 0.4²) (docs/vorocrust.md)."""
    import math

    from vorobound.rounding import format_down

    spacing = math.sqrt(1 - 0.4**2)
    share = 1 - 1 / rho_f
    excess = share * spacing**2 / (1 + math.sqrt(1 + share * spacing**2))  # X(2+X) = s, stably
    return (
        f"With S = {spacing:.5f}, LIP_CONST <= {format_down(excess / spacing)} keeps mu* <= "
        f"1 - 1/{rho_f:g} at every eps (X = Lambda*S caps 2eps/(1-eps))"
    )


if __name__ == "__main__":
    sys.exit(main())
