"""Worker processes that never outlive their parent, and one executor interface for tasks.

Pools start workers with the ``spawn`` method (no inherited threads or locks), each worker
asks the kernel to kill it when its parent dies (Linux ``PR_SET_PDEATHSIG``), and leaving the
pool's block on an exception (Ctrl-C included) terminates the workers at once instead of
waiting for their current task. A worker's start is shielded from Ctrl-C and SIGTERM (the
signal is handled the moment the worker exists and is known to its pool): a start cut short
would leave a child waiting for its instructions, which prints a traceback when the parent
exits. If the parent is killed outright, multiprocessing's resource tracker still removes the
pool's semaphores, without its "leaked semaphore" warning.
:func:`task_executor` gives the same ``concurrent.futures`` interface over this process, such
a pool, or a dask.distributed cluster.
"""

from __future__ import annotations

import concurrent.futures
import concurrent.futures.process
import contextlib
import contextvars
import ctypes
import functools
import multiprocessing
import multiprocessing.context
import multiprocessing.pool
import os
import signal
import sys
import threading
from collections.abc import Callable, Iterator

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


@contextlib.contextmanager
def _signals_deferred() -> Iterator[None]:
    """Hold SIGINT and SIGTERM while the block runs (main thread only; elsewhere nothing to
    do, Python runs signal handlers in the main thread) and deliver the first one caught, to
    the handlers in place before, once it is done."""
    held = (signal.SIGINT, signal.SIGTERM)
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    caught: list[int] = []
    previous = {}
    for sig in held:
        old = signal.getsignal(sig)
        if old is None:  # set outside Python: cannot be restored, leave it
            continue
        previous[sig] = old
        signal.signal(sig, lambda signum, frame: caught.append(signum))
    try:
        yield
    finally:
        for sig, old in previous.items():
            signal.signal(sig, old)
        if caught:
            signal.raise_signal(caught[0])


signals_deferred = _signals_deferred
"""Hold SIGINT and SIGTERM while a block runs, then deliver the first one caught (for cleanups
that an interrupt must not cut short)."""


class _ShieldedProcess(multiprocessing.context.SpawnProcess):
    """A spawned worker whose start Ctrl-C and SIGTERM cannot cut short (they are handled
    when ``start`` returns), recorded for the pool being built in this thread."""

    def start(self) -> None:
        with _signals_deferred():
            super().start()
            owner = _STARTING.get(None)
            if owner is not None:
                owner.append(self)


class _ShieldedSpawnContext(multiprocessing.context.SpawnContext):
    Process = _ShieldedProcess


_STARTING: contextvars.ContextVar[list] = contextvars.ContextVar("vorobound_pool_workers")
"""The list that records the workers started by the pool being used in this context."""


@contextlib.contextmanager
def _recorded_workers() -> Iterator[list]:
    """The workers started in this context while the block runs (a pool's own threads start
    replacements that the pool itself stops)."""
    started: list = []
    token = _STARTING.set(started)
    try:
        yield started
    finally:
        # A pool used inside a generator may be closed from another context.
        with contextlib.suppress(ValueError, RuntimeError):
            _STARTING.reset(token)


def _kill_started(started: list) -> None:
    """SIGKILL and reap the workers that are still alive."""
    for process in started:
        with contextlib.suppress(OSError, ValueError, AttributeError):
            if process.is_alive():
                process.kill()
    for process in started:
        with contextlib.suppress(OSError, ValueError, AttributeError, AssertionError):
            process.join(5)


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
    with _recorded_workers() as started:
        pool = None
        try:
            # An interrupt while the pool is being built is handled once it is built (and
            # known here): a pool left half-built keeps a thread that restarts its workers.
            with _signals_deferred():
                pool = _ShieldedSpawnContext().Pool(
                    processes=workers, initializer=_die_with_parent, initargs=(os.getpid(),)
                )
            yield pool
        except BaseException:
            # The pool stops its own thread that replaces workers before it stops them (killing
            # them first would have it start new ones); workers started before an interrupt
            # inside Pool() are known only to `started`.
            if pool is not None:
                _bounded(functools.partial(_stop, pool))
            _kill_started(started)
            raise
    pool.close()
    pool.join()


