"""Worker processes that never outlive their parent.

Pools start workers with the ``spawn`` method (no inherited threads or locks), each worker
asks the kernel to kill it when its parent dies (Linux ``PR_SET_PDEATHSIG``), and leaving the
pool's block on an exception (Ctrl-C included) terminates the workers at once instead of
waiting for their current task. If the parent is killed outright, multiprocessing's resource
tracker still removes the pool's semaphores, without its "leaked semaphore" warning.
"""

from __future__ import annotations

import contextlib
import ctypes
import multiprocessing
import multiprocessing.pool
import os
import signal
import sys
from collections.abc import Iterator

PR_SET_PDEATHSIG = 1
"""prctl option: the signal a process receives when its parent exits (Linux)."""
QUIET_TRACKER = "ignore:resource_tracker:UserWarning"
"""Warning filter of the resource tracker: a parent killed by SIGKILL cannot unregister its
semaphores, so the tracker removes them and would warn about "leaked" ones (two lines on the
user's terminal, for an exit that the user asked for)."""


def _die_with_parent(parent: int) -> None:
    """Worker initializer: SIGKILL when the parent exits; ignore Ctrl-C (the parent handles it)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if sys.platform.startswith("linux"):
        with contextlib.suppress(OSError, AttributeError):
            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(PR_SET_PDEATHSIG, signal.SIGKILL)
    if os.getppid() != parent:  # the parent died before the request took effect
        os._exit(1)


def usable_workers(requested: int, tasks: int) -> int:
    """Workers worth starting: at most the tasks and the CPUs, at least one."""
    return max(1, min(requested, tasks, os.cpu_count() or 1))


def _start_quiet_resource_tracker() -> None:
    """Start multiprocessing's resource tracker (if not running) with its leak warning off.

    The tracker is a separate interpreter that outlives a killed parent; it takes its warning
    filters from the environment it starts with, which is restored at once.
    """
    from multiprocessing import resource_tracker

    previous = os.environ.get("PYTHONWARNINGS")
    os.environ["PYTHONWARNINGS"] = ",".join(filter(None, [previous, QUIET_TRACKER]))
    try:
        resource_tracker.ensure_running()
    finally:
        if previous is None:
            del os.environ["PYTHONWARNINGS"]
        else:
            os.environ["PYTHONWARNINGS"] = previous


@contextlib.contextmanager
def process_pool(workers: int) -> Iterator[multiprocessing.pool.Pool]:
    """A process pool whose workers die with this process and stop at once on an exception.

    Use its ``imap`` for results in order as they finish. On any exception (Ctrl-C and
    SIGTERM included) the workers are terminated before the exception propagates.
    """
    _start_quiet_resource_tracker()
    pool = multiprocessing.get_context("spawn").Pool(
        processes=workers, initializer=_die_with_parent, initargs=(os.getpid(),)
    )
    try:
        yield pool
    except BaseException:
        pool.terminate()
        pool.join()
        raise
    pool.close()
    pool.join()
