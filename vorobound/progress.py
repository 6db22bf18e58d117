"""The one progress mechanism of the library: a callback that long computations call.

A :data:`Progress` callback receives ``(task, done, total)``: the name of a stage, how many of
its steps are finished, and how many there are (``None`` when unknown). Library code never
draws anything; the command line passes a callback that drives a progress bar.
"""

from __future__ import annotations

from collections.abc import Callable

Progress = Callable[[str, int, "int | None"], None]


def silent(task: str, done: int, total: int | None) -> None:
    """The default callback: ignore progress."""


class Counter:
    """Counts the steps of one task and reports each to a :data:`Progress` callback."""

    def __init__(self, progress: Progress | None, task: str, total: int | None = None):
        self.progress = progress or silent
        self.task, self.total, self.done = task, total, 0
        self.progress(task, 0, total)

    def step(self, count: int = 1) -> None:
        self.done += count
        self.progress(self.task, self.done, self.total)
