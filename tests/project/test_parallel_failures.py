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
