"""Ctrl-C at awkward moments is one line and exit 130 (issue 34: during the half second the
command line takes to import, it was a 20-line traceback)."""

import os
import subprocess
import sys
from pathlib import Path

import pytest
from helpers import signals_as_from_a_terminal

ROOT = Path(__file__).resolve().parents[2]

# SIGINT arrives while the command line imports typer: deterministic, not a race.
INTERRUPT_DURING_IMPORT = """
import builtins, os, signal, sys
real = builtins.__import__
def importing(name, *args, **kwargs):
    if name == "typer":
        os.kill(os.getpid(), signal.SIGINT)
    return real(name, *args, **kwargs)
builtins.__import__ = importing
sys.argv = ["vorobound", "--help"]
{run}
"""


@pytest.mark.parametrize(
    "run",
    [
        "import runpy; runpy.run_module('vorobound', run_name='__main__')",
        "from vorobound.launch import entry; entry()",
    ],
    ids=["python -m vorobound", "console script"],
)
def test_an_interrupt_during_import_is_one_line(run):
    done = _child(INTERRUPT_DURING_IMPORT.format(run=run))
    assert done.returncode == 130, done.stderr
    assert done.stderr == "interrupted\n"


# SIGINT arrives while the exit handlers run, after the command's output is written.
INTERRUPT_WHILE_EXITING = """
import atexit, os, signal, sys, time
atexit.register(lambda: (os.kill(os.getpid(), signal.{signal}), time.sleep(0.2)))
sys.argv = ["vorobound", "solve", "--json"]
from vorobound.launch import entry
entry()
"""


@pytest.mark.parametrize("signal", ["SIGINT", "SIGTERM"])
def test_an_interrupt_while_the_process_exits_is_one_line(signal):
    """Found by the hostile-input pass: Ctrl-C in the last half second, while the interpreter
    shut down, ended the run with exit 0 and an 'Exception ignored' traceback (or no line)."""
    done = _child(INTERRUPT_WHILE_EXITING.format(signal=signal))
    assert done.returncode == 130, done.stderr
    assert done.stderr == "interrupted\n"
    assert '"command": "solve"' in done.stdout  # the output was complete and is kept


def _child(code: str) -> subprocess.CompletedProcess:
    """Run ``code`` in a fresh interpreter that takes signals as a terminal's foreground job."""
    return subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        env=os.environ | {"PYTHONPATH": str(ROOT)},
        timeout=60,
        preexec_fn=signals_as_from_a_terminal,
    )
