"""The output folder of a check, tiled or not: one set of files, one writer per file.

``out`` gets the per-triangle rows (``table``, :data:`vorobound.tiling.rows.TABLES`),
sample.vtu, the gap histogram and summary.json, renamed into place together
(:func:`vorobound.files.write_set`) or not at all. A whole check writes its rows from memory;
the tiles of a tiled check write theirs into a hidden folder beside ``triangles`` while they
run, which becomes a Parquet dataset ``triangles/`` (one file per tile, readable by pyarrow,
pandas and dask) or is joined into one triangles.csv or triangles.npz (docs/scale.md, "Write").
"""

from __future__ import annotations

from collections.abc import Callable
from functools import partial
from pathlib import Path

import numpy as np

from ..files import discard_folder, ensure_folder, temporary_folder, write_set
from ..sampling.io.balls import fill_vtu
from ..sampling.io.columns import READABLE_PRECISION, columns_writer
from ..tiling.job import VTU_FLAGGED
from ..tiling.rows import guide_columns, join_parts, vtu_cells

SUMMARY = "summary.json"

Writers = dict[Path, Callable[[Path], None] | None]
"""Files of the set and their writers (None: a slot filled in before publishing)."""


class CheckOutputs:
    """The output folder of a check while it runs (a context manager).

    ``table`` is checked already (:func:`vorobound.reports.check.checked_table`). ``tiled``:
    the tiles write their rows into :attr:`parts` as they run. Leaving the block without
    :meth:`publish` removes that hidden folder.
    """

    def __init__(self, out: str | Path, table: str, tiled: bool = False):
        self.folder = Path(out)
        self.table = table
        self.tiled = tiled
        self.parts: Path | None = None

    def __enter__(self) -> CheckOutputs:
        self.folder = ensure_folder(self.folder)
        if self.tiled and self.table != "none":
            self.parts = temporary_folder(self.folder / "triangles")
        return self

    def __exit__(self, *exc) -> None:
        if self.parts is not None:
            discard_folder(self.parts)

    def writers(self, report) -> Writers:
        """The rows and sample.vtu of ``report`` (a tiled one's set lists summary.json first:
        its slot is None until :meth:`publish`)."""
        out: Writers = {}
        if self.tiled:
            out[self.folder / SUMMARY] = None
            vtu = report.run.vtu
            if vtu is not None and len(vtu.triples):
                out[self.folder / "sample.vtu"] = partial(_picked_vtu, report=report)
            if self.table in ("csv", "npz"):
                assert self.parts is not None
                path = self.folder / f"triangles.{self.table}"
                out[path] = partial(join_parts, self.parts, self.table)
            return out
        if self.table != "none":
            path = self.folder / f"triangles.{self.table}"
            out[path] = columns_writer(path, guide_columns(report.guides), READABLE_PRECISION)
        out[self.folder / "sample.vtu"] = partial(_whole_vtu, report=report)
        return out

    def folders(self) -> dict[Path, Path]:
        """Folders published with the files: a tiled check's Parquet dataset."""
        if self.tiled and self.table == "parquet" and self.parts is not None:
            return {self.folder / "triangles": self.parts}
        return {}

    def listed(self, writers: Writers) -> list[Path]:
        """What the result says it wrote: the files (so far) and the folders."""
        return [*writers, *self.folders()]

    def extra(self, report) -> dict:
        """More of the summary: a tiled check's ``rows``, where its rows went and how much of
        them the VTU shows."""
        if not self.tiled:
            return {}
        vtu = report.run.vtu
        shown = 0 if vtu is None else len(vtu.triples)
        return {
            "rows": {
                "table": self.table,
                "triangles": {
                    "parquet": "triangles/",
                    "csv": "triangles.csv",
                    "npz": "triangles.npz",
                }.get(self.table),
                "vtu_triangles": shown,
                "vtu_selection": (
                    "all guide triangles"
                    if shown == report.guides.count
                    else f"a uniform share of the guide triangles plus up to {VTU_FLAGGED} per "
                    "tile that break a bound or condition (decimated)"
                ),
            }
        }

    def publish(self, writers: Writers) -> list[Path]:
        """Write ``writers`` (every slot filled) and move the folders into place, as one set."""
        filled = {path: writer for path, writer in writers.items() if writer is not None}
        assert len(filled) == len(writers), "a slot of the output set was not filled"
        folders = self.folders()
        written = write_set(filled, folders)
        if folders:
            self.parts = None
        return written


def _whole_vtu(path: Path, report) -> None:
    """sample.vtu of a whole check: every ball (a vertex cell each) and guide triangle."""
    g = report.guides
    count = len(report.balls)
    blank = np.full(count, np.nan)
    cells = [("vertex", np.arange(count).reshape(-1, 1)), ("triangle", g.triples)]
    cell_data = {name: [blank, values] for name, values in vtu_cells(g).items()}
    point_data = {"radius": report.balls.radii, "lfs": report.lfs}
    fill_vtu(path, report.balls.centers, cells, point_data, cell_data)


def _picked_vtu(path: Path, report) -> None:
    """sample.vtu of a tiled check: the guide triangles its tiles picked, with the balls they
    use and their indices in the whole set."""
    vtu = report.run.vtu
    ids, first = np.unique(vtu.triples.ravel(), return_index=True)
    radii = vtu.radii.ravel()[first]
    point_data = {
        "radius": radii,
        "lfs": radii / report.params.delta,
        "ball_index": ids.astype(float),
    }
    cells = [("triangle", np.searchsorted(ids, vtu.triples))]
    cell_data = {name: [values] for name, values in vtu.cells.items()}
    fill_vtu(path, vtu.centers.reshape(-1, 3)[first], cells, point_data, cell_data)