# --- One executor interface for tasks: in process, a local process pool, or a dask cluster ----


class InlineExecutor(concurrent.futures.Executor):
    """Runs each task at once in this process (one worker: no start-up, no copies)."""

    def submit(self, fn, /, *args, **kwargs) -> concurrent.futures.Future:
        future: concurrent.futures.Future = concurrent.futures.Future()
        try:
            future.set_result(fn(*args, **kwargs))
        except Exception as exc:  # Ctrl-C and other BaseExceptions propagate at once
            future.set_exception(exc)
        return future


@contextlib.contextmanager
def task_executor(
    workers: int = 1, scheduler: str | None = None
) -> Iterator[tuple[concurrent.futures.Executor, int]]:
    """A ``concurrent.futures`` executor for independent tasks, and how many run at once.

    * ``scheduler`` (an address such as ``tcp://127.0.0.1:8786``): a dask.distributed cluster,
      through its ``concurrent.futures`` interface (``Client.get_executor``); needs the
      ``dask`` extra. Its workers are the cluster's.
    * else ``workers`` > 1: a process pool of spawned workers (at most one per CPU; the
      number returned is still ``workers``) that die with this process
      (:func:`_die_with_parent`); leaving the block on an exception (Ctrl-C included) kills
      them at once.
    * else: :class:`InlineExecutor`.

    A worker that dies (killed, out of memory) makes its task's ``result()`` raise; see
    :func:`task_result`.
    """
    if scheduler is not None:
        with _dask_logs_quiet(), _dask_executor(scheduler) as found:
            yield found
        return
    if workers <= 1:
        yield InlineExecutor(), 1
        return
    pool = concurrent.futures.ProcessPoolExecutor(
        # More processes than CPUs would only share them (and each holds a task's memory).
        max_workers=min(workers, os.cpu_count() or 1),
        mp_context=_ShieldedSpawnContext(),
        initializer=_die_with_parent,
        initargs=(os.getpid(),),
    )
    with _recorded_workers() as started:
        try:
            yield pool, workers
        except BaseException:
            # The pool starts workers as tasks are submitted: one started just before an
            # interrupt may not be in its table yet, but is in `started`.
            _kill_pool(pool, started)
            raise
    pool.shutdown(wait=True)


def _kill_pool(pool: concurrent.futures.ProcessPoolExecutor, started: list) -> None:
    """Stop a process pool now: kill its workers (those in its table and those ``started``
    but not yet in it) rather than wait for their tasks."""
    table = list((getattr(pool, "_processes", None) or {}).values())
    _kill_started(table + [p for p in started if p not in table])
    # The pool's feeder thread may be blocked writing a task into a pipe no worker reads any
    # more; multiprocessing joins that thread at exit (unbounded), so the process would never
    # end (a Ctrl-C that hung CI for 120 s). It is not waited for.
    calls = getattr(pool, "_call_queue", None)
    if calls is not None:
        with contextlib.suppress(Exception):
            calls.cancel_join_thread()
    # With its workers gone the pool's manager thread ends at once; waiting for it releases
    # the pool's semaphores before this process exits (else the resource tracker warns). A
    # worker killed while it sent a result can leave that thread waiting for ever (a hang of
    # over 13 minutes after Ctrl-C, issue 34): the wait is bounded.
    _bounded(lambda: pool.shutdown(wait=True, cancel_futures=True))


SHUTDOWN_SECONDS = 10
"""The longest wait for a pool to stop once its workers are killed (Ctrl-C, an error)."""


def _stop(pool: multiprocessing.pool.Pool) -> None:
    pool.terminate()
    pool.join()


def _bounded(call: Callable[[], object]) -> bool:
    """Run ``call`` in a daemon thread for at most :data:`SHUTDOWN_SECONDS`; whether it ended
    (a stop that hangs is left behind: its workers are dead, the process is leaving)."""
    thread = threading.Thread(target=call, name="vorobound-pool-stop", daemon=True)
    thread.start()
    thread.join(SHUTDOWN_SECONDS)
    return not thread.is_alive()


