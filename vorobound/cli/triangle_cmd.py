"""``vorobound triangle``: centers, radii and Theorem 1 for one weighted triangle."""

from __future__ import annotations

from typing import Annotated

import typer

from ..errors import InputError
from .options import Json, parse_numbers
from .render import emit, fmt, print_table


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
    as_json: Json = False,
) -> int:
    """Circumradius, signed orthoradius and Theorem 1's R − R̂ for one weighted triangle.

    radius_gap is R − R̂ after subtracting the minimum weight from all three (eq. (5)–(6),
    (29)); paper_literal is eq. (32) as printed, kept for comparison (see docs/errata.md).
    Python: vorobound.triangle(points=..., weights=...).
    """
    from ..api.triangle import triangle as run

    w = parse_numbers(weights, "--weights", 3)
    if (point is None) == (edges is None):
        raise InputError("give either three --point/-p options or --edges a,b,c")
    if point is not None:
        if len(point) != 3:
            raise InputError(f"a triangle needs exactly three --point/-p, got {len(point)}")
        result = run(points=[parse_numbers(p, "--point", (2, 3)) for p in point], weights=w)
    else:
        result = run(edges=parse_numbers(str(edges), "--edges", 3), weights=w)
    return emit(result, as_json, _show)


def _show(result) -> None:
    rows = [
        ("circumradius R", fmt(result.circumradius), "eq. (3), (15)"),
        ("orthoradius_sq (signed)", fmt(result.orthoradius_sq), "eq. (2)"),
        ("shifted orthoradius R̂", fmt(result.shifted_orthoradius), "eq. (5)–(6)"),
        ("R − R̂ (Theorem 1)", fmt(result.radius_gap, 15), "eq. (29)"),
        ("R − R̂ from two centers", fmt(result.radius_gap_direct, 15), "check"),
        ("R − sqrt(orthoradius_sq)", fmt(result.radius_gap_unshifted, 15), "given weights"),
        ("paper_literal", fmt(result.paper_literal, 15), "eq. (32) as printed"),
        ("k", fmt(result.k), "eq. (31)"),
        ("edges a, b, c", ", ".join(fmt(x) for x in result.edges), "eq. (7)–(9)"),
        ("min-weight vertex (A)", "ABC"[result.min_weight_vertex], "eq. (6)"),
        ("assumption (1) holds", str(result.assumption1_holds), "eq. (1)"),
    ]
    if result.circumcenter is not None:
        rows.append(("circumcenter", ", ".join(fmt(x) for x in result.circumcenter), ""))
        rows.append(("orthocenter", ", ".join(fmt(x) for x in result.orthocenter), ""))
    print_table("Weighted triangle", ("quantity", "value", "reference"), rows)
