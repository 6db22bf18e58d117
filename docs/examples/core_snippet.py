"""The README's code snippet, and what it prints."""

import contextlib
import io

SNIPPET = """\
import numpy as np
from vorobound import theorem1_from_edges, weighted_triangles

rng = np.random.default_rng(0)
points = rng.standard_normal((100_000, 3, 3))  # (..., 3, d) with d = 2 or 3
weights = np.tile([0.0, 0.01, 0.02], (100_000, 1))  # squared ball radii w = r²
tri = weighted_triangles(points, weights)
print(f"{tri.radius_gap[0]:.12g}")  # R − R̂ of the min-weight-shifted triangle, eq. (29)
print(f"{tri.orthoradius_sq[0]:.12g}")  # signed |p − ẑ|² − w, eq. (2)
print(tri.valid.sum(), "of", len(tri.valid), "rows valid")  # bad rows: NaN and valid False
edges = theorem1_from_edges([5.0, 4.0, 3.0], [0.0, 0.2, 0.5])  # a = |BC|, b = |CA|, c = |AB|
print(f"{edges.radius_gap:.12g}")  # Theorem 1 from edge lengths and weights alone
"""


def render() -> str:
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(SNIPPET, "core_snippet", "exec"), {})
    return f"```python\n{SNIPPET}```\n\nprints\n\n```\n{out.getvalue()}```\n"


if __name__ == "__main__":
    print(render(), end="")
