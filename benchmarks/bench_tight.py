"""Wall time of the tight bound at the paper parameters (σ = 3/4, δ/ε = 2, ρ_f = 1.38).

Run: ``python benchmarks/bench_tight.py [--repeats 3] [--tiny]``. Prints, for λ = None and λ = 1,

* the tight supremum of R − R̂ at ε = 0.0047 (:func:`vorobound.bounds.tight.tight_supremum`,
  default budgets), its fraction of the target (ρ_f − 1)δL_i and the best wall time of
  ``--repeats`` runs (target ≤ 2 s);
* the tight ε* (:func:`vorobound.bounds.tight.solve_tight`) and its wall time (target ≤ 30 s),

next to the rigorous chain's ε* for comparison.
"""

from __future__ import annotations

import argparse
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
from vorobound.bounds.eps_star import solve_eps_star  # noqa: E402
from vorobound.bounds.params import QualityParams  # noqa: E402
from vorobound.bounds.tight import solve_tight, tight_supremum  # noqa: E402

SUPREMUM_TARGET_S = 2.0
EPS_STAR_TARGET_S = 30.0
PAPER_EPS = 0.0047
TINY_BUDGETS = {"dense_samples": 2_000, "de_maxiter": 5}
"""Search budgets of a --tiny run."""


def timed(fn, repeats: int):
    """(result of the last run, best wall time in seconds)."""
    best, result = float("inf"), None
    for _ in range(repeats):
        start = time.perf_counter()
        result = fn()
        best = min(best, time.perf_counter() - start)
    return result, best


def verdict(seconds: float, target: float) -> str:
    return "ok" if seconds <= target else "SLOW"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3, help="runs per timing (best kept)")
    parser.add_argument(
        "--tiny",
        action="store_true",
        help="one run, small search budgets (CI: it runs; the numbers are not the bound's)",
    )
    args = parser.parse_args()
    budgets = TINY_BUDGETS if args.tiny else {}
    if args.tiny:
        args.repeats = 1
    params = QualityParams(target="additive").at(PAPER_EPS)
    print(f"paper parameters, {os.cpu_count()} cores")
    print(f"  rigorous eps*: {solve_eps_star(params.quality, 'rigorous').eps_star:.7f}")
    for lam in (None, 1.0):
        at_lam = params.but(lipschitz=lam)
        result, seconds = timed(lambda p=at_lam: tight_supremum(p, **budgets), args.repeats)
        evidence = result.evidence
        print(
            f"  λ={lam!s:4}  sup(R − R̂) at ε={PAPER_EPS}: {result.supremum:.10e} "
            f"= {result.supremum / params.gap_allowance:.6f} of the target, "
            f"{seconds:6.2f} s [{verdict(seconds, SUPREMUM_TARGET_S)} ≤ {SUPREMUM_TARGET_S} s]"
        )
        print(
            f"          starts agreeing {evidence.agreeing_starts}/{evidence.starts}, "
            f"spread {evidence.spread_of_local_optima:.1e}, dense sample max "
            f"{evidence.dense_sample_extreme / result.supremum:.4f} of sup "
            f"({evidence.dense_samples} points); active: " + ", ".join(evidence.active_constraints)
        )
    for lam in (None, 1.0):
        quality = params.quality.but(lipschitz=lam)
        star, seconds = timed(lambda q=quality: solve_tight(q, **budgets), args.repeats)
        print(
            f"  λ={lam!s:4}  tight eps*: {star.eps_star:.10f} (residual {star.residual:.1e}), "
            f"{seconds:6.2f} s [{verdict(seconds, EPS_STAR_TARGET_S)} ≤ {EPS_STAR_TARGET_S} s]"
        )


if __name__ == "__main__":
    main()