@contextlib.contextmanager
def _dask_executor(address: str) -> Iterator[tuple[concurrent.futures.Executor, int]]:
    from .errors import WorkerError

    patience = _worker_seconds()
    client = _dask_client(address)
    try:
        try:
            client.wait_for_workers(1, timeout=patience)
        except (TimeoutError, OSError) as exc:
            raise WorkerError(
                f"the dask cluster at {address} has no workers (waited {patience:g} "
                f"s: {type(exc).__name__}); start some with dask worker {address}"
            ) from None
        executor = client.get_executor(pure=False)
        slots = max(1, sum(client.nthreads().values()))
        watch = _WorkerWatch(client, executor, address, patience)
        try:
            yield executor, slots
        except BaseException:
            watch.stop()
            executor.shutdown(wait=False)
            raise
        watch.stop()
        executor.shutdown(wait=True)
    finally:
        with contextlib.suppress(Exception):
            client.close(timeout=DASK_CONNECT_SECONDS)
        _LOST.clear()


def reachable_scheduler(address: str) -> None:
    """Connect to the dask scheduler at ``address`` and let go at once, or a WorkerError: a
    command that spends minutes before it needs the cluster (the L estimate of ``sample
    --mesh``) calls this first, so a dead address is told in seconds, not after the work."""
    with _dask_logs_quiet():
        client = _dask_client(address)
        with contextlib.suppress(Exception):
            client.close(timeout=DASK_CONNECT_SECONDS)


_LOST: list[str] = []
"""Why the running dask computation was given up (set by :class:`_WorkerWatch`), for the
message of :func:`task_result`."""


class _WorkerWatch:
    """Cancels a dask computation whose cluster has had no worker for
    ``patience`` seconds (:data:`DASK_WORKER_SECONDS`): dask itself would wait for ever for a
    worker to come back (issue 34: a run whose only worker was killed never ended)."""

    def __init__(self, client, executor, address: str, patience: float, poll: float = 1.0):
        self.client, self.executor, self.address = client, executor, address
        self.patience, self.poll = patience, min(poll, patience / 4)
        self.done = threading.Event()
        self.thread = threading.Thread(target=self._run, name="vorobound-dask-watch", daemon=True)
        self.thread.start()

    def stop(self) -> None:
        self.done.set()

    def _run(self) -> None:
        import time

        without: float | None = None
        while not self.done.wait(self.poll):
            try:
                workers = len(self.client.scheduler_info().get("workers", {}))
            except Exception:  # the client is closing or reconnecting: dask reports that
                continue
            if workers:
                without = None
                continue
            now = time.monotonic()
            without = now if without is None else without
            if now - without >= self.patience:
                _LOST.append(
                    f"the dask cluster at {self.address} has had no worker for {self.patience:g} s"
                )
                with contextlib.suppress(Exception):
                    self.client.cancel(list(getattr(self.executor, "_futures", ())))
                return


@contextlib.contextmanager
def _dask_logs_quiet() -> Iterator[None]:
    """dask.distributed's own log lines (a lost scheduler prints a 30-line traceback as it tries
    to reconnect) are silenced: the run reports the failure in one line of its own."""
    import logging

    with contextlib.suppress(ImportError):
        import distributed  # noqa: F401 (its import configures its loggers: before, not after)
    # dask's configuration gives some of its loggers levels of their own (distributed.client).
    names = ["distributed"] + [
        name for name in list(logging.root.manager.loggerDict) if name.startswith("distributed.")
    ]
    loggers = [logging.getLogger(name) for name in names]
    levels = [logger.level for logger in loggers]
    for logger in loggers:
        logger.setLevel(logging.CRITICAL + 1)
    try:
        yield
    finally:
        for logger, level in zip(loggers, levels, strict=True):
            logger.setLevel(level)


