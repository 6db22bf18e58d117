"""``vorobound sample``: a σ-sparse ε-sample of a sphere, a torus or a mesh, with its guarantees."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ..errors import InputError
from .options import DeltaRatio, Eps, Json, Seed, Sigma, parse_numbers
from .progress import progress_bar
from .render import fmt, print_json, print_table

SphereOpt = Annotated[
    float | None, typer.Option("--sphere", metavar="R", help="Sphere of radius R (L = R).")
]
TorusOpt = Annotated[
    str | None,
    typer.Option("--torus", metavar="R,r", help="Ring torus, radii R > r (L = min(r, ρ))."),
]
MeshOpt = Annotated[
    Path | None,
    typer.Option(
        "--mesh",
        help="Triangle mesh (any format meshio reads); L from --lfs, --sizing, or else "
        "estimated from the mesh as by `vorobound lfs` (sharp features sampled first).",
    ),
]
MeshLfsOpt = Annotated[
    float | None, typer.Option("--lfs", help="Constant local feature size L of the mesh.")
]
SizingOpt = Annotated[
    Path | None,
    typer.Option("--sizing", help="CSV with the local feature size L per mesh vertex."),
]


def surface_shape(sphere, torus, mesh, lfs, sizing, required: bool = True, progress=None):
    """The surface named by the options (None if none is given and none is required)."""
    from ..bounds.params import LFS_RANGE
    from ..checks import checked_number
    from ..sampling.surfaces import analytic as surfaces

    def length(value: float, flag: str) -> float:
        return checked_number(value, flag, *LFS_RANGE)

    given = [x is not None for x in (sphere, torus, mesh)]
    if sum(given) > 1:
        raise InputError("give one surface: --sphere, --torus or --mesh")
    if mesh is None and (lfs is not None or sizing is not None):
        raise InputError("--lfs and --sizing describe a mesh: use them with --mesh")
    if sphere is not None:
        return surfaces.SphereShape(length(sphere, "--sphere"))
    if torus is not None:
        major, minor = (length(x, "--torus") for x in parse_numbers(torus, "--torus", 2))
        return surfaces.TorusShape(major, minor)
    if mesh is not None:
        if lfs is not None and sizing is not None:
            raise InputError("give --lfs or --sizing for the mesh, not both")
        return _mesh_shape(mesh, None if lfs is None else length(lfs, "--lfs"), sizing, progress)
    if required:
        raise InputError("give a surface: --sphere R, --torus R,r or --mesh FILE")
    return None


def _mesh_shape(path: Path, lfs: float | None, sizing: Path | None, progress):
    """The mesh with L constant (--lfs), per vertex (--sizing) or estimated from the mesh."""
    import numpy as np

    from ..sampling.io.meshes import read_sizing, read_triangle_mesh
    from ..sampling.surfaces.mesh import MeshShape

    mesh = read_triangle_mesh(path)
    if sizing is not None:
        return MeshShape(mesh, read_sizing(sizing, len(mesh.points)), f"sizing {sizing.name}")
    if lfs is not None:
        return MeshShape(mesh, np.full(len(mesh.points), lfs), f"constant {lfs:g}")
    from ..sampling.lfs.estimate import estimate_lfs
    from ..sampling.surfaces.mesh import FieldMeshShape

    estimate = estimate_lfs(mesh, progress=progress)
    return FieldMeshShape(estimate, f"estimated, {estimate.lipschitz:g}-Lipschitz (docs/lfs.md)")


def sample(
    eps: Eps,
    output: Annotated[
        Path,
        typer.Option(
            "-o", "--output", help="Sample file to write: .npz, .vtu or .csv (x, y, z, r, L)."
        ),
    ],
    sphere: SphereOpt = None,
    torus: TorusOpt = None,
    mesh: MeshOpt = None,
    lfs: MeshLfsOpt = None,
    sizing: SizingOpt = None,
    sigma: Sigma = 0.75,
    delta_ratio: DeltaRatio = 2.0,
    seed: Seed = 0,
    as_json: Json = False,
) -> None:
    """Sample a surface: σ-sparse, and an ε-sample by construction.

    The sample is a maximal σ-sparse subset of a jittered candidate lattice fine enough that
    maximality implies coverage (docs/samples.md). The file holds x, y, z, the ball radius
    r = δ·L (δ = (δ/ε)·ε) and L per point; `vorobound check --balls` reads it back. Reported:
    coverage_max (max distance to the sample over εL at random probe points, < 1 required) and
    sparsity_min (min |p_i − p_j|/(σε·min L) over all pairs, ≥ 1 required).
    """
    import time

    import numpy as np

    from ..bounds.params import SamplingParams
    from ..checks import checked_seed
    from ..sampling.balls import make_balls
    from ..sampling.io.balls import checked_output, write_balls
    from ..sampling.sampler import conditions
    from ..sampling.sampler.maximal import sample_surface
    from .options import quality_params

    output = checked_output(output)
    seed = checked_seed(seed)
    params = SamplingParams(eps, quality_params(sigma, delta_ratio, 1.38))
    start = time.perf_counter()
    with progress_bar(not as_json) as progress:
        shape = surface_shape(sphere, torus, mesh, lfs, sizing, progress=progress)
        result = sample_surface(shape, params.eps, params.sigma, seed, progress)
        balls = make_balls(result.points, params.delta * result.lfs, shape.name)
        sparse = conditions.sparsity(result.points, result.lfs, params.eps, params.sigma)
        rng = np.random.default_rng([seed, 1])
        count = max(conditions.MIN_PROBES, conditions.PROBES_PER_SAMPLE * len(balls))
        probes, probe_lfs = shape.random_points(count, rng)
        coverage, _ = conditions.coverage(result.points, params.eps, probes, probe_lfs)
    seconds = time.perf_counter() - start
    write_balls(output, balls, {"lfs": result.lfs})
    payload = {
        "surface": shape.name,
        "eps": params.eps,
        "sigma": params.sigma,
        "delta_ratio": params.delta_ratio,
        "seed": seed,
        "n_samples": len(balls),
        "n_candidates": result.candidates,
        "reach_ratio": result.reach_ratio,
        "coverage_max": coverage,
        "coverage_probes": count,
        "sparsity_min": sparse.extreme,
        "sparsity_violations": sparse.violations,
        "lipschitz": shape.lipschitz,
        "seconds": round(seconds, 3),
        "output": str(output),
    }
    if as_json:
        print_json(payload)
        return
    print_table(
        f"Sample of {shape.name} at ε = {params.eps:g}",
        ("quantity", "value", "meaning"),
        [
            ("samples", f"{len(balls):,}", f"from {result.candidates:,} lattice candidates"),
            ("coverage_max", fmt(coverage, 6), f"< 1 required (measured, {count:,} probes)"),
            ("guaranteed reach", fmt(result.reach_ratio, 6), "lattice cell reach / (εL)"),
            ("sparsity_min", fmt(sparse.extreme, 12), "≥ 1 required (exact, all pairs)"),
            ("λ of L", fmt(shape.lipschitz, 6), "Lipschitz constant of the surface's L"),
            ("time", f"{seconds:.1f} s", ""),
        ],
    )
    print(f"wrote {output}")
