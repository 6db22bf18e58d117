"""What ``vorobound sample --mesh`` costs at an ε, and the smallest ε it can build.

The cost is counted in plain-lattice candidates, :func:`.mesh_lattice.expected_candidates`
(∝ ∫dA/L²/ε²), the count `advise` shows; the slab sampler (:mod:`.slabs`) makes about a
quarter of them. CPU time grows linearly in that count; memory grows with it up to one slab
(``SLAB_CANDIDATES``) and then slowly (slabs in flight, the coverage probes up to their cap;
the samples are streamed to the file). With ``--workers N`` each worker holds its slabs.
The constants are measured by ``python benchmarks/bench_sample_cost.py`` (the CAD cube at
ε = 0.05, 0.025, 0.0125: 0.39, 1.5 and 5.8 million plain candidates, 2.65, 4.26 and 11.0 CPU
s, 169, 222 and 346 MB on the 2-core machine shared with other jobs; fitted as base + slope ×
candidates) and
``python benchmarks/bench_sample_slabs.py --parts cylinder`` (the 100-long cylinder at
ε = 0.0094977: 482 CPU s before streaming; 427.6 CPU s and 920 MiB streamed, 1 worker);
they are estimates, not bounds.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ...errors import InputError
from .mesh_lattice import expected_candidates
from .slabs import MAX_EXPECTED_CANDIDATES, SLAB_CANDIDATES

BYTES_PER_CANDIDATE = 32.0
"""Peak memory per plain-lattice candidate within one slab (measured slope, cube)."""
BYTES_PER_SAMPLED_CANDIDATE = 2.2
"""Peak memory per plain-lattice candidate beyond one slab: slabs in flight, the coverage
probes, the measurement's blocks (the cylinder at ε = 0.0094977, streamed, 1 worker: 2.63·10⁸
plain candidates, 920 MiB = 965 MB; 1.32 GB and 3.5 bytes before streaming)."""
BASE_BYTES = 165e6
"""Peak memory of a small ``vorobound sample --mesh`` run (interpreter, numpy, scipy, mesh)."""
CPU_SECONDS_PER_CANDIDATE = 1.83e-6
"""CPU seconds per plain-lattice candidate (lattice, greedy visit, checks): the larger of the
cube's fitted slope (1.56 µs) and the cylinder at ε = 0.0094977 (482 CPU s)."""
BASE_CPU_SECONDS = 2.0
"""CPU seconds of a small run (imports, the local feature size of a small mesh)."""


@dataclass(frozen=True)
class SamplerCost:
    """Estimated cost of ``vorobound sample --mesh`` at one ε."""

    candidates: float
    """About how many lattice candidates it builds."""
    memory_bytes: float
    """Estimated peak memory."""
    cpu_seconds: float
    """Estimated CPU time (not counting the local feature size of a large mesh)."""

    @property
    def samplable(self) -> bool:
        """Whether the sampler takes this on (a plain-lattice count of at most
        :data:`.slabs.MAX_EXPECTED_CANDIDATES`, a limit of time: memory is bounded by a slab)."""
        return self.candidates <= MAX_EXPECTED_CANDIDATES


def sampler_cost(inv_lfs_sq_integral: float, eps: float, sigma: float, lam: float) -> SamplerCost:
    """The estimated cost at ``eps`` on a mesh whose ∫dA/L² is ``inv_lfs_sq_integral``."""
    count = expected_candidates(inv_lfs_sq_integral, eps, sigma, lam)
    return SamplerCost(
        candidates=count,
        memory_bytes=BASE_BYTES
        + BYTES_PER_CANDIDATE * min(count, SLAB_CANDIDATES)
        + BYTES_PER_SAMPLED_CANDIDATE * max(count - SLAB_CANDIDATES, 0.0),
        cpu_seconds=BASE_CPU_SECONDS + CPU_SECONDS_PER_CANDIDATE * count,
    )


def smallest_samplable_eps(
    inv_lfs_sq_integral: float, sigma: float, lam: float, high: float = 0.999
) -> float:
    """The smallest ε (to 1e-9 relative) whose lattice has at most :data:`MAX_EXPECTED_CANDIDATES`
    candidates; the count decreases with ε, so every larger ε is samplable too.

    Raises
    ------
    InputError
        When even ``high`` needs more candidates.
    """

    def fits(eps: float) -> bool:
        return expected_candidates(inv_lfs_sq_integral, eps, sigma, lam) <= MAX_EXPECTED_CANDIDATES

    if not fits(high):
        raise InputError(
            f"even eps={high:g} needs more than {MAX_EXPECTED_CANDIDATES:.0e} lattice candidates: "
            "vorobound sample cannot sample this surface"
        )
    low = 1e-12
    if fits(low):
        return low
    while high / low > 1 + 1e-9:  # bisect in log ε: fits(high) and not fits(low)
        mid = math.sqrt(low * high)
        if fits(mid):
            high = mid
        else:
            low = mid
    return high
