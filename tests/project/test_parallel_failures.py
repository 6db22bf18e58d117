"""Failures of workers and clusters end a run with one line, in bounded time (issue 34: a
non-dask listener hung ``--scheduler`` over 300 s, a cluster with no workers waited silently,
a lost scheduler was exit 70 (CancelledError), ``--scheduler foo`` printed a ``Client.__del__``
traceback after 20 s, and a pool's shutdown after Ctrl-C hung over 13 minutes)."""

import concurrent.futures
import os
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from vorobound import parallel
from vorobound.errors import WorkerError

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def ball_file(tmp_path_factory):
    import vorobound

    path = tmp_path_factory.mktemp("balls") / "s.csv"
    vorobound.sample(eps=0.3, sphere=1.0, output=path)
    return path


@pytest.fixture
def silent_listener():
    """A plain TCP server on the loopback that accepts and never says a word."""
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen()
    accepted = []

    def accept():
        while True:
            try:
                accepted.append(server.accept()[0])
            except OSError:
                return

    threading.Thread(target=accept, daemon=True).start()
    yield f"tcp://127.0.0.1:{server.getsockname()[1]}"
    server.close()
    for connection in accepted:
        connection.close()


def test_a_cancelled_task_is_a_worker_error():
    future = concurrent.futures.Future()
    future.cancel()
    with pytest.raises(WorkerError, match="tile 3 was cancelled"):
        parallel.task_result(future, "tile 3")


def test_a_pool_that_does_not_stop_is_left_behind_in_bounded_time(monkeypatch):
    """A pool whose shutdown never returns (its manager thread waiting for a result a killed
    worker never sent) no longer holds the interrupted run."""
    monkeypatch.setattr(parallel, "SHUTDOWN_SECONDS", 0.5)
    stuck = threading.Event()

    class Stuck:
        _processes = {}

        def shutdown(self, wait=True, cancel_futures=False):
            stuck.wait(60)

    start = time.monotonic()
    parallel._kill_pool(Stuck(), [])
    assert time.monotonic() - start < 5
    stuck.set()


@pytest.mark.slow
def test_a_non_dask_listener_is_one_line_in_bounded_time(
    run_cli, ball_file, silent_listener, monkeypatch
):
    pytest.importorskip("distributed")
    monkeypatch.setattr(parallel, "DASK_CONNECT_SECONDS", 1)
    start = time.monotonic()
    code, _, err = run_cli(
        "check", "--balls", str(ball_file), "--eps", "0.3", "--scheduler", silent_listener
    )
    assert time.monotonic() - start < 20
    assert code == 2 and "no dask scheduler answered within 1 s" in err
    assert len(err.strip().splitlines()) == 1


@pytest.mark.slow
def test_a_cluster_without_workers_is_one_line(run_cli, ball_file, monkeypatch):
    distributed = pytest.importorskip("distributed")
    monkeypatch.setattr(parallel, "DASK_WORKER_SECONDS", 1)
    with distributed.LocalCluster(n_workers=0, processes=False, dashboard_address=None) as cluster:
        code, _, err = run_cli(
            "check",
            "--balls",
            str(ball_file),
            "--eps",
            "0.3",
            "--scheduler",
            cluster.scheduler_address,
        )
    assert code == 2 and "has no workers" in err, err
    assert len(err.strip().splitlines()) == 1


@pytest.mark.slow
def test_a_scheduler_address_without_port_is_one_line_and_no_del_traceback(ball_file):
    pytest.importorskip("distributed")
    start = time.monotonic()
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "vorobound",
            "check",
            "--balls",
            str(ball_file),
            "--eps",
            "0.3",
            "--scheduler",
            "foo",
        ],
        capture_output=True,
        text=True,
        timeout=120,
        env=os.environ | {"PYTHONPATH": str(ROOT)},
    )
    assert done.returncode == 2
    assert done.stderr.strip().splitlines() == [
        "error: cannot reach the dask scheduler at foo: missing port number in address 'foo'"
    ]
    assert time.monotonic() - start < 18  # the client's __del__ waited 20 s


# --- a real cluster that loses its scheduler or its only worker mid-run ----------------------


