"""Reading external balls (CSV, NPZ, meshio point sets) and writing samples."""

import meshio
import numpy as np
import pytest

from vorobound.errors import InputError, ReadError
from vorobound.sampling.balls import make_balls
from vorobound.sampling.io.balls import read_balls, write_balls

RNG = np.random.default_rng(0)
CENTERS = RNG.random((12, 3))
RADII = 0.1 + 0.1 * RNG.random(12)


def _csv(path, header=True, rows=None):
    rows = np.column_stack([CENTERS, RADII]) if rows is None else rows
    text = ("x,y,z,r\n" if header else "") + "\n".join(
        ",".join(repr(float(v)) for v in r) for r in rows
    )
    path.write_text(text)
    return path


@pytest.mark.parametrize("header", [True, False])
def test_csv(tmp_path, header):
    balls = read_balls(_csv(tmp_path / "b.csv", header))
    assert np.array_equal(balls.centers, CENTERS) and np.array_equal(balls.radii, RADII)


def test_csv_columns_in_any_order_and_radius_name(tmp_path):
    path = tmp_path / "b.csv"
    rows = np.column_stack([RADII, CENTERS[:, 2], CENTERS[:, 0], CENTERS[:, 1]])
    path.write_text("radius,z,x,y\n" + "\n".join(",".join(repr(float(v)) for v in r) for r in rows))
    balls = read_balls(path)
    assert np.array_equal(balls.centers, CENTERS) and np.array_equal(balls.radii, RADII)


@pytest.mark.parametrize("suffix", [".npz", ".vtu", ".csv"])
def test_written_samples_read_back(tmp_path, suffix):
    path = write_balls(tmp_path / f"s{suffix}", make_balls(CENTERS, RADII), {"lfs": RADII / 2})
    balls = read_balls(path)
    assert np.array_equal(balls.centers, CENTERS) and np.array_equal(balls.radii, RADII)


def test_npz_with_points_and_radii(tmp_path):
    path = tmp_path / "b.npz"
    np.savez(path, points=CENTERS, radii=RADII)
    assert np.array_equal(read_balls(path).radii, RADII)


def test_meshio_point_cloud_with_radius(tmp_path):
    path = tmp_path / "b.vtk"
    cells = [("vertex", np.arange(12).reshape(-1, 1))]
    meshio.write(path, meshio.Mesh(CENTERS, cells, point_data={"radius": RADII}))
    assert np.allclose(read_balls(path).radii, RADII)


@pytest.mark.parametrize(
    "rows, match",
    [
        # file lines count the header: ball i is on line i + 2
        (
            np.column_stack([CENTERS, np.where(np.arange(12) == 3, np.nan, RADII)]),
            "line 5: the radius",
        ),
        (
            np.column_stack([CENTERS, np.where(np.arange(12) == 5, -0.1, RADII)]),
            "line 7: the radius",
        ),
        (
            np.column_stack([np.where(np.arange(12)[:, None] == 2, np.inf, CENTERS), RADII]),
            "line 4: the center",
        ),
        (
            np.column_stack([np.vstack([CENTERS[:11], CENTERS[4]]), RADII]),
            "lines 6 and 13: the centers coincide",
        ),
        (np.column_stack([CENTERS[:3], RADII[:3]]), "at least 4"),
    ],
    ids=["nan", "negative", "infinite", "duplicate", "too-few"],
)
def test_bad_values_are_refused(tmp_path, rows, match):
    with pytest.raises(InputError, match=match):
        read_balls(_csv(tmp_path / "b.csv", rows=rows))


def test_not_a_point_set(tmp_path):
    path = tmp_path / "notes.txt"
    path.write_text("hello, this is not a mesh\n")
    with pytest.raises(ReadError):
        read_balls(path)
    (tmp_path / "b.csv").write_text("a,b,c\n1,2,3\n")
    with pytest.raises(ReadError, match="header"):
        read_balls(tmp_path / "b.csv")
    with pytest.raises(ReadError, match="no such file"):
        read_balls(tmp_path / "missing.csv")


def test_point_set_without_radius(tmp_path):
    path = tmp_path / "b.vtu"
    meshio.write(path, meshio.Mesh(CENTERS, [("vertex", np.arange(12).reshape(-1, 1))]))
    with pytest.raises(ReadError, match="radius"):
        read_balls(path)


def test_bad_output_name(tmp_path):
    with pytest.raises(InputError, match=r"\.npz, \.vtu or \.csv"):
        write_balls(tmp_path / "s.txt", make_balls(CENTERS, RADII), {})
    assert not list(tmp_path.iterdir())