def _dask_client(address: str):
    """A dask.distributed client of the scheduler at ``address``, connected within
    :data:`DASK_CONNECT_SECONDS` (plus a grace second) or a WorkerError: dask's own timeout
    does not cover a listener that accepts the connection and never answers its handshake
    (issue 34: a hang of over 300 s), so the connection is made in a thread and given up on."""
    from .errors import InputError, WorkerError

    try:
        from distributed import Client
    except ImportError:
        raise InputError(
            "--scheduler needs dask.distributed: pip install 'vorobound[dask]'"
        ) from None
    found: dict = {}

    def connect() -> None:
        try:
            found["client"] = Client(address, timeout=DASK_CONNECT_SECONDS, set_as_default=False)
        except BaseException as exc:  # handed to the caller
            found["error"] = exc
            _quiet_del(exc)

    thread = threading.Thread(target=connect, name="vorobound-dask-connect", daemon=True)
    thread.start()
    thread.join(DASK_CONNECT_SECONDS + 1)
    if thread.is_alive():
        raise WorkerError(
            f"cannot reach the dask scheduler at {address}: no dask scheduler answered within "
            f"{DASK_CONNECT_SECONDS:g} s (is another program listening there?)"
        )
    exc = found.get("error")
    if exc is None:
        return found["client"]
    if isinstance(exc, OSError | TimeoutError | ValueError | TypeError):
        reason = " ".join(str(exc).split()) or type(exc).__name__
        raise WorkerError(f"cannot reach the dask scheduler at {address}: {reason}") from None
    raise exc


def _quiet_del(exc: BaseException) -> None:
    """Let a client whose construction failed be collected without its ``__del__`` waiting
    for and then printing a traceback (``--scheduler foo``: a 20 s wait, then 9 lines): the
    half-built client is reachable from the traceback's frames, whose ``self`` is cleared."""
    traceback = exc.__traceback__
    while traceback is not None:
        client = traceback.tb_frame.f_locals.get("self")
        if client is not None and type(client).__name__ == "Client":
            with contextlib.suppress(Exception):
                client.status = "closed"  # __del__ then has nothing to close
        traceback = traceback.tb_next


DASK_CONNECT_SECONDS = 10
"""How long to wait for a dask scheduler to answer."""
DASK_WORKER_SECONDS = 30.0
"""How long to wait for a dask cluster's first worker, and for one to come back when it has
lost them all mid-run; the environment variable :data:`DASK_WORKER_VARIABLE` overrides it."""
DASK_WORKER_VARIABLE = "VOROBOUND_DASK_WORKER_SECONDS"


def _worker_seconds() -> float:
    """:data:`DASK_WORKER_SECONDS`, or the positive number of seconds the environment gives."""
    from .errors import InputError

    text = os.environ.get(DASK_WORKER_VARIABLE)
    if text is None:
        return DASK_WORKER_SECONDS
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not 0 < value < 1e6:
        raise InputError(f"{DASK_WORKER_VARIABLE}={text!r}: give a number of seconds in (0, 1e6)")
    return value


def task_result(future: concurrent.futures.Future, what: str):
    """``future.result()``, with a lost worker (killed, out of memory, a dask worker that died
    ``allowed-failures`` times) turned into one :class:`~vorobound.errors.WorkerError` naming
    ``what`` (the task)."""
    from .errors import WorkerError

    try:
        return future.result()
    except concurrent.futures.CancelledError:  # a dask scheduler or worker gone mid-run
        if _LOST:
            raise WorkerError(f"{_LOST[0]}: {what} was given up; nothing was written") from None
        raise WorkerError(
            f"the computation of {what} was cancelled (the dask scheduler or its workers went "
            "away?); nothing was written"
        ) from None
    except concurrent.futures.process.BrokenProcessPool:
        raise WorkerError(
            f"a worker process died while computing {what} (killed, or out of memory?); "
            "nothing was written"
        ) from None
    except Exception as exc:
        if type(exc).__name__ in ("KilledWorker", "CommClosedError", "FutureCancelledError"):
            raise WorkerError(
                f"the dask cluster lost {what} ({type(exc).__name__}: "
                f"{' '.join(str(exc).split())}); nothing was written"
            ) from None
        raise
