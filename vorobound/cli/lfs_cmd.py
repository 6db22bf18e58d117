"""``vorobound lfs``: estimate the local feature size L at the vertices of a triangle mesh."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from .command import invoke
from .options import LAMBDA_HELP, Json, Seed

if TYPE_CHECKING:
    from ..api.lfs import LfsResult
from .render import fmt, print_footer, print_table

MESH = "Triangle mesh (STL, OBJ, PLY, OFF, VTK, VTU, ...)."
"""--mesh of lfs."""
POSITIONAL_MESH_NOTE = (
    "note: `vorobound lfs MESH` is deprecated and goes in the next release; "
    "use `vorobound lfs --mesh MESH`, as every command takes a mesh"
)


def lfs(
    mesh_file: Annotated[
        Path | None,
        typer.Argument(
            metavar="[MESH]",
            hidden=True,
            help="The mesh as a positional argument (deprecated: use --mesh, as every command "
            "does).",
        ),
    ] = None,
    mesh: Annotated[Path | None, typer.Option("--mesh", metavar="FILE", help=MESH)] = None,
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
            metavar="LAMBDA",
            help=LAMBDA_HELP + "the estimate is made λ-Lipschitz, L(x) ← min_y L(y) + "
            "λ|x − y|, λ in [1e-12, 1e6]. The distance to the medial axis is already "
            "1-Lipschitz; λ < 1 lowers it (a gentler sizing field).",
        ),
    ] = 1.0,
    sharp_angle: Annotated[
        float,
        typer.Option(
            "--sharp-angle",
            metavar="DEGREES",
            help="Edges whose face normals differ by more than this many degrees are sharp: "
            "they split the surface into smooth patches, and L is that of the piecewise-smooth "
            "surface (docs/lfs.md).",
        ),
    ] = 30.0,
    seed: Seed = 0,
    as_json: Json = False,
) -> int:
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
    options = {name: value for name, value in locals().items() if name != "mesh_file"}
    from ..errors import InputError

    if (mesh is None) == (mesh_file is None):
        raise InputError("give the mesh once: --mesh FILE")
    code = invoke("lfs", _show, options, mesh=mesh or mesh_file, output=output or None)
    if mesh_file is not None:  # after the run: a bad input keeps its one line of error
        print(POSITIONAL_MESH_NOTE, file=sys.stderr)
    return code


def _show(result: LfsResult) -> None:
    estimate = result.estimate
    rows = [
        ("vertices / triangles", f"{result.vertices:,} / {result.triangles:,}"),
        (
            "pole sample (curved patches)",
            f"{estimate.sample_count:,} ({estimate.added_samples:,} fitted edge midpoints)",
        ),
        ("medial-axis points (poles)", f"{len(estimate.medial_points):,}"),
        ("face sites / refinement rounds", f"{result.face_sites:,} / {estimate.rounds}"),
        (
            "smooth patches / feature edges / corners",
            f"{estimate.patches:,} / {estimate.feature_edges:,} / "
            f"{len(estimate.feature_corners):,}",
        ),
        ("thinnest part (along normals)", fmt(result.thickness_min, 6)),
        ("estimates A vs B", _disagreement(estimate.disagreement)),
        (
            "L min / median / max",
            " / ".join(fmt(v, 6) for v in (result.lfs_min, result.lfs_median, result.lfs_max)),
        ),
        ("Lipschitz constant", fmt(estimate.lipschitz)),
        (f"sharp edges (> {estimate.sharp_angle:g}°)", f"{len(estimate.sharp_edges):,}"),
        ("largest dihedral angle", f"{estimate.max_dihedral:.1f}°"),
        ("time", f"{result.seconds:.2f} s"),
    ]
    rows += [("written", path) for path in result.written]
    name = Path(result.mesh).name
    print_table(f"Local feature size of {name}", ("quantity", "value"), rows)
    print_footer(f"method: {estimate.method}; estimate (numerical), not a certified bound")


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
