"""One set of rules for every ball reader (issue 34): the whole-file reader (``check --balls``)
and the streamed one (``check --balls --workers N``) accept and refuse the same hostile corpus,
with the same balls or the same error.

Before, they disagreed on quoted cells, trailing commas, ``#`` lines mid-file and 2-D NPZ
arrays; an NPZ whose ``.npy`` headers lie about the row count gave different ball sets; and
pyarrow guessed int64 from a first block of integers ("0"), then refused the file.
"""

import io
import json
import zipfile

import numpy as np
import pytest

from vorobound.errors import VoroboundError
from vorobound.sampling.balls import checked_rows
from vorobound.sampling.io import stream
from vorobound.sampling.io.balls import read_ball_arrays
from vorobound.sampling.io.stream import ball_chunks

ROWS = "0.5,0.25,1,0.5\n1.5,0.25,1,0.5\n0.5,1.25,1,0.5\n0.5,0.25,2,0.5\n"

CSV = {
    "plain": ROWS,
    "header": "x,y,z,r\n" + ROWS,
    "quoted header": '"x","y","z","r"\n' + ROWS,
    "radius header, other order": "radius,z,y,x\n0.5,1,0.25,0.5\n0.5,1,0.25,1.5\n0.5,1,1,1\n",
    "integers first": "0,0,0,1\n0,0,1,1\n" + ROWS * 30,
    "quoted cells": '"0.5",0.25,1,0.5\n' + ROWS,
    "quoted cell later": ROWS * 20 + '1,"2",3,4\n',
    "trailing commas": ROWS.replace("\n", ",\n"),
    "trailing comma on one row": ROWS * 20 + "1,2,3,4,\n",
    "extra columns": ROWS.replace("\n", ",7\n"),
    "extra header column": "x,y,z,r,id\n" + ROWS.replace("\n", ",7\n"),
    "header wider than rows": "x,y,z,r,id\n" + ROWS,
    "a short row": ROWS + "1,2,3\n" + ROWS,
    "a long row later": ROWS * 20 + "1,2,3,4,5\n" + ROWS,
    "blank lines mid-file": ROWS + "\n\n" + ROWS,
    "whitespace line mid-file": ROWS + "   \n" + ROWS,
    "comment mid-file": ROWS * 20 + "# a comment\n" + ROWS,
    "comment first": "# made by hand\nx,y,z,r\n" + ROWS,
    "crlf": ROWS.replace("\n", "\r\n"),
    "semicolons, decimal commas": ROWS.replace(",", ";").replace(".", ","),
    "semicolons": ROWS.replace(",", ";"),
    "tabs": ROWS.replace(",", "\t"),
    "spaces": ROWS.replace(",", "  "),
    "empty cell": ROWS + "1,,3,4\n",
    "text cell": ROWS * 20 + "1,two,3,4\n",
    "nan": ROWS + "nan,1,1,1\n",
    "zero radius": ROWS + "3,3,3,0\n",
    "header only": "x,y,z,r\n",
    "three columns": "1,2,3\n4,5,6\n",
    "bad header": "a,b,c,d\n" + ROWS,
    "empty": "",
    "bom": "\ufeffx,y,z,r\n" + ROWS,
}


def _npy(array: np.ndarray, shape=None) -> bytes:
    """The bytes of a .npy file of ``array``, its header saying ``shape`` (a lie if given)."""
    handle = io.BytesIO()
    fortran = bool(array.flags.f_contiguous and not array.flags.c_contiguous)
    header = {"descr": np.lib.format.dtype_to_descr(array.dtype), "fortran_order": fortran}
    header["shape"] = array.shape if shape is None else shape
    np.lib.format.write_array_header_1_0(handle, header)
    return handle.getvalue() + array.tobytes(order="F" if fortran else "C")


def _npz(path, compress=False, **arrays) -> None:
    method = zipfile.ZIP_DEFLATED if compress else zipfile.ZIP_STORED
    with zipfile.ZipFile(path, "w", method) as archive:
        for name, value in arrays.items():
            data = _npy(*value) if isinstance(value, tuple) else _npy(np.asarray(value))
            archive.writestr(f"{name}.npy", data)


