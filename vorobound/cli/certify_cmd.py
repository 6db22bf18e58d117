"""``vorobound certify``: an interval certificate of the tight bound, or its re-check."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ..constants import PAPER_DELTA_RATIO, PAPER_RHO_F, PAPER_SIGMA
from .options import DeltaRatio, Json, RhoF, Sigma, TargetChoice, TargetOpt
from .progress import progress_bar
from .render import fmt, print_json, print_table

EXIT_NOT_CERTIFIED = 1
"""ε_max is above the true ε* (a counterexample is printed) or the search hit a limit."""

CertLipschitz = Annotated[
    float | None,
    typer.Option(
        "--lipschitz",
        help="Add |L_x − L_y| ≤ λ|p_x − p_y| for each pair of vertices (λ = 1: local feature "
        "size).",
    ),
]
CertEps = Annotated[
    float | None,
    typer.Option(
        "--eps",
        help="Certify every ε in (0, EPS] (default: --fraction × the tight ε* that "
        "`vorobound solve --mode tight` prints for the same target).",
    ),
]
Fraction = Annotated[
    float, typer.Option("--fraction", help="Without --eps, certify this fraction of tight ε*.")
]
Out = Annotated[
    Path | None, typer.Option("--out", help="Write the certificate (JSON) to this file.")
]
Check = Annotated[
    Path | None,
    typer.Option(
        "--check",
        help="Re-verify this certificate file instead (its own parameters are used; the "
        "others are ignored).",
    ),
]
MaxDepth = Annotated[
    int | None,
    typer.Option("--max-depth", help="Deepest bisection before giving up (default: 120)."),
]
MaxBoxes = Annotated[
    int | None,
    typer.Option("--max-boxes", help="Most boxes examined before giving up (default: 2·10⁷)."),
]


def certify(
    sigma: Sigma = PAPER_SIGMA,
    delta_ratio: DeltaRatio = PAPER_DELTA_RATIO,
    rho_f: RhoF = PAPER_RHO_F,
    lipschitz: CertLipschitz = None,
    target: TargetOpt = TargetChoice.ratio,
    eps: CertEps = None,
    fraction: Fraction = 0.999,
    out: Out = None,
    check: Check = None,
    max_depth: MaxDepth = None,
    max_boxes: MaxBoxes = None,
    as_json: Json = False,
) -> None:
    """Prove with interval arithmetic that the target holds for every ε ≤ EPS: R ≤ ρ_f·R̂
    (ratio, eq. (54)) or R − R̂ ≤ (ρ_f − 1)·δ·L_i (additive).

    Covers every guide triangle of the constraint set (33)–(36), H3, pairwise sparsity and the
    optional Lipschitz conditions, by bisecting boxes (ε a coordinate) until each violates a
    constraint or has an outward-rounded bound within the target. Exit code 1, with a feasible
    counterexample, if EPS is above the true ε*. --check re-verifies a saved certificate. H3
    itself is an assumption from the VoroCrust literature.
    """
    if check is not None:
        return _check(check, as_json)
    from ..bounds.certify import CertifyRequest, NotCertified, certify_request, search_limits

    limits = search_limits(max_depth, max_boxes)
    with progress_bar(not as_json) as progress:
        request = CertifyRequest.of(
            sigma,
            delta_ratio,
            rho_f,
            lipschitz,
            eps=eps,
            fraction=fraction,
            target=target.value,
            progress=progress,
        )
        try:
            result = certify_request(request, **limits, progress=progress)
        except NotCertified as failure:
            _report_failure(failure, as_json, target.value)
            raise typer.Exit(EXIT_NOT_CERTIFIED) from None
    if out is not None:
        from ..bounds.certify.certificate import write_certificate

        write_certificate(out, result.certificate())
    search = result.search
    from ..bounds.targets import H3_STATUS

    payload = {
        "certified": True,
        "claim": "certified",
        "target": request.target,
        "statement": result.certificate()["statement"],
        "eps_certified": result.eps_certified,
        "eps_star_tight": request.eps_star_tight,
        "eps_star_tight_status": request.eps_star_status,
        "ratio": result.ratio,
        "boxes": search.boxes,
        "max_depth": search.max_depth,
        "seconds": search.seconds,
        "certificate": None if out is None else str(out),
        "params": {
            "sigma": sigma,
            "delta_ratio": delta_ratio,
            "rho_f": rho_f,
            "lipschitz": lipschitz,
        },
        "premise": H3_STATUS,
    }
    if as_json:
        print_json(payload)
        return
    rows = [
        ("target", payload["statement"].split(": ", 1)[-1].split(", with R^")[0]),
        ("certified: every ε ≤", fmt(result.eps_certified, 12)),
        ("tight ε*", f"{fmt(request.eps_star_tight, 12)} ({request.eps_star_status})"),
        ("certified / tight", fmt(result.ratio, 8)),
        ("boxes", str(search.boxes)),
        ("deepest bisection", str(search.max_depth)),
        ("seconds", fmt(search.seconds, 3)),
        ("certificate", "not written (use --out)" if out is None else str(out)),
    ]
    lam = "none" if lipschitz is None else f"{lipschitz:g}"
    print_table(
        f"Interval certificate, {request.target} target (σ = {sigma:g}, δ/ε = "
        f"{delta_ratio:g}, ρ_f = {rho_f:g}, λ = {lam})",
        ("quantity", "value"),
        rows,
    )
    print(f"premise: {H3_STATUS}")


def _check(path: Path, as_json: bool) -> None:
    from ..bounds.certify.certificate import (
        check_certificate,
        library_versions,
        read_certificate,
    )

    payload = read_certificate(path)
    with progress_bar(not as_json) as progress:
        report = check_certificate(payload, progress)
    out = {
        "valid": True,
        "certificate": str(path),
        "target": report.target,
        "eps_certified": report.eps_max,
        "params": {
            "sigma": report.sigma,
            "delta_ratio": report.delta_ratio,
            "rho_f": report.rho_f,
            "lipschitz": report.lipschitz,
        },
        "boxes": report.boxes,
        "leaves": report.leaves,
        "max_depth": report.max_depth,
        "largest_bound": report.largest_bound,
        "seconds": report.seconds,
        "versions": {"certificate": payload.get("versions"), "checker": library_versions()},
    }
    if as_json:
        print_json(out)
        return
    rows = [
        ("valid", "yes: every leaf re-verified, the leaves tile the domain"),
        ("target", report.target),
        ("every ε ≤", fmt(report.eps_max, 12)),
        (
            "σ, δ/ε, ρ_f, λ",
            f"{report.sigma:g}, {report.delta_ratio:g}, {report.rho_f:g}, {report.lipschitz}",
        ),
        ("boxes (leaves)", f"{report.boxes} ({report.leaves})"),
        ("largest bound / target", fmt(report.largest_bound, 10)),
        ("seconds", fmt(report.seconds, 3)),
    ]
    print_table(f"Certificate {path}", ("quantity", "value"), rows)


def _report_failure(failure, as_json: bool, target: str) -> None:
    """Print why certification stopped: the counterexample, or the unresolved box."""
    from ..bounds.certify.interval import DIMENSIONS, nearest_float
    from ..bounds.certify.search import absolute_configuration

    payload: dict = {"certified": False, "reason": str(failure)}
    found = failure.counterexample
    if found is not None:
        eps = found.point[0]
        tri = absolute_configuration(found.point)
        payload["counterexample"] = {
            "eps": eps,
            "b": float(tri.b[0]),
            "c": float(tri.c[0]),
            "theta": float(tri.theta[0]),
            "lfs_j": 1 + float(tri.excess_j[0]),
            "lfs_k": 1 + float(tri.excess_k[0]),
            "excess_j": float(tri.excess_j[0]),
            "excess_k": float(tri.excess_k[0]),
            "ratio_interval": [found.ratio_lower, found.ratio_upper],
            "ratio_float": found.ratio_float,
            "units": "L_i = 1; ratio = "
            + (
                "((R - R^)/R)/(1 - 1/rho_f), above 1 exactly where R > rho_f R^"
                if target == "ratio"
                else "(R - R^)/((rho_f - 1) delta L_i)"
            ),
        }
    if failure.box is not None:
        payload["box"] = [[nearest_float(lo), nearest_float(hi)] for lo, hi in failure.box]
    if as_json:
        if found is not None:  # the exact point that interval arithmetic checked
            payload["counterexample"]["coordinates"] = dict(
                zip(DIMENSIONS, found.point, strict=True)
            )
        print_json(payload)
        return
    print(f"not certified: {failure}")
    if found is not None:
        rows = [
            (k, fmt(v) if isinstance(v, float) else str(v))
            for k, v in payload["counterexample"].items()
        ]
        print_table(
            "Counterexample (feasible, checked in intervals and in floats)",
            ("quantity", "value"),
            rows,
        )
    if failure.box is not None:
        rows = [
            (name, f"[{fmt(lo)}, {fmt(hi)}]")
            for name, (lo, hi) in zip(DIMENSIONS, payload["box"], strict=True)
        ]
        print_table("Unresolved box", ("coordinate", "interval"), rows)
