"""Row chunks of a batch, run on a pool of threads (the numpy and compiled kernels release
the GIL, so threads run them in parallel), and the number of threads a computation may use.

:func:`thread_count` is that number for every threaded step of the library (these thread
pools, every scipy k-d tree query: ``workers=thread_count()``): one per core, or
``VOROBOUND_THREADS`` when set, unless a caller set a budget with :func:`limited_threads`, as
the workers of a tiled check do (one thread each, since the processes themselves share the
cores).
"""

from __future__ import annotations

import contextlib
import contextvars
import os
from collections.abc import Callable, Iterator
from concurrent.futures import ThreadPoolExecutor

_BUDGET: contextvars.ContextVar[int | None] = contextvars.ContextVar("threads", default=None)


THREADS_VARIABLE = "VOROBOUND_THREADS"
"""Environment variable that caps the threads of every step (a positive integer)."""


def thread_count() -> int:
    """Threads a computation may use: the budget of :func:`limited_threads`, else
    ``VOROBOUND_THREADS``, else the cores."""
    budget = _BUDGET.get()
    if budget:
        return budget
    setting = os.environ.get(THREADS_VARIABLE, "").strip()
    if setting.isdigit() and int(setting) > 0:
        return int(setting)
    return os.cpu_count() or 1


@contextlib.contextmanager
def limited_threads(count: int) -> Iterator[None]:
    """Within the block (in this thread), :func:`thread_count` is ``count``."""
    token = _BUDGET.set(max(1, int(count)))
    try:
        yield
    finally:
        _BUDGET.reset(token)


def chunk_bounds(n_rows: int, rows_per_chunk: int) -> list[tuple[int, int]]:
    """(start, stop) of consecutive chunks covering ``range(n_rows)``."""
    return [(s, min(s + rows_per_chunk, n_rows)) for s in range(0, n_rows, rows_per_chunk)]


def run_in_threads(task: Callable[[tuple[int, int]], None], bounds: list[tuple[int, int]]) -> None:
    """Call ``task(bounds[i])`` for every chunk, on up to :func:`thread_count` threads."""
    workers = min(len(bounds), thread_count())
    if workers <= 1:
        for chunk in bounds:
            task(chunk)
        return
    with ThreadPoolExecutor(max_workers=workers) as pool:
        list(pool.map(task, bounds))
