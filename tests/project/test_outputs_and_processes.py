"""Outputs are never half-written, workers never outlive their parent, sweeps stay small.

Subprocess tests: kill a ``figure`` and a ``sweep -o`` while they write and check the previous
files are intact; two concurrent ``figure`` runs each leave complete files; a killed or
terminated ``sweep --jobs 2`` leaves no live worker; a big paper sweep runs in bounded memory.
"""

import os
import signal
import subprocess
import sys
import time
import uuid
from pathlib import Path

import pytest
from helpers import processes_with as _processes_with
from helpers import run_main
from helpers import start as _start
from helpers import start_ready as _start_ready
from helpers import wait_until as _wait_until

from vorobound.errors import WriteError
from vorobound.files import TEMP_PREFIX, atomic_path, write_set, write_text

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


# --- the writer itself ---------------------------------------------------------------------


def test_failed_write_leaves_the_old_file_and_no_temporary(tmp_path):
    target = tmp_path / "out.txt"
    target.write_text("old")
    with pytest.raises(RuntimeError), atomic_path(target) as temp:
        temp.write_text("half")
        raise RuntimeError("writer failed")
    assert target.read_text() == "old"
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(TEMP_PREFIX)]


def test_a_set_is_replaced_whole_or_not_at_all(tmp_path):
    first, second = tmp_path / "a.txt", tmp_path / "b.txt"
    write_set({first: lambda p: p.write_text("A1"), second: lambda p: p.write_text("B1")})

    def broken(path):
        raise OSError(28, "No space left on device")

    with pytest.raises(WriteError):
        write_set({first: lambda p: p.write_text("A2"), second: broken})
    assert (first.read_text(), second.read_text()) == ("A1", "B1")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt", "b.txt"]


def test_missing_folder_is_a_clear_error(tmp_path):
    with pytest.raises(WriteError, match="does not exist"):
        write_text(tmp_path / "no" / "such" / "file.csv", "x")


# --- killed and concurrent commands ----------------------------------------------------------


BIG_SWEEP = ["sweep", "--sigma", "0.3:1.5:400", "--rho-f", "1.01:3:400", "--mode", "paper,rigorous"]


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM, signal.SIGKILL])
def test_interrupted_sweep_keeps_the_previous_file(tmp_path, sig):
    out = tmp_path / "out.csv"
    out.write_text("previous,content\n")
    proc, stderr = _start_ready([*BIG_SWEEP, "-o", str(out)])
    # Stopped while it writes: the temporary file is there.
    writing = _wait_until(
        lambda: (
            proc.poll() is not None
            or any(p.name.startswith(TEMP_PREFIX) for p in tmp_path.iterdir())
        ),
        120,
    )
    assert writing and proc.poll() is None, "the sweep ended before it could be interrupted"
    proc.send_signal(sig)
    lines = stderr.rest(proc, 60)
    assert out.read_text() == "previous,content\n"
    if sig is not signal.SIGKILL:
        assert proc.returncode == 130
        assert lines[-1].strip() == "interrupted"
        assert not [p for p in tmp_path.iterdir() if p.name.startswith(TEMP_PREFIX)]


def _figure_bytes(folder: Path) -> dict:
    return {p.name: p.read_bytes() for p in sorted(folder.glob("*.png"))}


@pytest.fixture(scope="module")
def figure_sets(tmp_path_factory):
    """The figure files for two parameter sets (the files depend only on the data)."""
    sets = {}
    for rho_f in ("1.38", "1.5"):  # in this process: the same files, without a start-up each
        folder = tmp_path_factory.mktemp(f"figures{rho_f}")
        code, _, err = run_main("figure", "--no-tight", "--rho-f", rho_f, "--out", str(folder))
        assert code == 0, err
        sets[rho_f] = _figure_bytes(folder)
    assert all(sets["1.38"][name] != sets["1.5"][name] for name in sets["1.38"])
    return sets


