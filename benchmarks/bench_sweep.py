"""Sweep throughput and memory: a paper-mode ε* grid streamed to a CSV file.

Usage: python benchmarks/bench_sweep.py [--side N ...] [--tiny]

Runs ``vorobound sweep --sigma 0.3:1.5:N --rho-f 1.01:3:N --mode paper --format csv -o FILE``
in a fresh process per size and prints rows, wall time, rows per second and the process's peak
resident memory. Constant memory across sizes is the point: rows stream out chunk by chunk.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

PROBE = (
    "import resource, sys\n"
    "from vorobound.cli import main\n"
    "code = main(sys.argv[1:])\n"
    "print('PEAK_KB', resource.getrusage(resource.RUSAGE_SELF).ru_maxrss, file=sys.stderr)\n"
    "sys.exit(code)\n"
)


def run(side: int, folder: Path) -> tuple[int, float, float]:
    out = folder / f"sweep{side}.csv"
    args = ["sweep", "--sigma", f"0.3:1.5:{side}", "--rho-f", f"1.01:3:{side}"]
    args += ["--mode", "paper", "--format", "csv", "-o", str(out)]
    start = time.perf_counter()
    done = subprocess.run(
        [sys.executable, "-c", PROBE, *args], capture_output=True, text=True, check=True
    )
    seconds = time.perf_counter() - start
    peak_mb = int(done.stderr.split("PEAK_KB")[1].split()[0]) / 1024
    return side * side, seconds, peak_mb


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--side", type=int, nargs="+", default=[100, 300, 1000])
    parser.add_argument("--tiny", action="store_true", help="--side 10 20 (CI: it runs)")
    args = parser.parse_args()
    if args.tiny:
        args.side = [10, 20]
    print(f"{'rows':>10s} {'seconds':>8s} {'rows/s':>10s} {'peak MB':>8s}")
    with tempfile.TemporaryDirectory() as folder:
        for side in args.side:
            rows, seconds, peak = run(side, Path(folder))
            print(f"{rows:10d} {seconds:8.2f} {rows / seconds:10.0f} {peak:8.1f}")


if __name__ == "__main__":
    main()
