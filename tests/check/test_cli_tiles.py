"""``vorobound check --balls F --workers K | --scheduler ADDRESS``: the tiled check from the command
line. Same n_guide_triangles, n_half_covered and gap_ratio_max as the untiled check and as
``--workers 1``; outputs as one set (Parquet dataset or CSV, summary, decimated VTU, figure);
one-line refusals; a killed worker or Ctrl-C leaves no output, no temporary file, no process.

Runs with the oldest dependencies too (CI): Parquet and dask parts skip without pyarrow/dask.
"""

import json
import os
import signal
import uuid
from pathlib import Path

import numpy as np
import pytest
from helpers import run_main

from vorobound.files import TEMP_PREFIX
from vorobound.sampling.balls import make_balls
from vorobound.sampling.io.balls import write_balls
from vorobound.sampling.sampler.maximal import sample_surface
from vorobound.sampling.sampler.torus_rows import torus_rows
from vorobound.sampling.surfaces.analytic import TorusShape

pytest.importorskip("gudhi")

COMPARED = ("n_guide_triangles", "n_half_covered", "gap_ratio_max")
"""The fields the issue names; tests/test_check_tiles.py compares every other one."""
EPS = 0.1


@pytest.fixture(scope="module")
def torus_file(tmp_path_factory):
    """Balls of a torus with varying L (radii differ, so the gap is not 0)."""
    sample = sample_surface(TorusShape(1.5, 1.0), EPS, 0.75, seed=0)
    path = tmp_path_factory.mktemp("balls") / "torus.csv"
    write_balls(path, make_balls(sample.points, 2 * EPS * sample.lfs), {})
    return path


def _summary(run_cli, *args):
    code, out, err = run_cli("check", *args, "--json")
    return _checked(code, out, err)


def _checked(code, out, err):
    summary = json.loads(out)
    assert code == (0 if summary["ok"] else 1), err  # 1: the check found violations
    return summary


@pytest.fixture(scope="module")
def runs(torus_file, tmp_path_factory):
    """The check of ``torus_file`` untiled, on one worker and on two, each run once for the
    tests below: the untiled and the two-worker runs write ``--table npz`` rows (into
    ``folder``/whole and ``folder``/tiled), which test_npz_rows_are_the_untiled_rows reads; the
    one-worker run writes ``--table csv`` (into ``folder``/csv: its tile's part files are joined
    as the two workers' are), which test_csv_outputs_are_one_set reads."""
    folder = tmp_path_factory.mktemp("runs")
    base = ["check", "--balls", str(torus_file), "--eps", str(EPS), "--json"]
    npz = ["--table", "npz", "--out"]
    csv = str(folder / "csv")
    return {
        "untiled": _checked(*run_main(*base, *npz, str(folder / "whole"))),
        "one": _checked(*run_main(*base, "--workers", "1", "--table", "csv", "--out", csv)),
        "two": _checked(*run_main(*base, "--workers", "2", *npz, str(folder / "tiled"))),
        "folder": folder,
    }


def test_workers_give_the_untiled_answer(runs):
    untiled, one, two = runs["untiled"], runs["one"], runs["two"]
    assert untiled["gap_ratio_max"] > 0
    for key in COMPARED:
        assert one[key] == untiled[key] == two[key], key
    assert one["tiles"]["executor"] == "in process"
    assert two["tiles"]["executor"] == "local process pool"


@pytest.mark.slow
def test_scheduler_gives_the_same_answer(run_cli, torus_file, runs):
    """Slow (a LocalCluster costs seconds): by default, the library's dask path is
    test_check_tiles.py::test_dask_local_cluster_gives_the_same_summary (every summary field)
    and ``--scheduler`` reaches it in test_unreachable_scheduler_is_one_line."""
    distributed = pytest.importorskip("distributed")
    base = ["--balls", str(torus_file), "--eps", str(EPS)]
    one = runs["one"]
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None
    ) as cluster:
        remote = _summary(run_cli, *base, "--scheduler", cluster.scheduler_address)
    for key in COMPARED:
        assert remote[key] == one[key], key
    assert remote["tiles"]["executor"] == "dask.distributed"


