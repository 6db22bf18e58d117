"""A sample of a surface and what it achieves: the ε-sample and σ-sparsity conditions."""

from __future__ import annotations

from dataclasses import dataclass

from ..bounds.params import SamplingParams
from ..progress import Progress
from ..sampling.balls import Balls, make_balls
from ..sampling.sampler import conditions
from ..sampling.sampler.maximal import Sample, sample_surface


@dataclass(frozen=True)
class SampleReport:
    """A σ-sparse ε-sample with its balls (r = δ·L) and its measured conditions."""

    sample: Sample
    balls: Balls
    coverage_max: float
    """max over the probes of (distance to the nearest sample)/(εL): below 1 required."""
    coverage_probes: int
    sparsity: conditions.PairReport
    """min |p_i − p_j|/(σε·min L) over all pairs (exact): at least 1 required."""


def sample_report(
    shape, params: SamplingParams, seed: int = 0, progress: Progress | None = None
) -> SampleReport:
    """Sample ``shape`` at ``params.eps`` (the lattice sampler, docs/samples.md) and measure
    coverage and sparsity.

    References
    ----------
    The sampling conditions of Section 4.1.
    """
    sample = sample_surface(shape, params.eps, params.sigma, seed, progress)
    balls = make_balls(sample.points, params.delta * sample.lfs, shape.name)
    sparse = conditions.sparsity_in_blocks(sample.points, sample.lfs, params.eps, params.sigma)
    coverage, _, probes = conditions.surface_coverage(shape, sample.points, params.eps, seed)
    return SampleReport(sample, balls, coverage, probes, sparse)
