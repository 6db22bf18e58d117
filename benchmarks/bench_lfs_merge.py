"""What merging the thin face pieces costs in L: gears estimated with the merge and without it
(every piece its own site), L at the vertices compared (issue 35).

Run: ``python benchmarks/bench_lfs_merge.py [--gear 5000 20000] [--tiny]`` (gears of 200 teeth;
the faces asked for are about, not exactly, what the gear gets: 5000 gives 6 800).

A merged site stands for no more surface than a piece of the spacing does (docs/lfs.md), but
the pieces of long thin faces are much narrower than the spacing, so without the merge L is
sampled more finely across them. Printed per gear: the sites and CPU seconds of both estimates,
and, over the vertices, the share where the merged L differs from the unmerged one by more than
5 %, the largest relative difference below it and above it (below: the merged estimate is the
more conservative one).
"""

from __future__ import annotations

import argparse
import os
import time
import warnings

import numpy as np


def estimate(faces: int, merged: bool, small: bool = False):
    """(L at the vertices, sites, CPU seconds) of the gear of about ``faces`` faces (200 teeth;
    ``small``: 12 teeth, a bore of 2)."""
    import vorobound.sampling.lfs.face_sites as face_sites
    from vorobound.sampling.lfs.estimate import estimate_lfs
    from vorobound.sampling.surfaces.cad_meshes import gear

    thin = face_sites.THIN
    face_sites.THIN = thin if merged else 0.0  # no piece is thin: nothing is merged
    try:
        mesh = gear(teeth=12, faces=faces, bore=2.0) if small else gear(faces=faces)
        start = time.process_time()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = estimate_lfs(mesh)
        return result.lfs, len(result.sites.points), time.process_time() - start
    finally:
        face_sites.THIN = thin


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--gear", type=int, nargs="*", default=[5000], help="faces")
    parser.add_argument(
        "--tiny", action="store_true", help="CI: a gear of 12 teeth and about 800 faces"
    )
    args = parser.parse_args()
    if args.tiny:
        args.gear = [800]
    print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores (shared machine)")
    print(
        f"{'gear faces':>10s} | {'sites merged':>12s} {'CPU':>6s} | {'unmerged':>9s} {'CPU':>6s} |"
        f" {'> 5 % off':>9s} {'most below':>10s} {'most above':>10s}"
    )
    for faces in args.gear:
        merged, merged_sites, merged_cpu = estimate(faces, True, args.tiny)
        plain, plain_sites, plain_cpu = estimate(faces, False, args.tiny)
        change = (merged - plain) / plain
        print(
            f"{faces:10,d} | {merged_sites:12,d} {merged_cpu:5.1f}s | {plain_sites:9,d} "
            f"{plain_cpu:5.1f}s | {100 * np.mean(np.abs(change) > 0.05):8.2f}% "
            f"{100 * max(-change.min(), 0):9.1f}% {100 * max(change.max(), 0):9.1f}%",
            flush=True,
        )
    print(f"load average {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
