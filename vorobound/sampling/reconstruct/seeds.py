"""Labelled seeds: the points whose Voronoi facets make M̂, each inside or outside the surface.

From balls, the seeds are the two seeds of every guide triangle (optionally also the one
uncovered seed of each half-covered triple: then every vertex of the union of balls' boundary
is a seed). From a file, they are the rows of VoroCrust's seed CSV: x, y, z, sizing, region id
(0 outside, 1 inside), with or without a header line; with a header the columns are found by
name (x, y, z and ``region_id`` or ``region``) and the others are ignored.

References
----------
The seeds and guide triangles of Section 4.1.
"""

from __future__ import annotations

import io
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...errors import ReadError
from ..balls import LENGTH_RANGE, Balls
from ..guides.seeds import SeededTriangles

MIN_SEEDS = 5
"""Fewer seeds have no Delaunay tetrahedralization (and a surface needs more)."""
REGION_NAMES = ("region_id", "region")
"""Header names of VoroCrust's region column, in the order they are looked for."""
SEED_COLUMNS = ("x", "y", "z", "sizing", "region_id")
"""The columns of VoroCrust's seed file, as :func:`seed_table` writes them."""


@dataclass(frozen=True)
class Seeds:
    """Seeds with their inside/outside label."""

    points: np.ndarray
    """(n, 3) seed positions."""
    inside: np.ndarray
    """(n,) True for a seed inside the surface (VoroCrust's region id 1)."""
    sizing: np.ndarray
    """(n,) VoroCrust's sizing column: for seeds made here, the smallest radius of the three
    balls the seed lies on."""
    triangle: np.ndarray
    """(n,) index into ``triples`` of the triple the seed belongs to (-1: read from a file)."""
    triples: np.ndarray
    """(m, 3) ball indices of the triples the seeds come from (empty for a file)."""
    labels: str
    """Where the labels come from: surface, sheets or file."""
    source: str

    def __len__(self) -> int:
        return len(self.points)


@dataclass(frozen=True)
class UnlabelledSeeds:
    """Seeds of ball triples before they are labelled."""

    points: np.ndarray
    sizing: np.ndarray
    triangle: np.ndarray
    """(n,) index into ``triples``."""
    side: np.ndarray
    """(n,) 0 or 1: which of the triple's two seeds (the order of ``SeededTriangles.seeds``)."""
    rows: np.ndarray
    """(n,) the row of the seed's triple in the ``SeededTriangles`` it came from."""
    triples: np.ndarray

    def labelled(self, inside: np.ndarray, labels: str, source: str) -> Seeds:
        return Seeds(self.points, inside, self.sizing, self.triangle, self.triples, labels, source)


def triangle_seeds(
    balls: Balls, seeded: SeededTriangles, half_covered: bool = False
) -> UnlabelledSeeds:
    """Both seeds of every guide triangle of ``seeded`` (and, with ``half_covered``, the
    uncovered seed of every half-covered triple).

    References
    ----------
    Eq. (2), (5); the guide triangles of Section 4.1.
    """
    keep = seeded.uncovered if half_covered else seeded.guide[:, None] & seeded.uncovered
    row, side = np.nonzero(keep)
    used, triangle = np.unique(row, return_inverse=True)
    triples = seeded.triples[used]
    return UnlabelledSeeds(
        points=seeded.seeds[row, side],
        sizing=balls.radii[triples].min(axis=1)[triangle],
        triangle=triangle,
        side=side,
        rows=row,
        triples=triples,
    )


