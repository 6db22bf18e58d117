"""Balls far from the origin (CAD parts in millimetres, site coordinates) give the same guide
triangles as at the origin (issue 34): every engine of ``check`` and the whole check, shifted
by 1e3 … 1e9."""

import numpy as np
import pytest

from vorobound.sampling.balls import Balls
from vorobound.sampling.guides.triangles import (
    find_guide_triangles,
    geogram_available,
    gudhi_available,
)

SHIFTS = [1e3, 1e5, 1e7, 1e9]


@pytest.fixture(scope="module")
def torus_balls(tmp_path_factory):
    import vorobound

    path = tmp_path_factory.mktemp("far") / "torus.npz"
    vorobound.sample(eps=0.25, torus=(3.0, 1.0), output=path)
    with np.load(path) as data:
        return Balls(np.column_stack([data["x"], data["y"], data["z"]]), data["radius"])


def _guides(balls, engine):
    return {tuple(row) for row in find_guide_triangles(balls, engine).guide.triples}


@pytest.mark.slow
@pytest.mark.parametrize("engine", ["geogram", "gudhi", "brute"])
def test_shifted_balls_have_the_same_guide_triangles(torus_balls, engine):
    if engine == "gudhi" and not gudhi_available():
        pytest.skip("gudhi is not installed")
    if engine == "geogram" and not geogram_available():
        pytest.skip("the compiled module was not built")
    reference = _guides(torus_balls, engine)
    assert len(reference) > 1000
    direction = np.array([1.0, -0.6, 0.3])
    for shift in SHIFTS:
        moved = Balls(torus_balls.centers + shift * direction, torus_balls.radii)
        assert _guides(moved, engine) == reference, shift


@pytest.mark.slow
def test_check_of_shifted_balls_gives_the_same_combinatorics(torus_balls, tmp_path, run_cli):
    import json

    found = []
    for shift in [0.0, *SHIFTS]:
        path = tmp_path / f"b{shift:g}.npz"
        x, y, z = (torus_balls.centers + shift).T
        np.savez(path, x=x, y=y, z=z, r=torus_balls.radii)
        code, out, err = run_cli("check", "--balls", str(path), "--eps", "0.25", "--json")
        payload = json.loads(out)
        found.append(
            (
                code,
                payload["ok"],
                payload["n_guide_triangles"],
                payload["n_half_covered"],
                payload["failures"],
            )
        )
    assert all(f == found[0] for f in found), found
