"""Row chunks of a batch, run on a pool of threads (the numpy and compiled kernels release
the GIL, so threads run them in parallel)."""

from __future__ import annotations

import os
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor


def chunk_bounds(n_rows: int, rows_per_chunk: int) -> list[tuple[int, int]]:
    """(start, stop) of consecutive chunks covering ``range(n_rows)``."""
    return [(s, min(s + rows_per_chunk, n_rows)) for s in range(0, n_rows, rows_per_chunk)]


def run_in_threads(task: Callable[[tuple[int, int]], None], bounds: list[tuple[int, int]]) -> None:
    """Call ``task(bounds[i])`` for every chunk, on up to one thread per core."""
    if len(bounds) <= 1:
        for chunk in bounds:
            task(chunk)
        return
    with ThreadPoolExecutor(max_workers=min(len(bounds), os.cpu_count() or 1)) as pool:
        list(pool.map(task, bounds))
