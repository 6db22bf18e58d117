"""A sample of a surface and what it achieves: the ε-sample and σ-sparsity conditions."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator
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

    @property
    def lfs_range(self) -> tuple[float, float]:
        """(min, max) of L over the samples."""
        lfs = self.sample.lfs
        return (float(lfs.min()), float(lfs.max())) if len(lfs) else (float("nan"),) * 2


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


@dataclass(frozen=True)
class StreamedSampleReport:
    """A mesh's sample streamed to its file (:func:`streamed_sample_report`): what was made
    and measured, without the samples."""

    samples: int
    candidates: int
    reach_ratio: float
    """As :attr:`vorobound.sampling.sampler.maximal.Sample.reach_ratio`."""
    lfs_range: tuple[float, float]
    coverage_max: float
    """max over the probes of (distance to the nearest sample)/(εL): exact below 1
    (:func:`~vorobound.sampling.sampler.conditions.coverage_of_blocks`)."""
    coverage_probes: int
    sparsity: conditions.PairReport
    """Exact below 2 (:func:`~vorobound.sampling.sampler.conditions.sparsity_of_blocks`)."""


WRITE_ROWS = 1 << 18
"""Samples per block written to the sample file."""


def streamed_sample_report(
    shape,
    params: SamplingParams,
    output,
    seed: int = 0,
    workers: int = 1,
    scheduler: str | None = None,
    progress: Progress | None = None,
) -> StreamedSampleReport:
    """Sample a mesh ``shape`` in slabs (:mod:`vorobound.sampling.sampler.slabs`), spilling each
    finished slab to a temporary file; measure coverage and sparsity block by block (a slab and
    the feature samples in its range); write the balls to ``output`` (NPZ, CSV: block by
    block; VTU: whole) through a temporary file renamed into place. Memory holds a few slabs
    and the coverage probes, not the sample.

    References
    ----------
    The sampling conditions of Section 4.1.
    """
    import numpy as np

    from ..errors import InputError
    from ..sampling.balls import MIN_BALLS, checked_rows
    from ..sampling.io.balls import write_balls_streamed
    from ..sampling.io.sample_spill import SampleSpill
    from ..sampling.sampler.slabs import slab_sample

    eps, sigma = params.eps, params.sigma
    with _spill_folder() as folder:
        spill = SampleSpill(folder)
        try:
            run = slab_sample(
                shape,
                eps,
                sigma,
                np.random.default_rng(seed),
                progress,
                workers=workers,
                scheduler=scheduler,
                sink=spill,
            )
        finally:
            spill.close()
        if spill.count < MIN_BALLS:
            raise InputError(f"{shape.name}: need at least {MIN_BALLS} samples, got {spill.count}")
        blocks = _slab_blocks(spill, run)
        sparse = conditions.sparsity_of_blocks(
            blocks, spill.read, run.axis, eps, sigma, spill.lfs_max
        )
        if not sparse.extreme > 0:
            raise InputError(f"{shape.name}: two samples coincide (rows {sparse.extreme_pair})")
        probes, probe_lfs = conditions.coverage_probes(shape, spill.count, seed)
        coverage, _ = conditions.coverage_of_blocks(
            blocks, spill.read, run.axis, eps, probes, probe_lfs
        )
        probe_count = len(probes)
        del probes, probe_lfs

        def chunks():
            for start in range(0, spill.count, WRITE_ROWS):
                points, lfs = spill.read(slice(start, start + WRITE_ROWS))
                centers, radii = checked_rows(points, params.delta * lfs, shape.name, start)
                yield centers, radii, {"lfs": lfs}

        write_balls_streamed(output, spill.count, chunks)
        count = spill.count
    return StreamedSampleReport(
        samples=count,
        candidates=run.made,
        reach_ratio=run.reach_ratio,
        lfs_range=(spill.lfs_min, spill.lfs_max),
        coverage_max=coverage,
        coverage_probes=probe_count,
        sparsity=sparse,
    )


@contextlib.contextmanager
def _spill_folder() -> Iterator[str]:
    """A temporary folder for the spill, removed on leaving even when Ctrl-C comes during its
    removal (held until it is gone): ``tempfile.TemporaryDirectory`` stops removing at the
    interrupt and forgets the folder (found by hand: an interrupt just after the sample file
    was written left the whole spill in the temporary folder)."""
    import shutil
    import tempfile

    from ..files import TEMP_PREFIX
    from ..parallel import signals_deferred

    folder = tempfile.mkdtemp(prefix=f"{TEMP_PREFIX}samples.")
    try:
        yield folder
    finally:
        with signals_deferred():
            shutil.rmtree(folder, ignore_errors=True)


def _slab_blocks(spill, run) -> list:
    """Row indices of each slab's samples and of the feature samples whose coordinate along
    the axis lies in the slab's range (the blocks of the measurements)."""
    import numpy as np

    first, stop = spill.blocks[0]
    coord = spill.read(slice(first, stop))[0][:, run.axis]
    slabs = len(run.borders) - 1
    owner = np.clip(np.searchsorted(run.borders, coord, side="right") - 1, 0, slabs - 1)
    features = np.arange(first, stop)
    return [
        np.concatenate([features[owner == slab], np.arange(*spill.blocks[1 + slab])])
        for slab in range(slabs)
    ]
