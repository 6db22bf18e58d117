"""``vorobound triangle``: centers, radii and Theorem 1 for one weighted triangle."""

from __future__ import annotations

from typing import Annotated

import typer

from ..errors import InputError
from .options import parse_numbers
from .render import fmt, print_json, print_table

OVERFLOW = (
    "the triangle is fine, but with these weights the orthoball (or the weight differences) "
    "overflows float64: no finite result"
)


def _check_edges(edges: list[float]) -> None:
    if min(edges) <= 0:
        raise InputError(f"edge lengths must be positive, got {edges}")
    a, b, c = sorted(edges)
    if c >= a + b:
        raise InputError(f"edges {edges} violate the triangle inequality (degenerate triangle)")


def triangle(
    point: Annotated[
        list[str] | None,
        typer.Option(
            "--point",
            "-p",
            metavar="X,Y[,Z]",
            help="A vertex as x,y or x,y,z; give it three times (A, B, C).",
        ),
    ] = None,
    edges: Annotated[
        str | None,
        typer.Option(
            "--edges",
            metavar="A,B,C",
            help="Edge lengths a,b,c with a = |BC|, b = |CA|, c = |AB| (instead of points).",
        ),
    ] = None,
    weights: Annotated[
        str,
        typer.Option(
            "--weights",
            "-w",
            metavar="WA,WB,WC",
            help="Weights wA,wB,wC: squared ball radii, may be negative.",
        ),
    ] = "0,0,0",
    as_json: Annotated[bool, typer.Option("--json", help="Print one JSON object.")] = False,
) -> None:
    """Circumradius, signed orthoradius and Theorem 1's R − R̂ for one weighted triangle.

    delta is R − R̂ after subtracting the minimum weight from all three (eq. (5)–(6), (29));
    paper_literal is eq. (32) as printed, kept for comparison (see docs/errata.md).
    """
    from ..geometry import theorem1_from_edges, weighted_triangles

    w = parse_numbers(weights, "--weights", 3)
    if (point is None) == (edges is None):
        raise InputError("give either three --point/-p options or --edges a,b,c")
    if point is not None:
        if len(point) != 3:
            raise InputError(f"a triangle needs exactly three --point/-p, got {len(point)}")
        coords = [parse_numbers(p, "--point", (2, 3)) for p in point]
        if len({len(c) for c in coords}) != 1:
            raise InputError("all three points must have the same dimension (2 or 3)")
        result = weighted_triangles(coords, w)
        if not bool(result.valid):
            if not bool(weighted_triangles(coords, [0.0, 0.0, 0.0]).valid):
                raise InputError("the points are collinear or coincident (no circumcircle)")
            raise InputError(OVERFLOW)
    else:
        lengths = parse_numbers(edges, "--edges", 3)
        _check_edges(lengths)
        result = theorem1_from_edges(lengths, w)
        if not bool(result.valid):
            if not bool(theorem1_from_edges(lengths, [0.0, 0.0, 0.0]).valid):
                raise InputError(f"edges {lengths} do not form a non-degenerate triangle")
            raise InputError(OVERFLOW)

    payload = {
        "circumradius": float(result.circumradius),
        "orthoradius_sq": float(result.orthoradius_sq),
        "shifted_orthoradius": float(result.shifted_orthoradius),
        "radius_gap": float(result.radius_gap),
        "delta": float(result.radius_gap),
        "delta_direct": None
        if result.radius_gap_direct is None
        else float(result.radius_gap_direct),
        "delta_unshifted": float(result.radius_gap_unshifted),
        "paper_literal": float(result.paper_literal),
        "k": float(result.k),
        "edges": result.edges,
        "sin_theta": float(result.sin_theta),
        "min_weight_vertex": int(result.min_weight_vertex),
        "assumption1_holds": bool(result.assumption1_holds),
    }
    if result.circumcenter is not None:
        payload["circumcenter"] = result.circumcenter
        payload["orthocenter"] = result.orthocenter
    if as_json:
        print_json(payload)
        return
    rows = [
        ("circumradius R", fmt(payload["circumradius"]), "eq. (3), (15)"),
        ("orthoradius_sq (signed)", fmt(payload["orthoradius_sq"]), "eq. (2)"),
        ("shifted orthoradius R̂", fmt(payload["shifted_orthoradius"]), "eq. (5)–(6)"),
        ("R − R̂ (Theorem 1)", fmt(payload["radius_gap"], 15), "eq. (29)"),
        ("R − R̂ from two centers", fmt(payload["delta_direct"], 15), "check"),
        ("R − sqrt(orthoradius_sq)", fmt(payload["delta_unshifted"], 15), "given weights"),
        ("paper_literal", fmt(payload["paper_literal"], 15), "eq. (32) as printed"),
        ("k", fmt(payload["k"]), "eq. (31)"),
        ("edges a, b, c", ", ".join(fmt(x) for x in payload["edges"].tolist()), "eq. (7)–(9)"),
        ("min-weight vertex (A)", "ABC"[payload["min_weight_vertex"]], "eq. (6)"),
        ("assumption (1) holds", str(payload["assumption1_holds"]), "eq. (1)"),
    ]
    if "circumcenter" in payload:
        rows.append(("circumcenter", ", ".join(fmt(x) for x in payload["circumcenter"]), ""))
        rows.append(("orthocenter", ", ".join(fmt(x) for x in payload["orthocenter"]), ""))
    print_table("Weighted triangle", ("quantity", "value", "reference"), rows)
