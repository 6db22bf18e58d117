"""The slab sampler's schedule: odd slabs only after both neighbours, slabs handed on in order,
and a bounded number of finished slabs held, whatever the order in which workers finish."""

import concurrent.futures

import numpy as np
import pytest

from vorobound.progress import Counter
from vorobound.sampling.sampler import slabs
from vorobound.sampling.sampler.slab_job import SlabDone


class _Shuffled(concurrent.futures.Executor):
    """Holds submitted slabs and finishes them in a random order when waited on."""

    def __init__(self, seed):
        self.rng = np.random.default_rng(seed)
        self.held: list[tuple[concurrent.futures.Future, int]] = []

    def submit(self, fn, /, job):
        future = concurrent.futures.Future()
        self.held.append((future, job))
        return future

    def finish_some(self):
        if not self.held:
            return
        for at in sorted(
            self.rng.choice(len(self.held), size=1 + len(self.held) // 2, replace=False)
        )[::-1]:
            future, slab = self.held.pop(at)
            future.set_result(SlabDone(slab, np.zeros((slab, 3)), np.zeros(slab), 1, 0.0))


class _Jobs:
    """Records, for each slab's job, which slabs were finished and held."""

    def __init__(self):
        self.seen: dict[int, set[int]] = {}

    def job(self, slab, finished):
        self.seen[slab] = set(finished)
        return slab


@pytest.mark.parametrize(
    "count, slots, seed", [(1, 1, 0), (2, 1, 0), (41, 1, 0), (200, 2, 1), (40, 3, 2)]
)
def test_the_schedule_is_two_coloured_ordered_and_bounded(monkeypatch, count, slots, seed):
    executor = _Shuffled(seed)
    real_wait = concurrent.futures.wait

    def wait(futures, return_when):
        if not any(f.done() for f in futures):
            executor.finish_some()
        return real_wait(futures, return_when=return_when)

    monkeypatch.setattr(concurrent.futures, "wait", wait)
    jobs, handed = _Jobs(), []
    made, _, rows = slabs._schedule(
        executor, slots, jobs, count, lambda p, f: handed.append(len(p)), Counter(None, "t", count)
    )
    assert handed == list(range(count)) == rows and made == count
    for slab, held in jobs.seen.items():
        if slab % 2:  # both neighbours finished before an odd slab's job is made
            assert {n for n in (slab - 1, slab + 1) if n < count} <= held
        assert len(held) <= 4 * slabs.SLABS_PER_WORKER * slots + 2
