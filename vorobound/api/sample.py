"""``vorobound sample``: a σ-sparse ε-sample of a sphere, a torus or a mesh, written to a file."""

from __future__ import annotations

import os
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from ..bounds.params import QualityParams
from ..constants import PAPER_DELTA_RATIO, PAPER_SIGMA
from ..errors import InputError, LatticeTooLarge
from ..progress import Progress
from .arguments import checked_arguments
from .result import Result, params_json, sample_lfs

if TYPE_CHECKING:
    from ..mesh import TriangleMesh
    from ..reports.sample import SampleReport, StreamedSampleReport


@dataclass(frozen=True, repr=False)
class SampleResult(Result):
    """A sample, where it was written, and the conditions it meets."""

    command = "sample"
    surface: str
    n_samples: int
    n_candidates: int
    coverage_max: float
    """Below 1 required (measured on random surface points)."""
    sparsity_min: float
    """At least 1 required (exact, over all pairs)."""
    sparsity_violations: int
    output: str
    seconds: float
    eps: float = field(repr=False)
    seed: int = field(repr=False)
    lipschitz: float = field(repr=False)
    reach_ratio: float = field(repr=False)
    coverage_probes: int = field(repr=False)
    quality: QualityParams = field(repr=False)
    report: SampleReport | StreamedSampleReport = field(repr=False)
    """:class:`vorobound.reports.sample.SampleReport`, or for a mesh (streamed to the file)
    :class:`vorobound.reports.sample.StreamedSampleReport`."""
    workers: int = field(default=1, repr=False)

    @property
    def ok(self) -> bool:
        return self.coverage_max < 1 and self.sparsity_violations == 0

    @property
    def verdict(self) -> str:
        parts = []
        if self.coverage_max >= 1:
            parts.append(f"coverage_max {self.coverage_max:.6g} >= 1")
        if self.sparsity_violations:
            parts.append(f"{self.sparsity_violations} pairs closer than the sparsity allows")
        return "the sample breaks its conditions: " + "; ".join(parts)

    def payload(self) -> dict:
        params = params_json(self.quality, self.eps, seed=self.seed)
        for key in ("rho_f", "target", "lipschitz"):
            params.pop(key)
        return {
            "params": params,
            **sample_lfs(params, self.report.lfs_range),
            "surface": self.surface,
            "n_samples": self.n_samples,
            "n_candidates": self.n_candidates,
            "reach_ratio": self.reach_ratio,
            "coverage_max": self.coverage_max,
            "coverage_probes": self.coverage_probes,
            "sparsity_min": self.sparsity_min,
            "sparsity_violations": self.sparsity_violations,
            "lipschitz": self.lipschitz,
            "workers": self.workers,
            "ok": self.ok,
            "seconds": round(self.seconds, 3),
            "output": self.output,
        }


@checked_arguments
def sample(
    *,
    eps: float,
    output: str | os.PathLike,
    sphere: float | None = None,
    torus: Sequence[float] | None = None,
    mesh: str | os.PathLike | TriangleMesh | None = None,
    lfs: float | None = None,
    sizing: str | os.PathLike | None = None,
    sigma: float = PAPER_SIGMA,
    delta_ratio: float = PAPER_DELTA_RATIO,
    seed: int = 0,
    workers: int = 1,
    scheduler: str | None = None,
    progress: Progress | None = None,
) -> SampleResult:
    """Sample a surface: σ-sparse, and an ε-sample by construction; write the balls.

    The sample is a maximal σ-sparse subset of a jittered candidate lattice fine enough that
    maximality implies coverage; a mesh is sampled slab by slab, a cell also being done once a
    sample provably covers it (docs/samples.md). ``output`` (.npz, .vtu or .csv) holds x, y,
    z, the ball radius r = δ·L and L per point; :func:`vorobound.check` reads it back. A mesh's
    slabs are sampled on ``workers`` local processes (1: here) or a dask ``scheduler``, the
    same sample for any number, and streamed to the file (memory: a few slabs).

    References
    ----------
    The sampling conditions of Section 4.1.
    """
    from ..checks import checked_count, checked_seed
    from ..reports.sample import sample_report, streamed_sample_report
    from ..sampling.io.balls import checked_output, write_balls
    from ..sampling.surfaces.analytic import RevolutionShape
    from .surfaces import Surface

    output = checked_output(os.fspath(output))
    seed = checked_seed(seed)
    workers = checked_count(workers, "workers", 1, 1 << 16)
    if workers != 1 and scheduler is not None:
        # The cluster's workers run the slabs: a number of local processes would be ignored.
        raise InputError(
            "give workers (local processes) or scheduler (a dask cluster's workers), not both"
        )
    quality = QualityParams(sigma, delta_ratio)
    params = quality.at(eps)
    if scheduler is not None and mesh is not None:
        from ..parallel import reachable_scheduler

        reachable_scheduler(scheduler)  # before the minutes of L, not after them
    start = time.perf_counter()
    shape = Surface(sphere, torus, mesh, lfs, sizing).shape(progress=progress)
    streamed = not isinstance(shape, RevolutionShape)
    if not streamed and (workers != 1 or scheduler is not None):
        raise InputError("workers and scheduler go with mesh (a sphere or torus is one lattice)")
    try:
        if streamed:
            run = streamed_sample_report(shape, params, output, seed, workers, scheduler, progress)
            samples, candidates, reach = run.samples, run.candidates, run.reach_ratio
        else:
            whole = sample_report(shape, params, seed, progress)
    except LatticeTooLarge as err:
        raise LatticeTooLarge(_with_smallest_eps(str(err), shape, quality)) from None
    report: SampleReport | StreamedSampleReport = run if streamed else whole
    if not streamed:
        write_balls(output, whole.balls, {"lfs": whole.sample.lfs})
        samples, candidates = len(whole.balls), whole.sample.candidates
        reach = whole.sample.reach_ratio
    seconds = time.perf_counter() - start
    return SampleResult(
        surface=shape.name,
        n_samples=samples,
        n_candidates=candidates,
        coverage_max=report.coverage_max,
        sparsity_min=report.sparsity.extreme,
        sparsity_violations=report.sparsity.violations,
        output=os.fspath(output),
        seconds=seconds,
        eps=params.eps,
        seed=seed,
        lipschitz=shape.lipschitz,
        reach_ratio=reach,
        coverage_probes=report.coverage_probes,
        quality=quality,
        report=report,
        workers=workers,
    )


def _with_smallest_eps(message: str, shape, quality: QualityParams) -> str:
    """The refusal, plus the smallest ε the sampler builds on a mesh and what it guarantees."""
    from ..reports.advisor import guarantee_words, smallest_samplable
    from ..rounding import format_down

    counts = shape.counts()
    if not counts.mesh_lattice:
        return message
    try:
        back = smallest_samplable(quality, counts, max(shape.lipschitz, 0.0))
    except InputError as err:
        return f"{message} ({err})"
    return (
        f"{message}; the smallest eps it builds on {shape.name} is {format_down(back.eps)}, "
        f"which guarantees {guarantee_words(back.guarantee)}"
    )
