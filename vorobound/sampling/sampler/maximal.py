"""σ-sparse ε-samples with a guarantee: a maximal sparse subset of a fine candidate lattice.

The candidates are visited in a random order (fixed by the seed); each is accepted unless an
accepted sample lies within σε·min(L) of it (the rule of :mod:`.greedy`; a mesh is sampled
slab by slab, features first, by :mod:`.slabs`). The result is the lexicographically first maximal
independent set of the conflict graph for that order, so it is σ-sparse by construction and,
by the choice of the lattice (:mod:`vorobound.sampling.sampler.lattice`), an ε-sample.

The visit runs in chunks of the order, each about ``CHUNK_GROWTH`` times the last: a chunk's
candidates that conflict with a sample accepted before it are dropped (one nearest-neighbour
query against the accepted samples), and conflicts inside the chunk are resolved in rounds (a
candidate joins once every earlier conflicting candidate of the chunk is decided), which gives
exactly the sequential result.

References
----------
The sampling conditions of Section 4.1 (ε-sample, σ-sparse).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...progress import Counter, Progress
from .greedy import _chunks, _conflicts_with, _first_independent, conflict_radius
from .lattice import Candidates

__all__ = ["Sample", "conflict_radius", "maximal_sparse_subset", "sample_surface"]


@dataclass(frozen=True)
class Sample:
    """A sample of a surface: points, their local feature size and how they were made."""

    points: np.ndarray
    """(n, 3) sample points."""
    lfs: np.ndarray
    """(n,) local feature size L at each point."""
    eps: float
    sigma: float
    lipschitz: float
    """Lipschitz constant λ of L on the surface (1 for an exact local feature size)."""
    surface: str
    """Name of the sampled surface."""
    seed: int
    candidates: int
    """Candidates made (the lattice; on a mesh, every cell's candidate of the slab sampler)."""
    reach_ratio: float
    """Guaranteed: every surface point is within reach_ratio·ε·L of its cell's candidate, or (a
    certified cell of the slab sampler) of the sample that certifies it."""


def maximal_sparse_subset(
    candidates: Candidates,
    eps: float,
    sigma: float,
    rng: np.random.Generator,
    progress: Progress | None = None,
) -> np.ndarray:
    """Indices of the maximal σ-sparse subset of ``candidates`` for a random visiting order.

    Parameters
    ----------
    candidates : Candidates
        Points and their L.
    eps, sigma : float
        Conflict when |p − q| < σε·min(L_p, L_q).
    rng : numpy.random.Generator
        Draws the visiting order.
    progress : Progress, optional
        Reports the candidates visited.

    Returns
    -------
    numpy.ndarray
        Accepted candidate indices, in visiting order.

    References
    ----------
    The σ-sparsity condition of Section 4.1.
    """
    from scipy.spatial import cKDTree

    points, lfs = candidates.points, candidates.lfs
    count = len(points)
    rank = rng.permutation(count)  # visiting position of each candidate
    counter = Counter(progress, "sampling", count)
    accepted: list[np.ndarray] = []
    tree, members = None, np.empty(0, dtype=np.int64)
    for start, stop in _chunks(count):
        # Lattice order is spatially coherent: gathers and tree queries in it stay in cache.
        ids = np.flatnonzero((rank >= start) & (rank < stop))
        if tree is not None:
            ids = ids[~_conflicts_with(tree, lfs[members], points, lfs, ids, eps, sigma)]
        ids = ids[np.argsort(rank[ids])]
        if len(ids):
            accepted.append(ids[_first_independent(points[ids], lfs[ids], eps, sigma)])
            members = np.sort(np.concatenate(accepted))
            tree = cKDTree(points[members], balanced_tree=False)
        counter.step(stop - start)
    return np.concatenate(accepted) if accepted else np.empty(0, dtype=np.int64)


def sample_surface(
    shape,
    eps: float,
    sigma: float,
    seed: int = 0,
    progress: Progress | None = None,
    workers: int = 1,
    scheduler: str | None = None,
) -> Sample:
    """A σ-sparse ε-sample of ``shape`` (a surface of revolution or a mesh), fixed by ``seed``.

    Parameters
    ----------
    shape : RevolutionShape or MeshShape
        The surface and its local feature size L.
    eps : float
        ε: every surface point x gets a sample within ε·L(x) (guaranteed by construction).
    sigma : float
        σ < 1: samples are at least σε·min(L) apart (exact).
    seed : int
        Seeds the jitter of the lattice and the visiting order.
    progress : Progress, optional
        Reports the stages "lattice" and "sampling".
    workers, scheduler : int, str
        A mesh's slabs on this many local processes or a dask cluster (:mod:`.slabs`; the
        same sample for any number).

    References
    ----------
    The sampling conditions of Section 4.1.
    """
    from ..surfaces.analytic import RevolutionShape
    from .lattice import revolution_candidates
    from .slabs import slab_sample

    rng = np.random.default_rng(seed)
    if isinstance(shape, RevolutionShape):
        Counter(progress, "lattice", None)
        candidates = revolution_candidates(shape, eps, sigma, rng)
        chosen = np.sort(maximal_sparse_subset(candidates, eps, sigma, rng, progress))
        points, lfs = candidates.points[chosen], candidates.lfs[chosen]
        made, ratio = len(candidates.points), candidates.reach_ratio
    else:
        run = slab_sample(shape, eps, sigma, rng, progress, workers=workers, scheduler=scheduler)
        points, lfs, made, ratio = run.points, run.lfs, run.made, run.reach_ratio
    return Sample(
        points=points,
        lfs=lfs,
        eps=eps,
        sigma=sigma,
        lipschitz=shape.lipschitz,
        surface=shape.name,
        seed=seed,
        candidates=made,
        reach_ratio=ratio,
    )
