"""The command line's progress bars: a rich display driven by the library's progress callback.

Library code reports ``(task, done, total)`` through :data:`vorobound.progress.Progress`; this
module is the only place that draws it (on stderr, so stdout stays clean for ``--json``).
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator

from ..progress import Progress, silent

PLAIN_SECONDS = 30.0
"""Without a terminal, a task's progress is printed as a line at most this often."""


def _lines() -> Progress:
    """A callback printing "progress: task done/total" on stderr, at most every
    ``PLAIN_SECONDS`` (the first line after that long)."""
    import sys
    import time

    last = [time.monotonic()]

    def report(task: str, done: int, total: int | None) -> None:
        now = time.monotonic()
        if now - last[0] < PLAIN_SECONDS:
            return
        last[0] = now
        amount = f"{done:,}" if total is None else f"{done:,}/{total:,}"
        print(f"progress: {task} {amount}", file=sys.stderr, flush=True)

    return report


@contextlib.contextmanager
def progress_bar(enabled: bool = True) -> Iterator[Progress]:
    """Yield a :data:`Progress` callback that draws one bar per task on stderr (or does nothing).

    Bars are drawn only when stderr is a terminal, and disappear when the block ends
    (``transient``), leaving only the command's output; a pipe or a file gets a plain line per
    task at most every ``PLAIN_SECONDS`` (none for a command that ends sooner).
    """
    if not enabled:
        yield silent
        return
    from rich.console import Console

    console = Console(stderr=True)
    if not console.is_terminal:
        yield _lines()
        return
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        TaskID,
        TextColumn,
        TimeElapsedColumn,
    )
    from rich.progress import (
        Progress as RichProgress,
    )

    columns = (
        TextColumn("{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
    )
    with RichProgress(*columns, console=console, transient=True) as bar:
        tasks: dict[str, TaskID] = {}

        def report(task: str, done: int, total: int | None) -> None:
            if task not in tasks:
                tasks[task] = bar.add_task(task, total=total)
            bar.update(tasks[task], completed=done, total=total)

        yield report
