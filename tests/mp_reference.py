"""High-precision reference for weighted-triangle geometry (mpmath, 60 digits)."""

from __future__ import annotations

import mpmath as mp

DIGITS = 60


def reference(points, weights) -> dict[str, mp.mpf]:
    """R, the shifted orthoradius, their difference and the signed squared orthoradius.

    Solves the center equations (2)–(3) directly in the triangle's plane at 60 digits, an
    algorithm independent of the library's vertex-free formulas.
    """
    with mp.workdps(DIGITS):
        p = [[mp.mpf(float(x)) for x in row] for row in points]
        w = [mp.mpf(float(x)) for x in weights]
        i_min = min(range(3), key=lambda i: w[i])
        w_min = w[i_min]
        a = p[i_min]
        others = [j for j in range(3) if j != i_min]
        vecs = [[p[j][t] - a[t] for t in range(len(a))] for j in others]
        dot = lambda x, y: mp.fsum(xi * yi for xi, yi in zip(x, y, strict=True))  # noqa: E731
        g = [[dot(vecs[r], vecs[s]) for s in range(2)] for r in range(2)]
        det = g[0][0] * g[1][1] - g[0][1] * g[0][1]

        def center(rhs):
            al = (g[1][1] * rhs[0] - g[0][1] * rhs[1]) / det
            be = (g[0][0] * rhs[1] - g[0][1] * rhs[0]) / det
            return [al * vecs[0][t] + be * vecs[1][t] for t in range(len(a))]

        x = center([g[0][0] / 2, g[1][1] / 2])
        xhat = center(
            [(g[0][0] - (w[others[0]] - w_min)) / 2, (g[1][1] - (w[others[1]] - w_min)) / 2]
        )
        radius = mp.sqrt(dot(x, x))
        shifted = mp.sqrt(dot(xhat, xhat))
        return {
            "circumradius": radius,
            "shifted_orthoradius": shifted,
            "delta": radius - shifted,
            "orthoradius_sq": dot(xhat, xhat) - w_min,
        }


def relative_error(value: float, ref: mp.mpf) -> float:
    with mp.workdps(DIGITS):
        return float(abs(mp.mpf(float(value)) - ref) / abs(ref))