@pytest.mark.slow
def test_killed_figure_runs_leave_complete_files(tmp_path, figure_sets):
    """SIGKILL at several moments of a run; every file is always the old or the new one."""
    old, fresh = figure_sets["1.38"], figure_sets["1.5"]
    target = tmp_path / "figures"
    target.mkdir()
    for name, content in old.items():
        (target / name).write_bytes(content)
    for delay in (1.0, 2.0, 3.0):
        proc = _start(["figure", "--no-tight", "--rho-f", "1.5", "--out", str(target)])
        time.sleep(delay)
        proc.kill()
        proc.wait(timeout=60)
        now = _figure_bytes(target)
        assert now.keys() == old.keys()
        for name, content in now.items():
            assert content in (old[name], fresh[name]), (delay, name)


def test_concurrent_figure_runs_each_leave_complete_files(tmp_path, figure_sets):
    shared = tmp_path / "shared"
    procs = [
        _start(["figure", "--no-tight", "--rho-f", rho_f, "--out", str(shared)])
        for rho_f in figure_sets
    ]
    for proc in procs:
        _, err = proc.communicate(timeout=180)
        assert proc.returncode == 0, err
    for name, content in _figure_bytes(shared).items():
        assert content in [files[name] for files in figure_sets.values()]
    assert sorted(p.name for p in shared.iterdir()) == [
        "comparison.png",
        "figure3.png",
        "ratio.png",
    ]


# --- worker processes -----------------------------------------------------------------------


TIGHT_SWEEP = [
    "sweep",
    "--mode",
    "tight",
    "--method",
    "optimize",
    "--sigma",
    "0.5,0.6,0.7,0.8",
    "--jobs",
    "2",
    "--yes",
]


@pytest.mark.skipif(not Path("/proc/self/environ").exists(), reason="needs Linux /proc")
@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGTERM])
def test_stopped_tight_sweep_leaves_no_live_workers(tmp_path, sig):
    marker = f"VOROBOUND_TEST_MARKER={uuid.uuid4().hex}"
    key, value = marker.split("=")
    proc, stderr = _start_ready([*TIGHT_SWEEP, "-o", str(tmp_path / "t.csv")], env={key: value})
    assert _wait_until(lambda: len(_processes_with(marker)) >= 3, 60), "workers did not start"
    proc.send_signal(sig)
    lines = stderr.rest(proc, 60)
    assert _wait_until(lambda: not _processes_with(marker), 20), "workers outlived the sweep"
    if sig is signal.SIGTERM:
        assert proc.returncode == 130 and lines[-1].strip() == "interrupted"


# --- memory -------------------------------------------------------------------------------


MEMORY_PROBE = (
    "import resource, sys\n"
    "resource.setrlimit(resource.RLIMIT_AS, (1 << 30, 1 << 30))\n"
    "from vorobound.cli import main\n"
    "code = main(sys.argv[1:])\n"
    "print('PEAK_KB', resource.getrusage(resource.RUSAGE_SELF).ru_maxrss, file=sys.stderr)\n"
    "sys.exit(code)\n"
)
GROWTH_LIMIT_KB = 30_000
"""Allowed growth of peak memory from 10⁴ to 9·10⁴ rows (streaming: nothing grows with the
grid; a table kept in memory would add ~200 bytes per row, 16 MB here)."""


