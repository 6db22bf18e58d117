"""The per-triangle rows of a check: their columns (triangles.csv), the cell values of the
VTU, the two sinks the pipeline (:func:`vorobound.tiling.job.check_part`) hands its rows to,
and the part files a tile writes and the driver joins into one table.

Every check writes its rows through these functions, tiled or not, so a column means the same
in each of them: a tile's sink (:class:`PartFiles`) writes them as a part file while the
check runs; a whole check's (:class:`InMemory`) keeps them, and the output set
(:class:`vorobound.reports.check_outputs.CheckOutputs`) writes them as one file with the rest.

References
----------
Theorem 1, eq. (29), (33)–(36), (54)–(55) and property H3 of Section 4.1.
"""

from __future__ import annotations

import shutil
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import WriteError
from ..sampling.guides.measure import GuideMeasurements
from ..sampling.io.columns import FILLERS, READABLE_PRECISION, fill_npz

TABLES = ("parquet", "npz", "csv", "none")
"""How a check's ``out`` holds the per-triangle rows: Parquet (one file, or a dataset
``triangles/`` of one file per tile), NPZ (one compressed file, the compact default without
pyarrow), CSV (10 significant digits) or not at all."""


def guide_columns(g: GuideMeasurements, triples: np.ndarray | None = None) -> dict:
    """The columns of triangles.csv for measured guide triangles; ``triples`` replaces their
    ball indices (a tile's rows carry the indices of the whole set)."""
    triples = g.triples if triples is None else triples
    columns = {
        "a_index": triples[:, 0],
        "b_index": triples[:, 1],
        "c_index": triples[:, 2],
        "lfs_i": g.lfs[:, 0],
        "lfs_j": g.lfs[:, 1],
        "lfs_k": g.lfs[:, 2],
        "circumradius": g.circumradius,
        "orthoradius_sq": g.orthoradius_sq,
        "radius_gap": g.radius_gap,
        "rho": g.rho,
        "gap_ratio": g.gap_ratio,
        "quality_ratio": g.quality_ratio,
        "h3_ratio": g.h3_ratio,
        "a_over_eps_lfs": g.edges[:, 0],
        "b_over_eps_lfs": g.edges[:, 1],
        "c_over_eps_lfs": g.edges[:, 2],
        "sin_theta": g.sin_theta,
        "inside": g.inside.astype(np.int64),
        "feature_reach": np.full(len(g), np.inf) if g.feature_reach is None else g.feature_reach,
        "at_feature": g.at_feature.astype(np.int64),
    }
    for name, rows in g.violated.items():
        columns[f"breaks_{name}"] = rows.astype(np.int64)
    for mode, rows in g.exceeds.items():
        columns[f"exceeds_{mode}"] = rows.astype(np.int64)
    for mode, rows in (g.exceeds_ratio or {}).items():
        columns[f"exceeds_ratio_{mode}"] = rows.astype(np.int64)
    return columns


@dataclass(frozen=True)
class PartRows:
    """A part's rows as the pipeline hands them to its sink: the measured guide triangles
    (local ball indices), the balls' indices in the whole set and the triangles'
    circumcenters (a whole check's coverage stage probes the surface there)."""

    tile: int
    ids: np.ndarray
    guides: GuideMeasurements
    circumcenters: np.ndarray | None


@dataclass(frozen=True)
class InMemory:
    """The sink of a whole check: its rows stay in memory."""

    def take(self, rows: PartRows) -> PartRows:
        return rows


@dataclass(frozen=True)
class PartFiles:
    """The sink of a tiled check: each tile's rows (global ball indices) as one part file in
    ``folder`` (``table``: parquet, npz or csv)."""

    folder: str
    table: str

    def take(self, rows: PartRows) -> None:
        columns = guide_columns(rows.guides, rows.ids[rows.guides.triples])
        try:
            write_part(part_path(self.folder, rows.tile, self.table), columns)
        except OSError as exc:
            raise WriteError(
                f"cannot write the rows of tile {rows.tile} into {self.folder}: "
                f"{exc.strerror or exc} (on a cluster the output folder must be on a file "
                "system its workers share)"
            ) from None


def vtu_cells(g: GuideMeasurements, rows: np.ndarray | None = None) -> dict[str, np.ndarray]:
    """The cell values of sample.vtu for the guide triangles ``rows`` (default: all)."""
    pick = slice(None) if rows is None else rows
    quality = g.quality_ratio[pick]
    return {
        "rho": g.rho[pick],
        "gap_ratio": g.gap_ratio[pick],
        "quality_ratio": np.where(np.isfinite(quality), quality, np.nan),
        "h3_ratio": g.h3_ratio[pick],
        "inside_constraint_set": g.inside[pick].astype(float),
        "at_feature": g.at_feature[pick].astype(float),
    }


def part_path(folder: str | Path, tile: int, table: str) -> Path:
    """The file of one tile's rows."""
    return Path(folder) / f"part-{tile:05d}.{table}"


def write_part(path: Path, columns: dict[str, np.ndarray]) -> None:
    """One tile's rows in the format of ``path``'s suffix (as an untiled check writes them)."""
    FILLERS[path.suffix](path, columns, READABLE_PRECISION)


def join_parts(parts: Path, table: str, path: Path) -> None:
    """One table at ``path`` from the tiles' part files (``csv``: one header, then every
    tile's rows; ``npz``: each column concatenated over the tiles, in the driver's memory)."""
    files = sorted(parts.glob(f"part-*.{table}"))
    if not files:
        raise WriteError(f"cannot write {path}: no tile wrote its rows")
    if table == "npz":
        loaded = [np.load(f) for f in files]
        names = loaded[0].files
        fill_npz(path, {name: np.concatenate([part[name] for part in loaded]) for name in names})
        return
    with open(path, "wb") as target:
        for index, part in enumerate(files):
            with open(part, "rb") as source:
                header = source.readline()
                if index == 0:
                    target.write(header)
                shutil.copyfileobj(source, target, 1 << 22)