GRID = (
    np.array([[0.5, 0.25, 1], [1.5, 0.25, 1], [0.5, 1.25, 1], [0.5, 0.25, 2]] * 5)
    + np.repeat(np.arange(5), 4)[:, None] * 3
)
X, Y, Z = GRID.T
R = np.full(len(GRID), 0.5)
N = len(R)

NPZ = {
    "columns": {"x": X, "y": Y, "z": Z, "r": R},
    "columns compressed": ({"x": X, "y": Y, "z": Z, "radius": R}, True),
    "points": {"points": GRID, "radii": R},
    "points in Fortran order": {"points": np.asfortranarray(GRID), "radii": R},
    "integer columns": {"x": X.astype(int), "y": Y.astype(int), "z": Z.astype(int), "r": R},
    "2-D columns": {
        "x": X.reshape(-1, 2),
        "y": Y.reshape(-1, 2),
        "z": Z.reshape(-1, 2),
        "r": R.reshape(-1, 2),
    },
    "points (n, 2)": {"points": GRID[:, :2], "radii": R},
    "radii (n, 1)": {"points": GRID, "radii": R[:, None]},
    "points and radii of different lengths": {"points": GRID, "radii": R[:-1]},
    "headers claim half the rows": {
        n: (v, (N // 2,)) for n, v in zip("xyzr", (X, Y, Z, R), strict=True)
    },
    "headers claim half the rows, compressed": (
        {n: (v, (N // 2,)) for n, v in zip("xyzr", (X, Y, Z, R), strict=True)},
        True,
    ),
    "headers claim twice the rows": {
        n: (v, (2 * N,)) for n, v in zip("xyzr", (X, Y, Z, R), strict=True)
    },
    "only x truncated": {"x": (X[:-3], (N,)), "y": Y, "z": Z, "r": R},
    "text array": {"points": np.array(["a"] * N), "radii": R},
    "no radii": {"points": GRID},
}


def _outcome(read):
    """(balls) or (error class, message) of a reader."""
    try:
        centers, radii = read()
    except VoroboundError as exc:
        return type(exc).__name__, str(exc)
    return np.column_stack([centers, radii]).tolist()


def _whole(path):
    centers, radii, lines = read_ball_arrays(path)
    return checked_rows(centers, radii, f"balls {path.name}", 0, lines)


def _streamed(path):
    parts = list(ball_chunks(path, chunk_rows=7))
    if not parts:
        return np.empty((0, 3)), np.empty(0)
    return np.concatenate([c for c, _ in parts]), np.concatenate([r for _, r in parts])


def _same(whole, streamed):
    if isinstance(whole, list) or isinstance(streamed, list):
        return whole == streamed
    # The same error; rows are named by file line (whole) or row number (streamed).
    return whole[0] == streamed[0] and (whole[1] == streamed[1] or whole[0] == "InputError")


@pytest.fixture(params=["pyarrow", "numpy"])
def csv_reader(request, monkeypatch):
    if request.param == "pyarrow":
        pytest.importorskip("pyarrow")
        monkeypatch.setattr(stream, "_CSV_BLOCK_BYTES", 64)  # many blocks from a small file
    else:
        monkeypatch.setattr(stream, "pyarrow_available", lambda: False)
    return request.param


@pytest.mark.parametrize("name", list(CSV))
def test_a_csv_is_read_alike_whole_and_streamed(name, csv_reader, tmp_path):
    path = tmp_path / "balls.csv"
    path.write_bytes(CSV[name].encode("utf-8"))
    whole, streamed = _outcome(lambda: _whole(path)), _outcome(lambda: _streamed(path))
    assert _same(whole, streamed), (whole, streamed)


@pytest.mark.parametrize("name", list(NPZ))
def test_an_npz_is_read_alike_whole_and_streamed(name, tmp_path):
    path = tmp_path / "balls.npz"
    arrays, compress = NPZ[name] if isinstance(NPZ[name], tuple) else (NPZ[name], False)
    _npz(path, compress, **arrays)
    whole, streamed = _outcome(lambda: _whole(path)), _outcome(lambda: _streamed(path))
    assert _same(whole, streamed), (whole, streamed)


def test_fortran_ordered_points_are_read_both_ways(tmp_path):
    path = tmp_path / "balls.npz"
    _npz(path, True, **NPZ["points in Fortran order"])
    assert np.array_equal(_whole(path)[0], GRID)
    assert np.array_equal(_streamed(path)[0], GRID)


@pytest.mark.parametrize(
    ("name", "message"),
    [
        ("2-D columns", "must be 1-D"),
        ("points (n, 2)", r"must be of shape \(n, 3\)"),
        ("headers claim half the rows", "its data holds more"),
        ("headers claim half the rows, compressed", "its data holds more"),
        ("headers claim twice the rows", "says 40 rows but its data holds 20"),
        ("only x truncated", "says 20 rows but its data holds 17"),
    ],
)
def test_npz_whose_headers_do_not_fit_the_data_is_refused(name, message, tmp_path):
    path = tmp_path / "balls.npz"
    arrays, compress = NPZ[name] if isinstance(NPZ[name], tuple) else (NPZ[name], False)
    _npz(path, compress, **arrays)
    with pytest.raises(VoroboundError, match=message):
        _whole(path)


ACCEPTED = [
    "quoted header",
    "integers first",
    "extra columns",
    "blank lines mid-file",
    "comment mid-file",
    "crlf",
    "bom",
]
REFUSED = [
    "semicolons, decimal commas",
    "quoted cells",
    "quoted cell later",
    "trailing commas",
    "a long row later",
    "text cell",
]


def test_the_corpus_decides_as_the_whole_reader_does(tmp_path):
    """What the shared rules accept and refuse (so agreement is not agreement on refusing all)."""
    for name in ACCEPTED + REFUSED:
        path = tmp_path / "balls.csv"
        path.write_text(CSV[name], encoding="utf-8")
        outcome = _outcome(lambda: _whole(path))  # noqa: B023
        assert isinstance(outcome, list) == (name in ACCEPTED), (name, outcome)


def _outcomes(run_cli, path, tmp_path):
    """(exit code, ok, n_samples, error line) of check --balls, untiled and with 2 workers."""
    found = []
    for extra in ([], ["--workers", "2"]):
        code, out, err = run_cli("check", "--balls", str(path), "--eps", "0.3", "--json", *extra)
        payload = json.loads(out) if out.strip() else {}
        found.append((code, payload.get("ok"), payload.get("n_samples"), err.strip()))
    return found


def _sample(tmp_path):
    import vorobound

    vorobound.sample(eps=0.3, sphere=1.0, output=tmp_path / "s.npz")
    with np.load(tmp_path / "s.npz") as data:
        return np.column_stack([data["x"], data["y"], data["z"]]), data["radius"]


def test_check_reads_integer_first_rows_with_workers(run_cli, tmp_path, monkeypatch):
    """A sample whose first rows are integers ("0", as sample writes the x = 0 face of a cube)
    was refused by the streamed reader (int64 guessed from the first block)."""
    pytest.importorskip("pyarrow")
    monkeypatch.setattr(stream, "_CSV_BLOCK_BYTES", 100)  # the first block: the first row
    centers, radii = _sample(tmp_path)
    centers = centers - centers[0]  # the first ball at the origin: "0,0,0"
    path = tmp_path / "balls.csv"
    rows = [
        f"{x:.17g},{y:.17g},{z:.17g},{r:.17g}" for (x, y, z), r in zip(centers, radii, strict=True)
    ]
    path.write_text("x,y,z,r\n" + "\n".join(rows) + "\n")
    assert path.read_text().splitlines()[1].startswith("0,0,0,")
    untiled, tiled = _outcomes(run_cli, path, tmp_path)
    assert untiled[0] == tiled[0] == 0, (untiled, tiled)
    assert untiled[2] == tiled[2] == len(radii)


@pytest.mark.parametrize("claim", [0.5, 2.0])
def test_check_refuses_lying_npz_headers_both_ways(run_cli, tmp_path, claim):
    centers, radii = _sample(tmp_path)
    shape = (int(len(radii) * claim),)
    path = tmp_path / "lying.npz"
    _npz(
        path,
        **{
            n: (np.ascontiguousarray(v), shape)
            for n, v in zip("xyzr", (*centers.T, radii), strict=True)
        },
    )
    untiled, tiled = _outcomes(run_cli, path, tmp_path)
    assert untiled[0] == tiled[0] == 2, (untiled, tiled)
    assert untiled[3] == tiled[3] and "header" in untiled[3] and "\n" not in untiled[3]