@pytest.fixture(scope="module")
def row_balls(tmp_path_factory):
    """About 1.3·10⁵ balls: many seconds on one dask worker thread."""
    import numpy as np

    from vorobound.sampling.balls import make_balls
    from vorobound.sampling.io.balls import write_balls
    from vorobound.sampling.sampler.torus_rows import torus_rows

    parts = list(torus_rows(3.0, 1.0, 0.03))
    balls = make_balls(np.concatenate([c for c, _ in parts]), np.concatenate([r for _, r in parts]))
    path = tmp_path_factory.mktemp("rows") / "rows.npz"
    write_balls(path, balls, {})
    return path


def _dask_process(tmp_path: Path, role: str, scheduler_file: Path) -> subprocess.Popen:
    args = {
        "scheduler": ["--port", "0"],
        "worker": ["--nthreads", "1", "--nworkers", "1", "--no-nanny"],
    }[role]
    return subprocess.Popen(
        [sys.executable, "-m", f"distributed.cli.dask_{role}", *args, "--no-dashboard"]
        + ["--scheduler-file", str(scheduler_file)],
        stdout=subprocess.DEVNULL,
        stderr=open(tmp_path / f"{role}.log", "w"),  # noqa: SIM115 (the process owns it)
    )


@pytest.mark.slow
@pytest.mark.parametrize("lost", ["scheduler", "worker"])
def test_a_cluster_that_dies_mid_run_is_one_line_and_no_output(tmp_path, row_balls, lost):
    """The scheduler or the only worker SIGKILLed while the tiles run: exit 2 with one line in
    bounded time, nothing written (a lost worker used to hang the run for ever; a lost
    scheduler printed dask's 30-line reconnect traceback)."""
    pytest.importorskip("distributed")
    import json
    import signal

    scheduler_file = tmp_path / "scheduler.json"
    processes = [_dask_process(tmp_path, "scheduler", scheduler_file)]
    try:
        deadline = time.monotonic() + 60
        while not scheduler_file.exists() and time.monotonic() < deadline:
            time.sleep(0.2)
        time.sleep(0.5)  # written, then complete
        address = json.loads(scheduler_file.read_text())["address"]
        processes.append(_dask_process(tmp_path, "worker", scheduler_file))
        out = tmp_path / "out"
        run = subprocess.Popen(
            [sys.executable, "-m", "vorobound", "check", "--balls", str(row_balls)]
            + ["--eps", "0.03", "--scheduler", address, "--out", str(out)],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.PIPE,
            text=True,
            env=os.environ | {"PYTHONPATH": str(ROOT), "VOROBOUND_DASK_WORKER_SECONDS": "3"},
        )
        # The tiles are running once the worker holds a task (its log says nothing by default):
        # the output's hidden folder exists and the run has lasted a while.
        deadline = time.monotonic() + 120
        while not (out.exists() and any(out.iterdir())) and time.monotonic() < deadline:
            time.sleep(0.2)
        time.sleep(3)
        assert run.poll() is None, "the run ended before the cluster could fail"
        victim = processes[0] if lost == "scheduler" else processes[1]
        start = time.monotonic()
        victim.send_signal(signal.SIGKILL)
        _, err = run.communicate(timeout=120)
        assert time.monotonic() - start < 60
        lines = err.strip().splitlines()
        assert run.returncode == 2 and len(lines) == 1, err
        assert "dask" in lines[0] and "nothing was written" in lines[0]
        if lost == "worker":
            assert "has had no worker for 3 s" in lines[0]
        assert list(out.iterdir()) == []
    finally:
        for process in processes:
            process.kill()
            process.wait(30)


@pytest.mark.parametrize("text", ["0", "-1", "nan", "inf", "soon", "1e308"])
def test_a_bad_worker_wait_is_refused(monkeypatch, text):
    from vorobound.errors import InputError

    monkeypatch.setenv(parallel.DASK_WORKER_VARIABLE, text)
    with pytest.raises(InputError, match="VOROBOUND_DASK_WORKER_SECONDS"):
        parallel._worker_seconds()


def test_the_worker_wait_comes_from_the_environment(monkeypatch):
    monkeypatch.delenv(parallel.DASK_WORKER_VARIABLE, raising=False)
    assert parallel._worker_seconds() == parallel.DASK_WORKER_SECONDS
    monkeypatch.setenv(parallel.DASK_WORKER_VARIABLE, "2.5")
    assert parallel._worker_seconds() == 2.5