def _peak_kb(rows_per_axis: int, out: Path) -> int:
    axis = f"0.3:1.5:{rows_per_axis}"
    args = ["sweep", "--sigma", axis, "--rho-f", f"1.01:3:{rows_per_axis}", "--mode", "paper"]
    args += ["--target", "additive"]
    done = subprocess.run(
        [sys.executable, "-c", MEMORY_PROBE, *args, "--format", "csv", "-o", str(out)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr
    assert out.read_text().count("\n") == rows_per_axis**2 + 1
    return int(done.stderr.split("PEAK_KB")[1].split()[0])


@pytest.mark.slow
def test_big_paper_sweep_runs_in_bounded_memory(tmp_path):
    small = _peak_kb(100, tmp_path / "small.csv")
    big = _peak_kb(300, tmp_path / "big.csv")
    assert big - small < GROWTH_LIMIT_KB, (small, big)


def test_devices_and_pipes_are_written_in_place_not_replaced(tmp_path):
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    reader = subprocess.Popen(["cat", str(fifo)], stdout=subprocess.PIPE)
    write_text(fifo, "through the pipe\n")
    assert reader.communicate(timeout=30)[0] == b"through the pipe\n"
    assert fifo.is_fifo()
    write_text("/dev/null", "discarded\n")
    assert Path("/dev/null").is_char_device()
    folder = tmp_path / "a folder"
    folder.mkdir()
    with pytest.raises(WriteError, match="folder"):
        write_text(folder, "x")


@pytest.mark.slow
def test_an_interrupt_lets_the_kd_tree_worker_threads_finish_first():
    """scipy's k-d tree queries with workers=-1 run daemon threads that write into arrays the
    main thread frees when it unwinds; an interrupt must wait for them (it crashed the process
    with a segmentation fault before)."""
    import threading

    import numpy as np
    from scipy.spatial import cKDTree

    from vorobound.cli import Interrupted, _signals_raise_interrupted

    rng = np.random.default_rng(0)
    tree = cKDTree(rng.random((100_000, 3)))
    queries = rng.random((3_000_000, 3))
    timer = threading.Timer(0.2, os.kill, (os.getpid(), signal.SIGINT))
    with pytest.raises(Interrupted), _signals_raise_interrupted():
        timer.start()
        tree.query(queries, k=4, workers=2)
    timer.join()
    running = [
        t
        for t in threading.enumerate()
        if (getattr(getattr(t, "_target", None), "__module__", "") or "").startswith("scipy.")
    ]
    assert not running


# --- an interrupt while a pool starts its workers -------------------------------------------

STARTUP_PROBE = """
import multiprocessing.process, os, signal, sys
from vorobound import parallel

class Stop(BaseException):
    pass

def stop(signum, frame):
    raise Stop

signal.signal(signal.SIGTERM, stop)
plain_start = multiprocessing.process.BaseProcess.start
starts = []

def start(self):
    # SIGTERM arrives while the second worker is being started: without the shield the
    # handler would raise before the worker has been handed its instructions.
    starts.append(self)
    if len(starts) == 2:
        os.kill(os.getpid(), signal.SIGTERM)
    plain_start(self)

multiprocessing.process.BaseProcess.start = start
try:
    if sys.argv[1] == "pool":
        with parallel.process_pool(2) as pool:
            print("not interrupted")
    else:
        with parallel.task_executor(2) as (executor, _):
            futures = [executor.submit(abs, -k) for k in range(4)]
            print("not interrupted", [f.result() for f in futures])
except Stop:
    print("interrupted", [p.exitcode is not None for p in starts])
"""


@pytest.mark.skipif(not Path("/proc/self/environ").exists(), reason="needs Linux /proc")
@pytest.mark.parametrize("kind", ["pool", "executor"])
def test_an_interrupt_during_worker_start_up_leaves_no_worker_and_no_traceback(kind):
    marker = f"VOROBOUND_TEST_MARKER={uuid.uuid4().hex}"
    key, value = marker.split("=")
    done = subprocess.run(
        [sys.executable, "-c", STARTUP_PROBE, kind],
        env=os.environ | {key: value},
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr
    # The signal is handled once the worker exists, and every worker started is stopped.
    assert done.stdout.strip() == "interrupted [True, True]", done.stdout
    assert "Traceback" not in done.stderr and "Error" not in done.stderr, done.stderr
    assert _wait_until(lambda: not _processes_with(marker), 20), "a worker outlived its parent"
