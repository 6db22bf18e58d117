"""Ball files read in chunks give the balls read_balls gives, and the same refusals."""

import zipfile

import numpy as np
import pytest

from vorobound.errors import InputError, ReadError
from vorobound.sampling.io import balls as balls_io
from vorobound.sampling.io import stream
from vorobound.sampling.io.balls import read_ball_arrays
from vorobound.sampling.io.stream import ball_chunks

ROWS = 2500


def _balls(seed=0):
    rng = np.random.default_rng(seed)
    return rng.normal(size=(ROWS, 3)) * 1e3, 10.0 ** rng.uniform(-3, 3, ROWS)


def _joined(path, chunk_rows=700):
    parts = list(ball_chunks(path, chunk_rows))
    assert all(len(r) <= chunk_rows for _, r in parts)
    return np.concatenate([c for c, _ in parts]), np.concatenate([r for _, r in parts])


def _write_csv(path, centers, radii, header="x,y,z,r"):
    table = np.column_stack([centers, radii])
    np.savetxt(path, table, delimiter=",", fmt="%.17g", header=header, comments="")


@pytest.fixture(params=["pyarrow", "numpy"])
def csv_reader(request, monkeypatch):
    if request.param == "pyarrow":
        pytest.importorskip("pyarrow")
    else:
        monkeypatch.setattr(stream, "pyarrow_available", lambda: False)
    return request.param


@pytest.mark.parametrize("header", ["x,y,z,r", "r,z,y,x", "", "X, Y, Z, radius"])
def test_csv_chunks_equal_the_whole_file(tmp_path, csv_reader, header):
    centers, radii = _balls()
    path = tmp_path / "b.csv"
    if header == "r,z,y,x":
        np.savetxt(
            path,
            np.column_stack([radii, centers[:, ::-1]]),
            delimiter=",",
            fmt="%.17g",
            header=header,
            comments="",
        )
    else:
        _write_csv(path, centers, radii, header)
    got = _joined(path)
    want = read_ball_arrays(path)
    assert np.array_equal(got[0], want[0]) and np.array_equal(got[1], want[1])
    assert np.array_equal(got[1], radii)


def test_npz_layouts_and_parquet(tmp_path):
    centers, radii = _balls(1)
    columns = tmp_path / "cols.npz"
    np.savez_compressed(columns, x=centers[:, 0], y=centers[:, 1], z=centers[:, 2], r=radii)
    points = tmp_path / "points.npz"
    np.savez(points, points=centers.astype(np.float32), radii=radii)
    for path in (columns, points):
        got, want = _joined(path), read_ball_arrays(path)
        assert np.array_equal(got[0], want[0]) and np.array_equal(got[1], want[1])
    pa = pytest.importorskip("pyarrow")
    import pyarrow.parquet as pq

    parquet = tmp_path / "b.parquet"
    table = pa.table({"X": centers[:, 0], "y": centers[:, 1], "z": centers[:, 2], "r": radii})
    pq.write_table(table, parquet, row_group_size=900)
    got = _joined(parquet)
    assert np.array_equal(got[0], centers) and np.array_equal(got[1], radii)


def test_a_bad_row_is_named_by_its_row_in_the_file(tmp_path, csv_reader):
    centers, radii = _balls()
    radii[2222] = -1.0
    path = tmp_path / "b.csv"
    _write_csv(path, centers, radii)
    with pytest.raises(InputError, match=r"ball 2222 \(0-based\): the radius is -1.0"):
        _joined(path)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("", "is empty"),
        ("a,b,c,d\n1,2,3,4\n", "header must name x, y, z and r"),
        ("x,y,z,r\n1,2,3,4\n1,2,three,4\n", "line 3: .three. is not a number"),
        ("1,2,3\n4,5,6\n", "need 4 columns"),
    ],
)
def test_csv_refusals(tmp_path, csv_reader, text, message):
    path = tmp_path / "b.csv"
    path.write_text(text)
    with pytest.raises(ReadError, match=message):
        _joined(path)


def test_npz_refusals(tmp_path):
    path = tmp_path / "f.npz"
    fortran = np.asfortranarray(np.arange(15.0).reshape(5, 3) + 1)
    np.savez(path, points=fortran, radii=np.ones(5))
    assert np.array_equal(_joined(path)[0], fortran)  # read column after column
    np.savez(path, x=np.ones(5), y=np.ones(4), z=np.ones(5), r=np.ones(5))
    with pytest.raises(ReadError, match="different lengths"):
        _joined(path)
    np.savez(path, points=np.array(["a"] * 5), radii=np.ones(5))
    with pytest.raises(ReadError, match="not real numbers"):
        _joined(path)
    (tmp_path / "z.npz").write_bytes(b"not a zip")
    with pytest.raises(ReadError, match="not an NPZ archive"):
        _joined(tmp_path / "z.npz")
    with zipfile.ZipFile(tmp_path / "e.npz", "w"):
        pass
    with pytest.raises(ReadError, match="need arrays"):
        _joined(tmp_path / "e.npz")


def test_parquet_refusals(tmp_path, monkeypatch):
    path = tmp_path / "b.parquet"
    path.write_bytes(b"PAR1 not really")
    monkeypatch.setattr(balls_io, "pyarrow_available", lambda: False)
    with pytest.raises(ReadError, match="need pyarrow"):
        _joined(path)
    monkeypatch.undo()
    pa = pytest.importorskip("pyarrow")
    with pytest.raises(ReadError, match="cannot read balls"):
        _joined(path)
    import pyarrow.parquet as pq

    pq.write_table(pa.table({"x": [1.0], "y": [2.0], "z": [3.0]}), path)
    with pytest.raises(ReadError, match="need columns x, y, z and r"):
        _joined(path)


@pytest.mark.parametrize("kind", ["timestamp", "bool"])
def test_parquet_columns_that_are_not_numbers_are_refused_whole_and_streamed(tmp_path, kind):
    """A timestamp column was an internal error (exit 70) and a boolean one was read as 0/1
    by read_balls; both are refused, as the streamed reader and NPZ files refuse them."""
    pa = pytest.importorskip("pyarrow")
    import pyarrow.parquet as pq

    x = pa.array(np.arange(5).astype("datetime64[s]")) if kind == "timestamp" else [True] * 5
    path = tmp_path / "b.parquet"
    pq.write_table(pa.table({"x": x, "y": [1.0] * 5, "z": [2.0] * 5, "r": [1.0] * 5}), path)
    with pytest.raises(ReadError, match="not real numbers"):
        read_ball_arrays(path)
    with pytest.raises(ReadError, match="not a table of numbers"):
        _joined(path)


@pytest.mark.parametrize(
    "delimiter, header",
    [(";", "x;y;z;r"), ("\t", "x\ty\tz\tr"), (" ", ""), (",", "# my balls\n\nx,y,z,r")],
    ids=["semicolons", "tabs", "spaces", "leading-comment"],
)
def test_every_csv_read_balls_reads_streams_the_same(tmp_path, csv_reader, delimiter, header):
    """The tiled check (--workers) refused semicolon, tab and space separated files and a
    leading comment line, all of which the whole-file check reads."""
    centers, radii = _balls()
    path = tmp_path / "b.csv"
    table = np.column_stack([centers, radii])
    np.savetxt(path, table, delimiter=delimiter, fmt="%.17g", header=header, comments="")
    got = _joined(path)
    want = read_ball_arrays(path)
    assert np.array_equal(got[0], want[0]) and np.array_equal(got[1], want[1])
