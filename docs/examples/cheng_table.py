"""docs/cheng.md: Cheng et al.'s constants against the numerical suprema (about 20 s).

The test recomputes the α = 0.3 row only (``quick_check``).
"""

from vorobound.studies.cheng import cheng_constants

ALPHAS = (0.1, 0.2, 0.3, 0.4, 0.45, 0.49)
HEADER = (
    "| α | c_rad = 1/√(1−4α²) | c_conj = 1/√(1−3α²) | 2-D numeric sup | 2-D sup/c_conj − 1 "
    "| 3-D numeric sup | 3-D max at h = 10⁻³ / 10⁻⁶ | regular tetrahedron, full weights |\n"
    "|---|---|---|---|---|---|---|---|\n"
)


def row(alpha: float) -> str:
    tri, tet = cheng_constants(alpha, 2), cheng_constants(alpha, 3)
    floors = tet.evidence.max_by_flatness_floor
    return (
        f"| {alpha} | {tri.c_rad:.12f} | {tri.c_conjectured:.12f} | {tri.numeric_sup:.12f} "
        f"| {tri.numeric_sup / tri.c_conjectured - 1:.1e} | {tet.numeric_sup} "
        f"| {floors['1e-03']:.4g} / {floors['1e-06']:.4g} "
        f"| {tet.evidence.regular_simplex_ratio:.12f} |\n"
    )


def render() -> str:
    return HEADER + "".join(row(alpha) for alpha in ALPHAS)


def quick_check(block: str) -> None:
    assert block.startswith(HEADER)
    assert row(0.3) in block, "docs/cheng.md is stale: run python scripts/update_docs.py"


if __name__ == "__main__":
    print(render(), end="")
