"""The files of one reconstruction: M̂ as VTU and PLY, the seeds as VTU and as VoroCrust's
seed CSV, the JSON summary, and the data of the quality figure."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np

from ..sampling.reconstruct.facets import PolygonSurface
from ..sampling.reconstruct.seeds import seed_table
from .reconstruct import ReconstructReport

QUALITY_FIGURE_STEM = "quality"
"""File name (without extension) of the figure of the facet distributions."""


def facet_fields(report: ReconstructReport) -> dict[str, np.ndarray]:
    """Per-facet arrays of M̂ for the VTU (NaN where not measured)."""
    surface, m = report.facets.surface, report.measures
    count = surface.n_facets
    blank = np.full(count, np.nan)
    bad = np.zeros(count)
    bad[report.topology.bad_facets] = 1.0
    return {
        "facet": np.arange(count, dtype=float),
        "hausdorff_over_eps_lfs": blank if m is None else m.facet_distance,
        "normal_deviation_deg": blank if m is None else m.normal_deviation,
        "edge_ratio": report.quality.edge_ratio,
        "min_angle_deg": report.quality.min_angle,
        "area": report.quality.area,
        "nonmanifold": bad,
        "inside_seed": surface.seed_pairs[:, 0].astype(float),
        "outside_seed": surface.seed_pairs[:, 1].astype(float),
    }


def polygon_cells(
    surface: PolygonSurface, fields: dict[str, np.ndarray]
) -> tuple[list[tuple[str, np.ndarray]], dict[str, list[np.ndarray]]]:
    """meshio cell blocks (triangle, quad, polygon of each size) and the matching cell data."""
    sizes = surface.sizes
    cells: list[tuple[str, np.ndarray]] = []
    data: dict[str, list[np.ndarray]] = {name: [] for name in fields}
    for size in np.unique(sizes):
        chosen = np.flatnonzero(sizes == size)
        start = surface.offsets[chosen]
        block = surface.corners[start[:, None] + np.arange(size)].astype(np.int32)
        kind = {3: "triangle", 4: "quad"}.get(int(size), "polygon")
        cells.append((kind, block))
        for name, values in fields.items():
            data[name].append(values[chosen])
    return cells, data


def _write_mhat_vtu(path: Path, report: ReconstructReport) -> None:
    from ..sampling.io.balls import fill_vtu

    surface = report.facets.surface
    cells, data = polygon_cells(surface, facet_fields(report))
    fill_vtu(path, surface.vertices, cells, {}, data)


def _write_mhat_ply(path: Path, report: ReconstructReport) -> None:
    import meshio

    surface = report.facets.surface
    cells, _ = polygon_cells(surface, {})
    meshio.write(path, meshio.Mesh(surface.vertices, cells), file_format="ply")


def _write_seeds_vtu(path: Path, report: ReconstructReport) -> None:
    from ..sampling.io.balls import fill_vtu

    seeds = report.seeds
    cells = [("vertex", np.arange(len(seeds)).reshape(-1, 1))]
    point_data = {
        "region_id": seeds.inside.astype(float),
        "sizing": seeds.sizing,
        "triangle": seeds.triangle.astype(float),
    }
    fill_vtu(path, seeds.points, cells, point_data)


def _write_seeds_csv(path: Path, report: ReconstructReport) -> None:
    from ..sampling.io.columns import fill_csv

    names, table = seed_table(report.seeds)
    fill_csv(path, dict(zip(names, table.T, strict=True)))


def output_writers(report: ReconstructReport, out_dir: str | Path) -> dict[Path, Callable]:
    """Writers of mhat.vtu (ParaView; facet fields), mhat.ply, seeds.vtu (with region_id),
    seeds.csv (VoroCrust's seed format) and summary.json in ``out_dir``, for
    :func:`vorobound.files.write_set`. The quality figure (``QUALITY_FIGURE_STEM``) joins the
    set in the command line."""
    out = Path(out_dir)
    writers = {
        out / "mhat.vtu": lambda path: _write_mhat_vtu(path, report),
        out / "mhat.ply": lambda path: _write_mhat_ply(path, report),
        out / "seeds.vtu": lambda path: _write_seeds_vtu(path, report),
        out / "seeds.csv": lambda path: _write_seeds_csv(path, report),
    }
    return writers


def quality_distributions(report: ReconstructReport) -> dict[str, np.ndarray]:
    """The per-facet arrays the quality figure shows (label ↦ values)."""
    shown = {
        "shortest / longest edge": report.quality.edge_ratio,
        "smallest angle (°)": report.quality.min_angle,
    }
    if report.measures is not None:
        shown["distance to the surface / (εL)"] = report.measures.facet_distance
        shown["normal deviation (°)"] = report.measures.normal_deviation
    return shown
