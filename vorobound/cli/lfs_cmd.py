"""``vorobound lfs``: estimate the local feature size L at the vertices of a triangle mesh."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Annotated

import typer

from .options import Json, Seed
from .progress import progress_bar
from .render import fmt, print_json, print_table


def lfs(
    mesh: Annotated[
        Path, typer.Argument(help="Triangle mesh (STL, OBJ, PLY, OFF, VTK, VTU, ...).")
    ],
    output: Annotated[
        list[Path] | None,
        typer.Option(
            "-o",
            "--output",
            metavar="FILE",
            help="Write L per vertex: .csv (x,y,z,lfs; what --sizing reads) or .vtu (the mesh "
            "with point data lfs and sharp, for ParaView). Repeat for both.",
        ),
    ] = None,
    samples: Annotated[
        int | None,
        typer.Option(
            "--samples",
            metavar="N",
            help="Size of the surface sample the medial axis is estimated from: every vertex, "
            "plus up to N − (vertices) edge midpoints placed on a smooth quartic fit of the "
            "surface (longest edges first, at most one per edge, none next to sharp, boundary "
            "or non-manifold edges). 0: the vertices only. Default: every edge gets a midpoint "
            "if the sample then has at most 60000 points (meshes of up to about 15 000 "
            "vertices; more accurate, several times slower), else none (docs/lfs.md).",
        ),
    ] = None,
    lipschitz: Annotated[
        float,
        typer.Option(
            "--lipschitz",
            help="λ in [1e-12, 1e6]: make L λ-Lipschitz, L(x) ← min_y L(y) + λ|x − y|. The "
            "distance to the medial axis is already 1-Lipschitz; λ < 1 lowers it (a gentler "
            "sizing field).",
        ),
    ] = 1.0,
    sharp_angle: Annotated[
        float,
        typer.Option(
            "--sharp-angle",
            help="Edges whose face normals differ by more than this many degrees are sharp "
            "(reported; the paper's analysis covers smooth surfaces only).",
        ),
    ] = 30.0,
    seed: Seed = 0,
    as_json: Json = False,
) -> None:
    """Local feature size L (distance to the medial axis) at every vertex of a mesh.

    L is the distance to the Voronoi poles (Amenta-Bern) of a surface sample: the vertices and
    edge midpoints placed on a quartic fit of the surface (--samples). It estimates the smooth
    surface's L, accurately when the vertices lie on that surface and are dense compared with L
    (docs/lfs.md). Warnings name what limits it: sharp edges, an open or non-manifold mesh,
    degenerate faces, edges long compared with L.
    """
    import numpy as np

    from ..checks import checked_seed
    from ..files import write_set
    from ..sampling.lfs import estimate_lfs
    from ..sampling.lfs_io import checked_lfs_output, lfs_writers
    from ..sampling.mesh_io import read_triangle_mesh

    seed = checked_seed(seed)
    outputs = [checked_lfs_output(path) for path in output or []]
    start = time.perf_counter()
    triangle_mesh = read_triangle_mesh(mesh)
    with progress_bar(not as_json) as progress:
        options = {} if samples is None else {"samples": samples}
        estimate = estimate_lfs(
            triangle_mesh,
            lipschitz=lipschitz,
            sharp_angle=sharp_angle,
            seed=seed,
            progress=progress,
            **options,
        )
    seconds = time.perf_counter() - start
    written = [str(path) for path in write_set(lfs_writers(outputs, estimate))]
    values = estimate.lfs
    report = estimate.mesh_report
    payload = {
        "mesh": str(mesh),
        "method": estimate.method,
        "vertices": len(triangle_mesh.points),
        "triangles": len(triangle_mesh.triangles),
        "samples": estimate.sample_count,
        "added_samples": estimate.added_samples,
        "medial_points": len(estimate.medial_points),
        "lipschitz": estimate.lipschitz,
        "lfs_min": float(values.min()),
        "lfs_median": float(np.median(values)),
        "lfs_max": float(values.max()),
        "sharp_angle": estimate.sharp_angle,
        "sharp_edges": len(estimate.sharp_edges),
        "max_dihedral": estimate.max_dihedral,
        "boundary_edges": report.boundary_edges,
        "nonmanifold_edges": report.nonmanifold_edges,
        "degenerate_triangles": report.degenerate_triangles,
        "duplicate_vertices": report.duplicate_vertices,
        "warnings": list(estimate.warnings),
        "written": written,
        "seconds": seconds,
    }
    if as_json:
        print_json(payload)
        return
    rows = [
        ("vertices / triangles", f"{payload['vertices']:,} / {payload['triangles']:,}"),
        (
            "surface sample",
            f"{estimate.sample_count:,} ({estimate.added_samples:,} fitted edge midpoints)",
        ),
        ("medial-axis points (poles)", f"{payload['medial_points']:,}"),
        (
            "L min / median / max",
            " / ".join(fmt(payload[k], 6) for k in ("lfs_min", "lfs_median", "lfs_max")),
        ),
        ("Lipschitz constant", fmt(estimate.lipschitz)),
        (f"sharp edges (> {sharp_angle:g}°)", f"{payload['sharp_edges']:,}"),
        ("largest dihedral angle", f"{estimate.max_dihedral:.1f}°"),
        ("time", f"{seconds:.2f} s"),
    ]
    rows += [("written", path) for path in written]
    print_table(f"Local feature size of {mesh.name}", ("quantity", "value"), rows)
    print(f"method: {estimate.method}; estimate (numerical), not a certified bound")
