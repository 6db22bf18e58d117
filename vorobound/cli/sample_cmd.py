"""``vorobound sample``: a σ-sparse ε-sample of a sphere, a torus or a mesh, with its guarantees."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ..constants import PAPER_DELTA_RATIO, PAPER_SIGMA
from .command import grouped, invoke
from .options import (
    DeltaRatio,
    Eps,
    Json,
    Seed,
    Sigma,
    SurfaceOptions,
)
from .render import fmt, print_table


@grouped
def sample(
    eps: Eps,
    output: Annotated[
        Path,
        typer.Option(
            "-o",
            "--output",
            metavar="FILE",
            help="Sample file to write: .npz, .vtu or .csv (x, y, z, r, L), from the suffix.",
        ),
    ],
    surface: SurfaceOptions = SurfaceOptions(),
    sigma: Sigma = PAPER_SIGMA,
    delta_ratio: DeltaRatio = PAPER_DELTA_RATIO,
    seed: Seed = 0,
    workers: Annotated[
        int,
        typer.Option(
            "--workers",
            metavar="N",
            help="Sample a mesh's slabs on this many local processes (1: one after another "
            "in this process): the same sample for any N. At most one process per CPU runs "
            "at once. Not with --scheduler, whose cluster brings its own workers.",
        ),
    ] = 1,
    scheduler: Annotated[
        str | None,
        typer.Option(
            "--scheduler",
            metavar="ADDRESS",
            help="Sample a mesh's slabs on a dask.distributed cluster, e.g. "
            "tcp://127.0.0.1:8786 (needs the dask extra of vorobound).",
        ),
    ] = None,
    as_json: Json = False,
) -> int:
    """Sample a surface: σ-sparse, and an ε-sample by construction.

    The sample is a maximal σ-sparse subset of a jittered candidate lattice fine enough that
    maximality implies coverage; a mesh is sampled slab by slab, where a cell is also done once
    a sample provably covers it (docs/samples.md), each finished slab streamed to the file, so
    memory is bounded by a few slabs (--workers N: slabs on N processes). The file
    holds x, y, z, the ball radius r = δ·L (δ = (δ/ε)·ε) and L per point; `vorobound check
    --balls` reads it back. Reported: coverage_max (max distance to the sample over εL at random
    probe points, < 1 required) and sparsity_min (min |p_i − p_j|/(σε·min L) over all pairs,
    ≥ 1 required); exit code 1 if either fails. Python: vorobound.sample(eps=..., output=...,
    torus=(3, 1)).
    """
    return invoke("sample", _show, locals())


def _show(result) -> None:
    print_table(
        f"Sample of {result.surface} at ε = {result.eps:g}",
        ("quantity", "value", "meaning"),
        [
            (
                "samples",
                f"{result.n_samples:,}",
                f"from {result.n_candidates:,} lattice candidates",
            ),
            (
                "coverage_max",
                fmt(result.coverage_max, 6),
                f"< 1 required (measured, {result.coverage_probes:,} probes)",
            ),
            (
                "guaranteed reach",
                fmt(result.reach_ratio, 6),
                "cell reach / (εL): to its candidate or certifying sample",
            ),
            ("sparsity_min", fmt(result.sparsity_min, 12), "≥ 1 required (exact, all pairs)"),
            ("λ of L", fmt(result.lipschitz, 6), "Lipschitz constant of the surface's L"),
            ("time", f"{result.seconds:.1f} s", ""),
        ],
    )
    print(f"wrote {result.output}")
