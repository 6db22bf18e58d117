"""The output folder of a tiled check: per-tile rows published with the summary, a decimated
VTU and the figure as one set (docs/scale.md, "Write")."""

from __future__ import annotations

import json
import shutil
from collections.abc import Callable
from pathlib import Path

import numpy as np

from ..errors import InputError, WriteError
from ..files import discard_folder, ensure_folder, temporary_folder, write_set
from ..sampling.io.balls import pyarrow_available
from .tiled_report import TiledCheckReport

TABLES = ("parquet", "csv", "none")
"""How a tiled check writes its per-triangle rows."""


class TiledOutputs:
    """The output folder of a tiled check while it runs (a context manager).

    The tiles write their rows (``table``: ``parquet`` files, ``csv`` files, or ``none``) into
    a hidden folder beside ``triangles``; :meth:`publish` writes summary.json, the decimated
    sample.vtu and any extra files (the figure) and renames everything into place as one set:
    ``triangles/`` (a Parquet dataset, one file per tile, readable by pyarrow, pandas and dask)
    or ``triangles.csv``. Leaving the block without publishing removes the hidden folder.
    """

    def __init__(self, out: str | Path, table: str = "parquet"):
        if table not in TABLES:
            raise InputError(f"table: expected one of {', '.join(TABLES)}, got {table!r}")
        if table == "parquet" and not pyarrow_available():
            raise InputError(
                "Parquet rows need pyarrow (pip install 'vorobound[parquet]'); "
                "or write them as CSV (--table csv) or not at all (--table none)"
            )
        self.folder = Path(out)
        self.table = table
        self.parts: Path | None = None

    def __enter__(self) -> TiledOutputs:
        self.folder = ensure_folder(self.folder)
        self.parts = temporary_folder(self.folder / "triangles")
        return self

    def __exit__(self, *exc) -> None:
        if self.parts is not None:
            discard_folder(self.parts)

    def writers(self, report: TiledCheckReport) -> dict[Path, Callable[[Path], None]]:
        """summary.json, sample.vtu (when it has triangles) and triangles.csv (``csv``)."""
        summary = report.summary() | {"rows": self.rows(report)}
        text = json.dumps(summary, indent=2, allow_nan=False) + "\n"
        out = {self.folder / "summary.json": lambda path: path.write_text(text, "utf-8")}
        if report.vtu is not None and len(report.vtu.triples):
            out[self.folder / "sample.vtu"] = lambda path: _write_vtu(path, report)
        if self.table == "csv":
            out[self.folder / "triangles.csv"] = self._concatenate
        return out

    def publish(self, writers: dict[Path, Callable[[Path], None]]) -> list[Path]:
        """Write ``writers`` and move the rows into place, as one set."""
        folders = {self.folder / "triangles": self.parts} if self.table == "parquet" else {}
        written = write_set(writers, folders)
        self.parts = None if folders else self.parts
        return written

    def rows(self, report: TiledCheckReport) -> dict:
        """Where the rows went and how much of them the VTU shows (the summary's ``rows``)."""
        shown = 0 if report.vtu is None else len(report.vtu.triples)
        return {
            "table": self.table,
            "triangles": {"parquet": "triangles/", "csv": "triangles.csv"}.get(self.table),
            "vtu_triangles": shown,
            "vtu_selection": (
                "all guide triangles"
                if shown == report.guides.count
                else "a uniform share of the guide triangles plus up to 1000 per tile that "
                "break a bound or condition (decimated)"
            ),
        }

    def _concatenate(self, path: Path) -> None:
        """triangles.csv from the tiles' CSV files: one header, then every tile's rows."""
        parts = sorted(self.parts.glob("part-*.csv"))
        with open(path, "wb") as target:
            for index, part in enumerate(parts):
                with open(part, "rb") as source:
                    header = source.readline()
                    if index == 0:
                        target.write(header)
                    shutil.copyfileobj(source, target, 1 << 22)
        if not parts:
            raise WriteError(f"cannot write {path}: no tile wrote its rows")


def _write_vtu(path: Path, report: TiledCheckReport) -> None:
    from ..sampling.io.balls import fill_vtu

    v = report.vtu
    ids, first = np.unique(v.triples.ravel(), return_index=True)
    points = v.centers.reshape(-1, 3)[first]
    radii = v.radii.ravel()[first]
    cells = np.searchsorted(ids, v.triples)
    point_data = {
        "radius": radii,
        "lfs": radii / report.params.delta,
        "ball_index": ids.astype(float),
    }
    fill_vtu(path, points, [("triangle", cells)], point_data, {k: [c] for k, c in v.cells.items()})