def _no_leftovers(folder: Path) -> None:
    assert not [p.name for p in folder.iterdir() if p.name.startswith(TEMP_PREFIX)]


def test_csv_outputs_are_one_set(runs):
    s, out = runs["one"], runs["folder"] / "csv"
    names = sorted(p.name for p in out.iterdir())
    assert names == ["gap_histogram.png", "sample.vtu", "summary.json", "triangles.csv"]
    rows = np.genfromtxt(out / "triangles.csv", delimiter=",", names=True)
    assert len(rows) == s["n_guide_triangles"]
    assert float(rows["gap_ratio"].max()) == pytest.approx(
        s["gap_ratio_max"], rel=1e-9
    )  # 10 digits
    assert s["rows"]["table"] == "csv"
    saved = json.loads((out / "summary.json").read_text())
    assert saved["n_guide_triangles"] == s["n_guide_triangles"]
    import meshio

    mesh = meshio.read(out / "sample.vtu")
    assert len(mesh.cells_dict["triangle"]) == s["rows"]["vtu_triangles"] > 0
    _no_leftovers(out)


def test_npz_rows_are_the_untiled_rows(runs):
    """``--table npz`` in tiles: one triangles.npz joined from the tiles' parts, with the rows
    of the untiled check (the same triangles, exactly the same values)."""
    s, whole, folder = runs["two"], runs["untiled"], runs["folder"]
    assert s["rows"] == {
        "table": "npz",
        "triangles": "triangles.npz",
        "vtu_triangles": s["n_guide_triangles"],
        "vtu_selection": "all guide triangles",
    }
    assert str(folder / "tiled" / "triangles.npz") in s["written"]
    with (
        np.load(folder / "tiled" / "triangles.npz") as tiled,
        np.load(folder / "whole" / "triangles.npz") as untiled,
    ):
        assert tiled.files == untiled.files
        assert len(tiled["a_index"]) == s["n_guide_triangles"] == whole["n_guide_triangles"]
        order = np.lexsort([tiled[n] for n in ("c_index", "b_index", "a_index")])
        want = np.lexsort([untiled[n] for n in ("c_index", "b_index", "a_index")])
        for name in untiled.files:
            assert np.array_equal(tiled[name][order], untiled[name][want], equal_nan=True), name
    _no_leftovers(folder / "tiled")


def test_parquet_dataset_replaces_the_previous_one(run_cli, torus_file, tmp_path):
    pq = pytest.importorskip("pyarrow.parquet")
    out = tmp_path / "out"
    (out / "triangles").mkdir(parents=True)
    (out / "triangles" / "stale.parquet").write_text("old")
    args = ["--balls", str(torus_file), "--eps", str(EPS), "--workers", "1", "--out", str(out)]
    s = _summary(run_cli, *args)
    assert s["rows"]["table"] == "parquet"
    assert not (out / "triangles" / "stale.parquet").exists()
    table = pq.read_table(out / "triangles")
    assert table.num_rows == s["n_guide_triangles"]
    assert max(table.column("gap_ratio").to_pylist()) == s["gap_ratio_max"]
    _no_leftovers(out)


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--workers", "2", "--torus", "1.5,1"], "coverage against a surface"),
        (["--table", "csv"], "give out too"),
        (["--workers", "1", "--table", "csv"], "give out too"),
        (["--workers", "1", "--engine", "hull"], "engine hull"),
    ],
)
def test_refusals_are_one_line(run_cli, torus_file, extra, message):
    code, out, err = run_cli("check", "--balls", str(torus_file), "--eps", str(EPS), *extra)
    assert code == 2 and out == ""
    assert message in err and len(err.strip().splitlines()) == 1


def test_workers_need_balls_and_a_positive_count(run_cli):
    code, _, err = run_cli("check", "--torus", "3,1", "--eps", "0.1", "--workers", "2")
    assert code == 2 and "go with balls" in err
    code, _, err = run_cli("check", "--balls", "x.csv", "--eps", "0.1", "--workers", "0")
    assert code == 2 and "Traceback" not in err


