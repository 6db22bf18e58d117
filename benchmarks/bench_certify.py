"""Interval certificates of the tight bound: how close to ε* they get, and how long they take.

Run: ``python benchmarks/bench_certify.py [--fraction 0.999] [--sets paper,lipschitz,...]
[--targets additive,ratio]``. For each parameter set and target it certifies every
ε ≤ fraction·ε* (ε* the closed-form tight ε* of that target),
writes the certificate to a temporary file, re-checks it from the file, and prints

* ε_certified, ε* and their ratio (target ≥ 0.999), boxes, deepest bisection;
* the search time (target ≤ 300 s on 2 cores, goal ≤ 60 s) and the time of each of the two
  checkers that ``certify --check`` runs (the prover's own re-check and the independent one of
  :mod:`vorobound.bounds.independent`; target ≤ 60 s each), wall and CPU seconds;
* as the baseline of the same run, the search at 0.9·ε* (the cost of the last digits);
* the time of one closed-form ε* (``tight_eps_star_closed_form``), which solve uses.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
from vorobound.bounds.certify import certify  # noqa: E402
from vorobound.bounds.certify.certificate import (  # noqa: E402
    check_certificate,
    read_certificate,
    write_certificate,
)
from vorobound.bounds.independent import check_independently  # noqa: E402
from vorobound.bounds.params import QualityParams  # noqa: E402
from vorobound.bounds.tight.closed_form import tight_eps_star_closed_form  # noqa: E402
from vorobound.rounding import format_down, format_up

SETS = {
    "paper": (0.75, 2.0, 1.38, None),
    "lipschitz": (0.75, 2.0, 1.38, 1.0),
    "sigma-0.5": (0.5, 2.0, 1.38, None),
    "delta-ratio-3": (0.75, 3.0, 1.38, None),
}
"""σ, δ/ε, ρ_f, λ of the measured parameter sets."""
RATIO_TARGET = 0.999
SEARCH_TARGET_S = 300.0
SEARCH_GOAL_S = 60.0
CHECK_TARGET_S = 60.0
BASELINE_FRACTION = 0.9
CLOSED_FORM_CALLS = 2000
TINY_FRACTION = 0.5
"""Fraction of ε* a --tiny run certifies (few boxes)."""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fraction", type=float, default=RATIO_TARGET)
    parser.add_argument("--sets", default=",".join(SETS), help="comma list of " + ", ".join(SETS))
    parser.add_argument("--targets", default="additive,ratio", help="comma list of targets")
    parser.add_argument(
        "--tiny",
        action="store_true",
        help=f"--fraction {TINY_FRACTION} --sets paper --targets ratio (CI: it runs)",
    )
    args = parser.parse_args()
    if args.tiny:
        args.fraction, args.sets, args.targets = TINY_FRACTION, "paper", "ratio"
    print(f"{os.cpu_count()} cores; fraction {args.fraction} of the closed-form tight eps*")
    tight_eps_star_closed_form(*SETS["paper"])  # imports scipy once, outside the timing
    start = time.perf_counter()
    for _ in range(CLOSED_FORM_CALLS):
        tight_eps_star_closed_form(*SETS["paper"])
    per_call = (time.perf_counter() - start) / CLOSED_FORM_CALLS
    print(f"closed-form tight eps*: {per_call * 1e6:.0f} us per call")
    for target, name in ((t, n) for t in args.targets.split(",") for n in args.sets.split(",")):
        sigma, ratio, rho_f, lam = SETS[name]
        quality = QualityParams(sigma, ratio, rho_f, lipschitz=lam, target=target)
        baseline = certify(quality, fraction=BASELINE_FRACTION)
        result = certify(quality, fraction=args.fraction)
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, "cert.json")
            write_certificate(path, result.certificate())
            size = os.path.getsize(path)
            payload = read_certificate(path)
            report, check_s, check_cpu = _timed(check_certificate, payload)
            second, second_s, second_cpu = _timed(check_independently, payload)
            assert second.leaves == report.leaves and second.eps_max == report.eps_max
        search = result.search
        verdict = "ok" if search.seconds <= SEARCH_TARGET_S else "SLOW"
        goal = "goal met" if search.seconds <= SEARCH_GOAL_S else "goal missed"
        print(
            f"{target:9} {name:14} sigma={sigma:g} delta/eps={ratio:g} rho_f={rho_f:g} "
            f"lambda={lam}\n"
            f"  eps* ({result.request.eps_star_status}) = "
            f"{format_down(result.request.eps_star_tight, 9)}\n"
            f"  certified eps <= {format_down(result.eps_certified, 9)}  ratio {result.ratio:.6f} "
            f"[{'ok' if result.ratio >= RATIO_TARGET else 'LOW'} >= {RATIO_TARGET}]\n"
            f"  search: {search.boxes} boxes, depth {search.max_depth}, {search.seconds:.2f} s "
            f"[{verdict} <= {SEARCH_TARGET_S:g} s, {goal} <= {SEARCH_GOAL_S:g} s]; "
            f"baseline at {BASELINE_FRACTION}: {baseline.search.boxes} boxes, "
            f"{baseline.search.seconds:.2f} s (x{search.seconds / baseline.search.seconds:.2f})\n"
            f"  check: {report.leaves} leaves, largest bound/target "
            f"{format_up(report.largest_bound, 9)}; "
            f"prover's checker {check_s:.3f} s ({check_cpu:.3f} s CPU), independent checker "
            f"{second_s:.3f} s ({second_cpu:.3f} s CPU) "
            f"[{'ok' if max(check_s, second_s) <= CHECK_TARGET_S else 'SLOW'} <= "
            f"{CHECK_TARGET_S:g} s each]; file {size / 1e6:.2f} MB"
        )


def _timed(checker, payload):
    """(report, wall seconds, CPU seconds) of one checker on a certificate."""
    wall, cpu = time.perf_counter(), time.process_time()
    report = checker(payload)
    return report, time.perf_counter() - wall, time.process_time() - cpu


if __name__ == "__main__":
    main()
