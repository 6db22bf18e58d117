"""``vorobound triangle``: centers, radii and Theorem 1 for one weighted triangle."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from ..errors import InputError
from .arguments import checked_arguments
from .result import Result, as_float

OVERFLOW = (
    "the triangle is fine, but with these weights the orthoball (or the weight differences) "
    "overflows float64: no finite result"
)
DEPRECATED_KEYS = {
    "delta": "radius_gap",
    "delta_direct": "radius_gap_direct",
    "delta_unshifted": "radius_gap_unshifted",
}
"""JSON keys of earlier versions, still written for one release (CHANGELOG)."""


@dataclass(frozen=True, repr=False)
class TriangleResult(Result):
    """One weighted triangle: circumradius, signed orthoradius and R − R̂ (Theorem 1)."""

    command = "triangle"
    circumradius: float
    """R, eq. (3), (15)."""
    orthoradius_sq: float
    """Signed R̂² for the weights as given, eq. (2)."""
    shifted_orthoradius: float
    """R̂ after subtracting the minimum weight, eq. (5)–(6)."""
    radius_gap: float
    """R − R̂ of Theorem 1, eq. (29)."""
    radius_gap_direct: float | None
    """The difference of the two radii from the two centers (points only; a check)."""
    radius_gap_unshifted: float | None
    """R − sqrt(orthoradius_sq) for the weights as given (None where R̂² < 0)."""
    paper_literal: float
    """Eq. (32) as printed (docs/errata.md E1)."""
    k: float
    """Eq. (31)."""
    edges: tuple[float, float, float]
    """a = |BC|, b = |CA|, c = |AB| (eq. (7)–(9))."""
    sin_theta: float
    min_weight_vertex: int
    """0, 1, 2 for A, B, C: the vertex whose weight is subtracted (eq. (6))."""
    assumption1_holds: bool
    circumcenter: tuple[float, ...] | None = None
    orthocenter: tuple[float, ...] | None = None
    weights: tuple[float, float, float] = (0.0, 0.0, 0.0)
    points: tuple[tuple[float, ...], ...] | None = None

    def payload(self) -> dict:
        out = {
            "params": {
                "points": self.points,
                "edges": None if self.points else self.edges,
                "weights": self.weights,
            },
            "circumradius": self.circumradius,
            "orthoradius_sq": self.orthoradius_sq,
            "shifted_orthoradius": self.shifted_orthoradius,
            "radius_gap": self.radius_gap,
            "radius_gap_direct": self.radius_gap_direct,
            "radius_gap_unshifted": self.radius_gap_unshifted,
            "paper_literal": self.paper_literal,
            "k": self.k,
            "edges": self.edges,
            "sin_theta": self.sin_theta,
            "min_weight_vertex": self.min_weight_vertex,
            "assumption1_holds": self.assumption1_holds,
        }
        if self.circumcenter is not None:
            out["circumcenter"] = self.circumcenter
            out["orthocenter"] = self.orthocenter
        for old, new in DEPRECATED_KEYS.items():
            out[old] = out[new]
        out["deprecated_keys"] = DEPRECATED_KEYS
        return out


def _check_edges(edges: list[float]) -> None:
    if min(edges) <= 0:
        raise InputError(f"edge lengths must be positive, got {edges}")
    a, b, c = sorted(edges)
    if c >= a + b:
        raise InputError(f"edges {edges} violate the triangle inequality (degenerate triangle)")


def _finite_numbers(values, what: str, counts: tuple[int, ...]) -> list[float]:
    import math
    import numbers

    values = list(values)
    if len(values) not in counts:
        want = " or ".join(map(str, counts))
        raise InputError(f"{what} needs {want} numbers, got {len(values)}")
    out = []
    for value in values:
        if isinstance(value, bool) or not isinstance(value, numbers.Real):
            raise InputError(f"{what}: {value!r} is not a number")
        if not math.isfinite(float(value)):
            raise InputError(f"{what}: {value!r} is not a finite number")
        out.append(float(value))
    return out


@checked_arguments
def triangle(
    *,
    points: Sequence[Sequence[float]] | None = None,
    edges: Sequence[float] | None = None,
    weights: Sequence[float] = (0.0, 0.0, 0.0),
) -> TriangleResult:
    """Circumradius, signed orthoradius and Theorem 1's R − R̂ for one weighted triangle.

    Parameters
    ----------
    points : three points (x, y) or (x, y, z), optional
        The vertices A, B, C.
    edges : (a, b, c), optional
        Edge lengths instead of points: a = |BC|, b = |CA|, c = |AB|.
    weights : (w_A, w_B, w_C)
        Squared ball radii (may be negative).

    References
    ----------
    Eq. (2)–(6), (15), (29)–(32); Theorem 1.
    """
    from ..geometry import theorem1_from_edges, weighted_triangles

    w = _finite_numbers(weights, "weights", (3,))
    if (points is None) == (edges is None):
        raise InputError("give either three points or the three edge lengths")
    coords = None
    if points is not None:
        points = list(points)
        if len(points) != 3:
            raise InputError(f"a triangle needs exactly three points, got {len(points)}")
        coords = [_finite_numbers(p, "a point", (2, 3)) for p in points]
        if len({len(c) for c in coords}) != 1:
            raise InputError("all three points must have the same dimension (2 or 3)")
        result = weighted_triangles(coords, w)
        if not bool(result.valid):
            if not bool(weighted_triangles(coords, [0.0, 0.0, 0.0]).valid):
                raise InputError("the points are collinear or coincident (no circumcircle)")
            raise InputError(OVERFLOW)
    else:
        lengths = _finite_numbers(edges, "edges", (3,))
        _check_edges(lengths)
        result = theorem1_from_edges(lengths, w)
        if not bool(result.valid):
            if not bool(theorem1_from_edges(lengths, [0.0, 0.0, 0.0]).valid):
                raise InputError(f"edges {lengths} do not form a non-degenerate triangle")
            raise InputError(OVERFLOW)
    direct = result.radius_gap_direct
    return TriangleResult(
        circumradius=float(result.circumradius),
        orthoradius_sq=float(result.orthoradius_sq),
        shifted_orthoradius=float(result.shifted_orthoradius),
        radius_gap=float(result.radius_gap),
        radius_gap_direct=None if direct is None else as_float(direct),
        radius_gap_unshifted=as_float(result.radius_gap_unshifted),
        paper_literal=float(result.paper_literal),
        k=float(result.k),
        edges=_triple(result.edges),
        sin_theta=float(result.sin_theta),
        min_weight_vertex=int(result.min_weight_vertex),
        assumption1_holds=bool(result.assumption1_holds),
        circumcenter=None
        if result.circumcenter is None
        else tuple(float(x) for x in result.circumcenter),
        orthocenter=None
        if result.orthocenter is None
        else tuple(float(x) for x in result.orthocenter),
        weights=_triple(w),
        points=None if coords is None else tuple(tuple(c) for c in coords),
    )


def _triple(values) -> tuple[float, float, float]:
    """Three numbers as a tuple of plain floats."""
    a, b, c = (float(x) for x in values)
    return a, b, c
