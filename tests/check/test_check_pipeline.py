"""The check has one pipeline (:func:`vorobound.tiling.job.check_part`): a whole check runs it
once, as one tile in process; a tiled check runs it per tile. Its options (GUDHI's slabs, the
measured λ) change what they say they change and nothing else."""

import dataclasses

import numpy as np
import pytest

import vorobound
from vorobound.bounds.params import QualityParams, SamplingParams
from vorobound.errors import InputError
from vorobound.reports import check as whole_check
from vorobound.sampling.balls import make_balls
from vorobound.sampling.guides.engines import Engine
from vorobound.sampling.guides.triangles import geogram_available
from vorobound.sampling.io.balls import write_balls
from vorobound.sampling.sampler.maximal import sample_surface
from vorobound.sampling.surfaces.analytic import TorusShape
from vorobound.tiling import job as pipeline

pytest.importorskip("gudhi")

EPS = 0.3


@pytest.fixture(scope="module")
def torus_balls():
    sample = sample_surface(TorusShape(1.5, 1.0), EPS, 0.75, seed=2)
    return make_balls(sample.points, 2.0 * EPS * sample.lfs)


def _counted(monkeypatch, module):
    """Count the calls of ``module.check_part`` (the name the caller looks up)."""
    calls = []
    original = pipeline.check_part

    def counted(job, *args, **kwargs):
        calls.append(job)
        return original(job, *args, **kwargs)

    monkeypatch.setattr(module, "check_part", counted)
    return calls


def test_a_whole_check_is_one_part_of_the_pipeline(monkeypatch):
    calls = _counted(monkeypatch, whole_check)
    result = vorobound.check(torus=(1.5, 1.0), eps=EPS)
    assert len(calls) == 1
    job = calls[0]
    assert job.is_whole and job.core.all() and job.settings.slabs
    assert job.lfs is not None  # the torus's exact L, not r/δ
    assert result.n_guide_triangles == result.report.tallies.guides.count > 0


def test_a_tiled_check_runs_the_same_pipeline_per_tile(monkeypatch, torus_balls, tmp_path):
    path = tmp_path / "torus.npz"
    write_balls(path, torus_balls, {})
    calls = _counted(monkeypatch, pipeline)  # run_tile calls it by its module name
    result = vorobound.check(balls=path, eps=EPS, workers=1)
    runs = result.report.run.tiling
    assert len(calls) == runs.tiles + runs.rerun >= 1
    assert not any(job.is_whole for job in calls)
    assert not any(job.settings.slabs or job.settings.measure_lipschitz for job in calls)


def _settings(balls, **changes):
    params = SamplingParams(EPS, QualityParams(lipschitz=1.0))
    settings = pipeline.TileSettings.whole(balls, params, 1.0, Engine.gudhi, "torus")
    return dataclasses.replace(settings, **changes)


def test_slabs_change_the_candidates_only(torus_balls):
    """One regular triangulation (a tile's) or GUDHI's slabs on threads (a whole check's): the
    same guide triangles and measurements; the candidate count is the engine's diagnostic."""
    found = {}
    for slabs in (True, False):
        job = pipeline.TileJob.whole(torus_balls, _settings(torus_balls, slabs=slabs))
        found[slabs] = pipeline.check_part(job)
    a, b = found[True], found[False]
    assert a.guides.count == b.guides.count > 0
    assert a.guides.maxima == b.guides.maxima and a.guides.counts == b.guides.counts
    assert np.array_equal(a.guides.histogram, b.guides.histogram)
    assert a.sparsity == b.sparsity and a.lipschitz == b.lipschitz
    rows = [{tuple(t) for t in outcome.kept.guides.triples.tolist()} for outcome in (a, b)]
    assert rows[0] == rows[1]


@pytest.mark.skipif(not geogram_available(), reason="the compiled module was not built")
@pytest.mark.parametrize("slabs", [True, False])
def test_geogram_and_gudhi_give_the_same_candidates_and_guides(torus_balls, slabs):
    """The two regular triangulations (geogram's exact one, CGAL's) propose the same triples,
    in slabs (a whole check) and as one triangulation (a tile), so the check is the same."""
    found = {}
    for engine in (Engine.gudhi, Engine.geogram):
        settings = _settings(torus_balls, slabs=slabs, engine=engine.value)
        found[engine] = pipeline.check_part(pipeline.TileJob.whole(torus_balls, settings))
    a, b = found[Engine.gudhi], found[Engine.geogram]
    assert a.guides.count == b.guides.count > 0
    assert a.candidates == b.candidates and a.with_seeds == b.with_seeds
    assert a.guides.maxima == b.guides.maxima and a.guides.counts == b.guides.counts
    assert np.array_equal(a.kept.guides.triples, b.kept.guides.triples)


def test_the_bounds_stage_runs_where_the_settings_have_none(torus_balls):
    """A whole check computes its bounds and the histogram's edges after λ (one rule,
    tiling.tally.gap_edges); a tile is given the driver's."""
    computed = pipeline.check_part(pipeline.TileJob.whole(torus_balls, _settings(torus_balls)))
    assert "bounds" in computed.seconds and len(computed.bounds) == 4
    given = _settings(
        torus_balls, bounds=computed.bounds, ratio_bounds=computed.ratio_bounds, edges=None
    )
    # Edges missing: the stage runs again and gives the same edges, so the same histogram.
    again = pipeline.check_part(pipeline.TileJob.whole(torus_balls, given))
    assert np.array_equal(again.guides.histogram, computed.guides.histogram)


def test_a_measured_lipschitz_needs_the_whole_sample(torus_balls):
    settings = _settings(torus_balls, measure_lipschitz=True)
    whole = pipeline.TileJob.whole(torus_balls, settings)
    outcome = pipeline.check_part(whole)
    assert outcome.params.lipschitz > 0  # L varies on this torus
    tile = dataclasses.replace(whole, beta=1.0)
    with pytest.raises(InputError, match="whole sample"):
        pipeline.check_part(tile)


def test_a_whole_check_without_guide_triangles_stops_after_the_seeds(monkeypatch):
    """As before the one pipeline: the error comes before any measurement or condition."""
    from vorobound.errors import NoGuideTriangles
    from vorobound.sampling.sampler import conditions

    def unreachable(*args, **kwargs):
        raise AssertionError("measured after the seeds stage")

    monkeypatch.setattr(pipeline, "measure_guides", unreachable)
    monkeypatch.setattr(conditions, "neighbours", unreachable)
    centers = np.array([[0.0, 0, 0], [5, 0, 0], [0, 5, 0], [0, 0, 5], [5, 5, 5]])
    balls = make_balls(centers, np.full(5, 0.1))
    params = SamplingParams(EPS, QualityParams(lipschitz=1.0))
    with pytest.raises(NoGuideTriangles, match="^far apart: no guide triangle"):
        whole_check.check_balls(balls, params, engine="brute", source="far apart")