def test_unreachable_scheduler_is_one_line(run_cli, torus_file, monkeypatch):
    pytest.importorskip("distributed")
    import vorobound.parallel

    monkeypatch.setattr(vorobound.parallel, "DASK_CONNECT_SECONDS", 1)
    code, _, err = run_cli(
        "check", "--balls", str(torus_file), "--eps", str(EPS), "--scheduler", "tcp://127.0.0.1:9"
    )
    assert code == 2 and "cannot reach the dask scheduler" in err
    assert len(err.strip().splitlines()) == 1


@pytest.mark.parametrize("tiles", [["--workers", "1"], []], ids=["tiled", "whole"])
def test_parquet_without_pyarrow_is_refused(run_cli, torus_file, tmp_path, monkeypatch, tiles):
    """Checked in one place for either check, before any work: one line, no output."""
    import vorobound.sampling.io.balls as balls_io

    monkeypatch.setattr(balls_io, "pyarrow_available", lambda: False)
    out = tmp_path / "o"
    args = ["--balls", str(torus_file), "--eps", str(EPS), *tiles, "--out", str(out)]
    code, _, err = run_cli("check", *args, "--table", "parquet")
    assert code == 2 and "pip install 'vorobound[parquet]'" in err
    assert len(err.strip().splitlines()) == 1 and not out.exists()


# --- a killed worker, Ctrl-C --------------------------------------------------------------


ROWS_EPS = 0.022


@pytest.fixture(scope="module")
def rows_file(tmp_path_factory):
    """About 2.4·10⁵ balls: two tiles (tiling.engine.tile_count), several seconds on two
    workers."""
    parts = list(torus_rows(3.0, 1.0, ROWS_EPS))
    balls = make_balls(np.concatenate([c for c, _ in parts]), np.concatenate([r for _, r in parts]))
    path = tmp_path_factory.mktemp("rows") / "rows.npz"
    write_balls(path, balls, {})
    return path


def _workers(marker: str) -> list[int]:
    from helpers import processes_with as _processes_with

    found = []
    for pid in _processes_with(marker):
        try:
            command = Path(f"/proc/{pid}/cmdline").read_bytes()
        except OSError:
            continue
        if b"spawn_main" in command:
            found.append(pid)
    return found


def _start_tiled(rows_file, out: Path, marker: str):
    """The tiled check started, once its signal handlers are in: (process, its stderr)."""
    from helpers import start_ready as _start_ready

    key, value = marker.split("=")
    args = ["check", "--balls", str(rows_file), "--eps", str(ROWS_EPS), "--workers", "2"]
    return _start_ready([*args, "--out", str(out)], env={key: value})


@pytest.mark.slow
@pytest.mark.skipif(not Path("/proc/self/environ").exists(), reason="needs Linux /proc")
@pytest.mark.parametrize("how", ["kill a worker", "ctrl-c"])
@pytest.mark.parametrize("delay", [0.0, 2.0])
def test_a_failed_run_leaves_nothing(rows_file, tmp_path, how, delay):
    """Stopped as the workers start, or while they compute tiles."""
    import time

    from helpers import processes_with as _processes_with
    from helpers import wait_until as _wait_until

    out = tmp_path / "out"
    marker = f"VOROBOUND_TEST_MARKER={uuid.uuid4().hex}"
    proc, stderr = _start_tiled(rows_file, out, marker)
    started = _wait_until(
        lambda: out.exists() and any(out.iterdir()) and len(_workers(marker)) == 2, 120
    )
    assert started, "the tiles did not start"
    time.sleep(delay)
    assert proc.poll() is None, "the run ended before it could be stopped"
    if how == "kill a worker":
        os.kill(_workers(marker)[0], signal.SIGKILL)
    else:
        proc.send_signal(signal.SIGINT)
    lines = stderr.rest(proc, 120)
    err = "\n".join(lines)
    if how == "kill a worker":
        assert proc.returncode == 2 and "worker process died" in lines[-1]
    else:
        assert proc.returncode == 130 and lines[-1] == "interrupted"
    assert len(lines) == 1 and "Traceback" not in err
    assert list(out.iterdir()) == []  # no output, no temporary folder
    assert _wait_until(lambda: not _processes_with(marker), 20), "processes outlived the run"
