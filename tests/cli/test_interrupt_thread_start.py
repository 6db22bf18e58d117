"""Ctrl-C while scipy's k-d tree is starting its worker threads (found by hand on
``sample --mesh --workers 2``: exit 70, "internal error: RuntimeError: cannot join thread
before it is started", and a KeyError traceback of the half-started thread)."""

import threading
import time

from vorobound.cli import NATIVE_START_WAIT, _wait_for_native_workers


def _scipy_work():
    pass


_scipy_work.__module__ = "scipy.spatial._fake"  # what the interrupt handler waits for


def test_a_listed_but_unstarted_scipy_thread_does_not_break_the_interrupt():
    thread = threading.Thread(target=_scipy_work)
    # As threading.Thread.start leaves it between listing the thread and its system start.
    with threading._active_limbo_lock:
        threading._limbo[thread] = thread
    try:
        start = time.monotonic()
        _wait_for_native_workers()  # raised RuntimeError before
        assert time.monotonic() - start < NATIVE_START_WAIT + 1.0
    finally:
        with threading._active_limbo_lock:
            threading._limbo.pop(thread, None)


def test_a_started_scipy_thread_is_still_waited_for():
    done = threading.Event()

    def work():
        time.sleep(0.3)
        done.set()

    work.__module__ = "scipy.spatial._fake"
    thread = threading.Thread(target=work)
    thread.start()
    _wait_for_native_workers()
    assert done.is_set()
