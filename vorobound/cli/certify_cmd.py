"""``vorobound certify``: an interval certificate of the tight bound, or its re-check."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ..constants import PAPER_DELTA_RATIO, PAPER_RHO_F, PAPER_SIGMA
from ..rounding import format_down, format_up
from .command import invoke
from .options import LAMBDA_HELP, DeltaRatio, Json, RhoF, Sigma, TargetChoice, TargetOpt
from .render import fmt, print_footer, print_table

CertLipschitz = Annotated[
    float | None,
    typer.Option(
        "--lipschitz",
        metavar="LAMBDA",
        help=LAMBDA_HELP + "added to the constraint set between the vertices of every guide "
        "triangle (λ = 1: a local feature size).",
    ),
]
CertEps = Annotated[
    float | None,
    typer.Option(
        "--eps",
        metavar="EPS",
        help="Certify every ε in (0, EPS] (default: --fraction × the tight ε* that "
        "`vorobound solve --mode tight` prints for the same target).",
    ),
]
Fraction = Annotated[
    float,
    typer.Option(
        "--fraction", metavar="FRACTION", help="Without --eps, certify this fraction of tight ε*."
    ),
]
Output = Annotated[
    Path | None,
    typer.Option("-o", "--output", metavar="FILE", help="Write the certificate (JSON) here."),
]
Check = Annotated[
    Path | None,
    typer.Option(
        "--check",
        metavar="FILE",
        help="Re-verify this certificate file instead, with two checkers (the prover's own and "
        "an independent one); valid only when both accept it. Its own parameters are used; "
        "the others are ignored.",
    ),
]
MaxDepth = Annotated[
    int | None,
    typer.Option(
        "--max-depth", metavar="N", help="Deepest bisection before giving up (default: 120)."
    ),
]
MaxBoxes = Annotated[
    int | None,
    typer.Option(
        "--max-boxes", metavar="N", help="Most boxes examined before giving up (default: 2·10⁷)."
    ),
]


def certify(
    sigma: Sigma = PAPER_SIGMA,
    delta_ratio: DeltaRatio = PAPER_DELTA_RATIO,
    rho_f: RhoF = PAPER_RHO_F,
    lipschitz: CertLipschitz = None,
    target: TargetOpt = TargetChoice.ratio,
    eps: CertEps = None,
    fraction: Fraction = 0.999,
    output: Output = None,
    check: Check = None,
    max_depth: MaxDepth = None,
    max_boxes: MaxBoxes = None,
    as_json: Json = False,
) -> int:
    """Prove with interval arithmetic that the target holds for every ε ≤ EPS: R ≤ ρ_f·R̂
    (ratio, eq. (54)) or R − R̂ ≤ (ρ_f − 1)·δ·L_i (additive).

    Covers every guide triangle of the constraint set (33)–(36), H3, pairwise sparsity and the
    optional Lipschitz conditions, by bisecting boxes (ε a coordinate) until each violates a
    constraint or has an outward-rounded bound within the target. Exit code 1, with a feasible
    counterexample, if EPS is above the true ε*. --check re-verifies a saved certificate with
    two checkers, the prover's own and an independent one sharing none of its code; it is
    valid only when both accept it (exit code 1, naming the checker, when they disagree). H3
    itself is an assumption from the VoroCrust literature. Python: vorobound.certify(...),
    vorobound.check_certificate(FILE).
    """
    options = dict(locals())
    if options.pop("check") is not None:
        return invoke("check_certificate", _show_check, {"as_json": as_json}, path=check)
    return invoke("certify", _show, options)


def _show(result) -> None:
    if not result.certified:
        _show_failure(result)
        return
    q, search = result.quality, result.certification.search
    status = result.certification.request.eps_star_status
    rows = [
        ("target", result.statement.split(": ", 1)[-1].split(", with R^")[0]),
        ("certified: every ε ≤", format_down(result.eps_certified, 12)),
        ("tight ε*", f"{format_down(result.eps_star_tight, 12)} ({status})"),
        ("certified / tight", fmt(result.ratio, 8)),
        ("boxes", str(search.boxes)),
        ("deepest bisection", str(search.max_depth)),
        ("seconds", fmt(search.seconds, 3)),
        (
            "certificate",
            "not written (use -o FILE)" if result.certificate is None else result.certificate,
        ),
    ]
    lam = "none" if q.lipschitz is None else f"{q.lipschitz:g}"
    print_table(
        f"Interval certificate, {result.target} target (σ = {q.sigma:g}, δ/ε = "
        f"{q.delta_ratio:g}, ρ_f = {q.rho_f:g}, λ = {lam})",
        ("quantity", "value"),
        rows,
    )
    print_footer(f"premise: {result.premise}")


def _show_check(checked) -> None:
    r = checked.report
    if checked.valid:
        valid = "yes: both checkers re-verified every leaf, the leaves cover the domain"
    else:
        valid = "NO: the two checkers disagree"
    rows = [
        ("valid", valid),
        *(
            (
                f"{c.name} checker",
                f"accepts ({c.seconds:.3f} s)" if c.valid else f"REJECTS: {c.reason}",
            )
            for c in checked.checkers
        ),
        ("target", r.target),
        ("every ε ≤" if checked.valid else "claimed: every ε ≤", format_down(r.eps_max, 12)),
        ("σ, δ/ε, ρ_f, λ", f"{r.sigma:g}, {r.delta_ratio:g}, {r.rho_f:g}, {r.lipschitz}"),
        ("boxes (leaves)", f"{r.boxes} ({r.leaves})"),
        ("largest bound / target", format_up(r.largest_bound, 10)),
        ("seconds (both checkers)", fmt(checked.seconds, 3)),
    ]
    print_table(f"Certificate {checked.certificate}", ("quantity", "value"), rows)


def _show_failure(result) -> None:
    """Why certification stopped: the counterexample, or the unresolved box."""
    from ..bounds.certify.interval import DIMENSIONS

    data = result.to_dict()
    found = data.get("counterexample")
    if found is not None:
        rows = [
            (k, fmt(v) if isinstance(v, float) else str(v))
            for k, v in found.items()
            if k != "coordinates"
        ]
        print_table(
            "Counterexample (feasible, checked in intervals and in floats)",
            ("quantity", "value"),
            rows,
        )
    if "box" in data:
        rows = [
            (name, f"[{fmt(lo)}, {fmt(hi)}]")
            for name, (lo, hi) in zip(DIMENSIONS, data["box"], strict=True)
        ]
        print_table("Unresolved box", ("coordinate", "interval"), rows)
