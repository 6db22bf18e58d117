"""Relative errors against the 60-digit mpmath reference, per family of test triangles.

Prints the worst error of ``radius_gap`` (R − R̂, Theorem 1) and of R, and the median error of
``radius_gap_direct`` (the difference of two separately computed radii), for comparison.

Run: ``python scripts/accuracy_report.py`` (needs the ``test`` extra for mpmath). The families
and the reference are the test suite's own (``tests/hard_triangles.py``,
``tests/mp_reference.py``); this prints the numbers that the tests only bound.
"""

from __future__ import annotations

import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests"))
sys.path.insert(0, os.path.join(HERE, ".."))

from hard_triangles import families  # noqa: E402
from mp_reference import reference, relative_error  # noqa: E402

from vorobound import weighted_triangles  # noqa: E402


def main() -> None:
    print(
        f"{'family':28s} {'rows':>5s} {'max error R−R̂':>16s} {'max error R':>12s} "
        f"{'median error two-radii':>26s}"
    )
    for name, (points, weights) in families().items():
        result = weighted_triangles(points, weights)
        delta, radius, direct = [], [], []
        for i in range(len(points)):
            ref = reference(points[i], weights[i])
            delta.append(relative_error(result.radius_gap[i], ref["delta"]))
            radius.append(relative_error(result.circumradius[i], ref["circumradius"]))
            direct.append(relative_error(result.radius_gap_direct[i], ref["delta"]))
        print(
            f"{name:28s} {len(points):5d} {max(delta):16.2e} {max(radius):12.2e} "
            f"{float(np.median(direct)):26.2e}"
        )


if __name__ == "__main__":
    main()
