"""Helpers shared by the test folders (tests/ is on pytest's ``pythonpath``, pyproject.toml):
the command line's contracts written once, and the processes the subprocess tests start.

- ``assert_one_line_error``: bad input is exit 2, nothing on stdout, exactly one line on stderr,
  no traceback (COMMON rule of every command).
- ``json_of``: a command's ``--json`` output, after asserting it succeeded.
- ``run_main``: the command line in-process where ``run_cli`` cannot be used (module fixtures
  that share one run between tests).
- ``start``, ``start_ready``, ``ReadyStderr``, ``processes_with``, ``wait_until``: commands run
  as child processes (``python -m vorobound``), and the processes that carry a marker.
The ``run_cli`` fixture (tests/conftest.py) runs the command line in-process.
"""

from __future__ import annotations

import contextlib
import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PYTHON = [sys.executable, "-m", "vorobound"]


def assert_one_line_error(code: int, out: str | None, err: str, *fragments: str) -> None:
    """The contract for bad input: exit 2, stdout empty (pass ``out=None`` where a test does not
    capture it), exactly one line on stderr, no traceback, and every fragment in that line."""
    assert code == 2, (code, err)
    if out is not None:
        assert out == "", out
    assert len(err.strip().splitlines()) == 1, err
    assert "Traceback" not in err, err
    for fragment in fragments:
        assert fragment in err, (fragment, err)


def json_of(result: tuple[int, str, str]) -> dict:
    """The parsed ``--json`` output of ``run_cli(...)``'s (code, out, err), which must be exit 0."""
    code, out, err = result
    assert code == 0, err
    return json.loads(out)


def run_main(*args: str) -> tuple[int, str, str]:
    """Run ``vorobound`` in-process, outside a test (a module-scoped fixture, where the
    ``run_cli`` fixture's ``capsys`` is not available): (exit code, stdout, stderr)."""
    import io

    from vorobound.cli import main

    capture = pytest.MonkeyPatch()
    out, err = io.StringIO(), io.StringIO()
    capture.setattr(sys, "stdout", out)
    capture.setattr(sys, "stderr", err)
    try:
        code = main(list(args))
    finally:
        capture.undo()
    return code, out.getvalue(), err.getvalue()


def signals_as_from_a_terminal() -> None:
    """``preexec_fn`` of a child that a test sends signals to: SIGINT and SIGTERM handled by
    default and not blocked, as in a command started from a terminal, whatever the test
    process inherited or left (an ignored or blocked SIGINT is inherited across exec, and the
    child would never see the test's Ctrl-C)."""
    import signal

    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, signal.SIG_DFL)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT, signal.SIGTERM})


def start(args, env=None, stdout=subprocess.PIPE, **kwargs):
    return subprocess.Popen(
        PYTHON + args,
        env=os.environ | (env or {}),
        stdout=stdout if stdout is not None else subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=signals_as_from_a_terminal,
        **kwargs,
    )


class ReadyStderr:
    """A child's stderr read line by line in a thread; ``ready`` is set once the child says
    its signal handlers are installed (``VOROBOUND_SIGNALS_READY``), or at the end of stderr."""

    def __init__(self, proc):
        self.lines: list[str] = []
        self.ready = threading.Event()
        self.thread = threading.Thread(target=self._read, args=(proc.stderr,), daemon=True)
        self.thread.start()

    def _read(self, stream):
        from vorobound.cli import SIGNALS_READY_LINE

        for line in stream:
            line = line.rstrip("\n")
            if line == SIGNALS_READY_LINE:
                self.ready.set()
            else:
                self.lines.append(line)
        self.ready.set()

    def rest(self, proc, timeout: float) -> list[str]:
        """The rest of stderr once the process ends. A process still running after ``timeout``
        is asked for its threads' stacks (SIGUSR1, see the CLI) and killed; the test fails
        with them."""
        try:
            proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            with contextlib.suppress(OSError):
                proc.send_signal(signal.SIGUSR1)
                time.sleep(3)
                proc.kill()
            proc.wait(30)
            self.thread.join(timeout=30)
            stacks = "\n".join(self.lines[-200:])
            pytest.fail(f"the command did not end within {timeout} s; its stacks:\n{stacks}")
        self.thread.join(timeout=timeout)
        return [line for line in self.lines if line.strip()]


def start_ready(args, env=None, timeout=120):
    """Start a command and return (process, its stderr) once its signal handlers are in: a
    signal sent now is the command's to handle, however loaded the machine."""
    from vorobound.cli import SIGNALS_READY_VARIABLE

    proc = start(args, env=(env or {}) | {SIGNALS_READY_VARIABLE: "1"}, stdout=None)
    stderr = ReadyStderr(proc)
    assert stderr.ready.wait(timeout), "no readiness line"
    assert proc.poll() is None, f"the command ended before it was ready: {stderr.lines}"
    return proc, stderr


def processes_with(marker: str | bytes) -> list[int]:
    """The ids of the processes whose environment holds ``marker`` (Linux /proc)."""
    needle = marker.encode() if isinstance(marker, str) else marker
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            if needle in (entry / "environ").read_bytes():
                found.append(int(entry.name))
        except OSError:
            continue
    return found


def wait_until(condition, timeout: float) -> bool:
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if condition():
            return True
        time.sleep(0.2)
    return condition()
