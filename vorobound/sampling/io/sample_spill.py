"""Samples spilled to a binary file as they are made, read back a block at a time.

The streamed mesh sampler (:func:`vorobound.sampling.sampler.slabs.slab_sample` with a sink)
appends each finished block of samples (x, y, z, L as float64 rows) to a file in a temporary
folder; the sampling conditions are then measured block by block and the sample file is
written from the spill (:func:`vorobound.sampling.io.balls.write_balls_streamed`), so memory
holds a few blocks, not the sample.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...errors import WriteError

COLUMNS = 4
"""x, y, z, L per row."""


class SampleSpill:
    """A sink of sample blocks (call it with points (n, 3) and L (n,)) backed by a file."""

    def __init__(self, folder: str | Path):
        self.file = Path(folder) / "samples.f8"
        self.count = 0
        self.blocks: list[tuple[int, int]] = []
        self.lfs_min, self.lfs_max = np.inf, -np.inf
        try:
            self.handle = open(self.file, "wb")
        except OSError as exc:
            raise WriteError(f"cannot write {self.file}: {exc.strerror or exc}") from None

    def __call__(self, points: np.ndarray, lfs: np.ndarray) -> None:
        rows = np.column_stack([points, lfs]).astype("<f8")
        try:
            self.handle.write(rows.tobytes())
        except OSError as exc:
            raise WriteError(f"cannot write {self.file}: {exc.strerror or exc}") from None
        self.blocks.append((self.count, self.count + len(rows)))
        self.count += len(rows)
        if len(rows):
            self.lfs_min = min(self.lfs_min, float(lfs.min()))
            self.lfs_max = max(self.lfs_max, float(lfs.max()))

    def close(self) -> None:
        self.handle.close()

    def read(self, ids) -> tuple[np.ndarray, np.ndarray]:
        """(points, L) of the rows ``ids`` (a slice or indices) in memory. The file is mapped
        for this read only: pages of a mapping held open would count towards the process's
        memory until the whole spill had been read."""
        self.close()
        if not self.count:
            return np.zeros((0, 3)), np.zeros(0)
        table = np.memmap(self.file, dtype="<f8", mode="r", shape=(self.count, COLUMNS))
        rows = np.array(table[ids], dtype=float)
        del table
        return rows[:, :3], rows[:, 3]
