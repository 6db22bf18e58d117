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
            help="Vertex part of the pole sample of the curved patches: their vertices, plus "
            "up to N − (vertices) edge midpoints placed on a smooth quartic fit (longest edges "
            "first, none on feature edges). 0: no midpoints. Default: every edge gets one if "
            "that makes at most 60000 points, else none. Face sites, thickness and feature "
            "terms do not depend on it (docs/lfs.md).",
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
            help="Edges whose face normals differ by more than this many degrees are sharp: "
            "they split the surface into smooth patches, and L is that of the piecewise-smooth "
            "surface (docs/lfs.md).",
        ),
    ] = 30.0,
    seed: Seed = 0,
    as_json: Json = False,
) -> None:
    """Local feature size L of the piecewise-smooth surface a mesh describes, at every vertex.

    Sharp edges (--sharp-angle) split the surface into smooth patches. L is the largest
    λ-Lipschitz function below: the distance to the Voronoi poles of the curved patches
    (medial balls touching two adjacent patches left out), half the thickness across the part
    and the curvature radius (a second, independent estimate and an upper bound), and the size
    of the sharp features. It is evaluated at points spread inside the faces, refined until
    stable, so a coarse and a fine export of one part give the same L (docs/lfs.md). Warnings
    say where the two estimates disagree, and name an open or non-manifold mesh, degenerate
    faces or coarse curved patches. `sample --mesh` and `advise --mesh` use this same L.
    """
    import numpy as np

    from ..checks import checked_seed
    from ..files import write_set
    from ..sampling.io.lfs_files import checked_lfs_output, lfs_writers
    from ..sampling.io.meshes import read_triangle_mesh
    from ..sampling.lfs.estimate import estimate_lfs

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
        "patches": estimate.patches,
        "feature_edges": estimate.feature_edges,
        "feature_corners": len(estimate.feature_corners),
        "feature_length": estimate.feature_length,
        "feature_inv_lfs": estimate.feature_inv_lfs,
        "rounds": estimate.rounds,
        "face_sites": int((estimate.sites.kind == 1).sum()),
        "thickness_min": _finite_min(estimate.sites.thickness),
        "disagreement": estimate.disagreement,
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
            "pole sample (curved patches)",
            f"{estimate.sample_count:,} ({estimate.added_samples:,} fitted edge midpoints)",
        ),
        ("medial-axis points (poles)", f"{payload['medial_points']:,}"),
        (
            "face sites / refinement rounds",
            f"{payload['face_sites']:,} / {payload['rounds']}",
        ),
        (
            "smooth patches / feature edges / corners",
            f"{estimate.patches:,} / {estimate.feature_edges:,} / {payload['feature_corners']:,}",
        ),
        ("thinnest part (along normals)", fmt(payload["thickness_min"], 6)),
        ("estimates A vs B", _disagreement(estimate.disagreement)),
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


def _finite_min(values):
    import numpy as np

    finite = values[np.isfinite(values)]
    return float(finite.min()) if len(finite) else None


def _disagreement(info: dict) -> str:
    """One line on where the medial estimate and the thickness/curvature bound disagree."""
    if not info.get("compared"):
        return (
            "the medial estimate needs vertices or fitted midpoints inside curved patches: "
            "thickness and curvature only"
        )
    return (
        f"medial above 2× the bound at {100 * info['share_above']:.2f} % of "
        f"{info['compared']:,} face sites (worst {info['worst_ratio']:.3g}×)"
    )