def read_seed_file(path: str | Path) -> Seeds:
    """VoroCrust's seed CSV (module docstring), checked: finite values, labels 0 or 1, both
    labels present, distinct points, at least ``MIN_SEEDS`` rows.

    Raises
    ------
    ReadError
        With one line saying what is wrong and where.
    """
    path = Path(path)
    if not path.is_file():
        reason = "no such file" if not path.exists() else "not a regular file"
        raise ReadError(f"cannot read seeds {path}: {reason}")
    try:
        text = path.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as exc:
        reason = getattr(exc, "strerror", None) or "not UTF-8 text"
        raise ReadError(f"cannot read seeds {path}: {reason}") from None
    lines = [line for line in text.splitlines() if line.strip()]
    if not lines:
        raise ReadError(f"seeds {path} is empty")
    header = [cell.strip().lower() for cell in lines[0].split(",")]
    columns: list[int | None] = [0, 1, 2, 3, 4]
    if header[:3] == ["x1coord", "x2coord", "x3coord"]:
        lines = lines[1:]  # vc_mesh's own header names 4 of the 5 columns: x, y, z, sizing, region
        if not lines:
            raise ReadError(f"seeds {path}: a header and no rows")
    elif not _is_number(header[0]):
        region = next((name for name in REGION_NAMES if name in header), None)
        if not {"x", "y", "z"} <= set(header):
            raise ReadError(f"seeds {path}: the header must name x, y and z, got {lines[0]!r}")
        if region is None:
            raise ReadError(
                f"seeds {path}: no labels (the header names no region_id or region column)"
            )
        sizing = header.index("sizing") if "sizing" in header else None
        columns = [header.index("x"), header.index("y"), header.index("z"), sizing]
        columns.append(header.index(region))
        lines = lines[1:]
        if not lines:
            raise ReadError(f"seeds {path}: a header and no rows")
    try:
        table = np.loadtxt(io.StringIO("\n".join(lines)), delimiter=",", ndmin=2)
    except ValueError as exc:
        raise ReadError(f"seeds {path}: not a table of numbers ({exc})") from None
    width = table.shape[1]
    if columns == [0, 1, 2, 3, 4] and width < 5:
        raise ReadError(
            f"seeds {path}: no labels (rows have {width} columns; VoroCrust's seed file has "
            "x, y, z, sizing, region id)"
        )
    if width <= max(c for c in columns if c is not None):
        raise ReadError(
            f"seeds {path}: the header names {len(header)} columns but the rows have {width}"
        )
    return _checked(table, columns, path)


def _checked(table: np.ndarray, columns: list, path: Path) -> Seeds:
    where = f"seeds {path}"
    points = table[:, columns[:3]]
    region = table[:, columns[4]]
    sizing = table[:, columns[3]] if columns[3] is not None else np.full(len(table), np.nan)
    bad = np.flatnonzero(~np.isfinite(points).all(axis=1) | ~np.isfinite(region))
    if len(bad):
        raise ReadError(f"{where}: seed row {bad[0] + 1} is not finite ({len(bad)} such rows)")
    if len(points) and float(np.abs(points).max()) > LENGTH_RANGE[1]:
        raise ReadError(
            f"{where}: coordinates must lie within ±{LENGTH_RANGE[1]:g} (the supported range)"
        )
    bad = np.flatnonzero((region != 0) & (region != 1))
    if len(bad):
        raise ReadError(
            f"{where}: seed row {bad[0] + 1} has region id {region[bad[0]]:g}; expected 0 "
            f"(outside) or 1 (inside) ({len(bad)} such rows)"
        )
    if len(points) < MIN_SEEDS:
        raise ReadError(f"{where}: need at least {MIN_SEEDS} seeds, got {len(points)}")
    if float(np.ptp(points, axis=0).max()) < LENGTH_RANGE[0]:
        raise ReadError(
            f"{where}: the seeds span less than {LENGTH_RANGE[0]:g} (the supported range of "
            "lengths)"
        )
    inside = region == 1
    if inside.all() or not inside.any():
        only = "inside (1)" if inside.all() else "outside (0)"
        raise ReadError(
            f"{where}: every seed has the label {only}; M̂ lies between inside and outside seeds"
        )
    order = np.lexsort(points.T[::-1])
    same = np.flatnonzero((np.diff(points[order], axis=0) == 0).all(axis=1))
    if len(same):
        first, second = sorted((int(order[same[0]]), int(order[same[0] + 1])))
        raise ReadError(f"{where}: seed rows {first + 1} and {second + 1} are the same point")
    count = len(points)
    return Seeds(
        points=np.ascontiguousarray(points),
        inside=inside,
        sizing=sizing,
        triangle=np.full(count, -1),
        triples=np.empty((0, 3), dtype=np.int64),
        labels="file",
        source=path.name,
    )


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def seed_table(seeds: Seeds) -> tuple[list[str], np.ndarray]:
    """The columns and rows of VoroCrust's seed CSV for ``seeds`` (region id 1 inside)."""
    table = np.column_stack([seeds.points, seeds.sizing, seeds.inside.astype(float)])
    return list(SEED_COLUMNS), table
