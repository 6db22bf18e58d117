"""A tiled check (streamed, tiles with halos) gives the untiled check's answer, bit for bit.

The guide triangles and every row measured on them are compared exactly, and every field of
the summary except the candidate counts (which depend on how space is cut: a tile proposes the
triangles of its own regular triangulation). Ball sets: a sphere (equal radii), a torus with
varying L, a row sample of a torus (near-lattice), balls of a CAD-like mesh with a sizing field;
tiles down to smaller than one ball. Plus the tile plan itself (ownership is a partition, the
halo rule equals its definition), a dask LocalCluster, and memory that does not grow with N.
"""

import json

import numpy as np
import pytest

from vorobound.bounds.params import QualityParams, SamplingParams
from vorobound.reports.check import check_balls, triangle_columns
from vorobound.reports.check_outputs import CheckOutputs
from vorobound.reports.check_tiled import check_ball_file
from vorobound.sampling.balls import make_balls
from vorobound.sampling.io.balls import pyarrow_available, read_balls, write_balls
from vorobound.sampling.sampler.maximal import sample_surface
from vorobound.sampling.sampler.torus_rows import torus_rows
from vorobound.sampling.surfaces.analytic import SphereShape, TorusShape
from vorobound.tiling import plan as tiles

pytest.importorskip("gudhi")

DECOMPOSITION_DEPENDENT = {"n_candidate_triples", "n_with_seeds", "timings"}
"""Summary fields that depend on the tiling (docs/scale.md); every other one must agree."""
TILED_ONLY = {"tiles", "worst"}


def _surface_balls(shape, eps, path, seed=0):
    sample = sample_surface(shape, eps, 0.75, seed=seed)
    balls = make_balls(sample.points, 2.0 * eps * sample.lfs)
    write_balls(path, balls, {})
    return path


def _mesh_balls(path, eps=0.3):
    from vorobound.sampling.surfaces.cad_meshes import l_bracket
    from vorobound.sampling.surfaces.mesh import MeshShape

    mesh = l_bracket()
    p = mesh.points
    shape = MeshShape(mesh, 0.6 + 0.05 * p[:, 0] + 0.03 * p[:, 2], "test sizing")
    return _surface_balls(shape, eps, path, seed=1)


def _row_balls(path, eps):
    parts = list(torus_rows(3.0, 1.0, eps))
    balls = make_balls(np.concatenate([c for c, _ in parts]), np.concatenate([r for _, r in parts]))
    write_balls(path, balls, {})
    return path


CASES = {
    "sphere": (lambda p: _surface_balls(SphereShape(1.0), 0.12, p), 0.12),
    "torus-varying-L": (lambda p: _surface_balls(TorusShape(1.5, 1.0), 0.1, p), 0.1),
    "torus-rows": (lambda p: _row_balls(p, 0.08), 0.08),
    "mesh": (_mesh_balls, 0.3),
}


def _rows(columns: dict) -> dict:
    order = np.lexsort((columns["c_index"], columns["b_index"], columns["a_index"]))
    return {name: np.asarray(values)[order] for name, values in columns.items()}


def _tiled_rows(parts_folder) -> dict:
    if pyarrow_available():
        import pyarrow.parquet as pq

        table = pq.read_table(sorted(parts_folder.glob("part-*.parquet")))
        return _rows({name: table.column(name).to_numpy() for name in table.column_names})
    frames = [np.genfromtxt(p, delimiter=",", names=True) for p in parts_folder.glob("*.csv")]
    table = np.concatenate([np.atleast_1d(f) for f in frames if f.size])
    return _rows({name: table[name] for name in table.dtype.names})


def _compare(path, eps, tmp_path, quality=None, lipschitz=1.0, **tiled):
    params = SamplingParams(eps, (quality or QualityParams()).but(lipschitz=lipschitz))
    untiled = check_balls(read_balls(path), params, source=path.name)
    table = "parquet" if pyarrow_available() else "csv"
    with CheckOutputs(tmp_path / "out", table, tiled=True) as outputs:
        report = check_ball_file(path, params, outputs=outputs, **tiled)
        got = _tiled_rows(outputs.parts)
    want = _rows(triangle_columns(untiled))
    assert got.keys() == want.keys()
    for name in want:  # the same guide triangles, the same measurements, bit for bit
        assert np.array_equal(got[name].astype(want[name].dtype), want[name], equal_nan=True), name
    a, b = untiled.summary(), report.summary()
    assert set(b) == set(a) | TILED_ONLY
    for key in set(a) - DECOMPOSITION_DEPENDENT - {"by_class"}:
        assert b[key] == a[key], key
    # Where a maximum sits depends on the order of ties (a whole sphere has many): compare
    # everything of the split by class but that.
    assert _without_worst(b["by_class"]) == _without_worst(a["by_class"])
    return report


def _without_worst(classes: dict) -> dict:
    return {
        name: {k: v for k, v in entry.items() if k != "worst"} if isinstance(entry, dict) else entry
        for name, entry in classes.items()
    }


# The varying-L torus at ε = 0.1 is slow here: test_violations_and_worst_pairs_are_counted_once
# compares the tiled and the untiled check of the same balls by default.
@pytest.mark.parametrize(
    "case",
    [pytest.param(c, marks=pytest.mark.slow) if c == "torus-varying-L" else c for c in CASES],
)
def test_tiled_check_equals_the_untiled_one(case, tmp_path):
    make, eps = CASES[case]
    path = make(tmp_path / f"{case}.npz")
    report = _compare(path, eps, tmp_path, tile_balls=max(200, len(read_balls(path)) // 6))
    assert report.run.tiling.tiles >= 4


def test_violations_and_worst_pairs_are_counted_once(tmp_path):
    """σ = 0.95 and λ = 0.05 for a sample made with σ = 0.75 and 1-Lipschitz L: many pairs
    break both, near tile borders too; counts and worst lists agree with the untiled check."""
    path = _surface_balls(TorusShape(1.5, 1.0), 0.1, tmp_path / "t.npz")
    report = _compare(
        path, 0.1, tmp_path, quality=QualityParams(sigma=0.95), lipschitz=0.05, tile_balls=500
    )
    s = report.summary()
    assert s["sparsity_violations"] > 100 and s["lipschitz_violations"] > 100
    assert len(s["sparsity_worst"]) == len(s["lipschitz_worst"]) == 10


def test_tiles_smaller_than_a_ball(tmp_path):
    # 503 balls in 63 tiles (ε = 0.4; at ε = 0.3 it was 896 balls in 112 tiles, twice the CPU).
    path = _surface_balls(TorusShape(1.5, 1.0), 0.4, tmp_path / "t.npz")
    report = _compare(path, 0.4, tmp_path, tile_balls=8, chunk_rows=100)
    assert report.run.tiling.tiles >= len(read_balls(path)) / 8
    # Boxes of about two balls each, halos of several radii: every ball is in many halos.
    assert report.summary()["tiles"]["halo_share"] > 10


def test_tiles_partition_the_balls_and_halos_follow_their_rule():
    rng = np.random.default_rng(3)
    centers = rng.uniform(-1, 1, (3000, 3)) * [1.0, 0.5, 0.2]
    radii = 0.02 + 0.08 * rng.random(3000)
    low, high = centers.min(axis=0), centers.max(axis=0)
    plan = tiles.plan_tiles(centers[::3], len(centers), 200, low, high)
    owner = plan.owner(centers)
    inside = (plan.lo[owner] <= centers).all(axis=1) & (centers <= plan.hi[owner]).all(axis=1)
    assert inside.all() and plan.count >= 10
    beta = 0.05 + 0.1 * rng.random(plan.count)
    rows, tile, core = plan.members(centers, radii, beta)
    assert np.array_equal(core, owner[rows] == tile) and np.all(np.diff(rows) >= 0)
    got = set(zip(rows.tolist(), tile.tolist(), strict=True))
    gap = np.stack([tiles.box_distance(centers, plan.lo[t], plan.hi[t]) for t in range(plan.count)])
    want = set(zip(*np.nonzero((gap <= radii + beta[:, None]).T), strict=True))
    assert got == want
    assert {(i, int(owner[i])) for i in range(len(centers))} <= got


def test_subsample_keeps_every_stride_th_row():
    sample = tiles.Subsample(limit=100)
    points = np.arange(3000 * 3, dtype=float).reshape(-1, 3)
    for start in range(0, 3000, 700):
        sample.add(start, points[start : start + 700])
    kept = sample.points()
    assert 50 <= len(kept) <= 100
    assert np.array_equal(kept[:, 0] / 3 % sample.stride, np.zeros(len(kept)))


@pytest.fixture(scope="module")
def torus_in_tiles(tmp_path_factory):
    """Balls of the torus (1.5, 1) at ε = 0.12 and their check in 7 forced tiles on one worker
    (in this process): the reference of the two tests below."""
    path = _surface_balls(TorusShape(1.5, 1.0), 0.12, tmp_path_factory.mktemp("t") / "t.npz")
    params = SamplingParams(0.12, QualityParams(lipschitz=1.0))
    return path, params, check_ball_file(path, params, workers=1, tile_balls=800).summary()


def test_dask_local_cluster_gives_the_same_summary(torus_in_tiles):
    distributed = pytest.importorskip("distributed")
    path, params, local = torus_in_tiles
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None
    ) as cluster:
        report = check_ball_file(path, params, scheduler=cluster.scheduler_address, tile_balls=800)
    remote = report.summary()
    assert remote["tiles"]["executor"] == "dask.distributed"
    for key in set(local) - DECOMPOSITION_DEPENDENT - TILED_ONLY:
        assert remote[key] == local[key], key


def test_one_and_two_workers_give_the_same_summary(torus_in_tiles):
    """Forced small tiles, the same plan: every field but the timings and the run's own
    description (executor, processes, memory) is identical, candidate counts too."""
    path, params, one = torus_in_tiles
    two = check_ball_file(path, params, workers=2, tile_balls=800).summary()
    assert one["tiles"]["count"] == two["tiles"]["count"] >= 6
    assert one["tiles"]["halo_share"] == two["tiles"]["halo_share"]
    for key in set(one) - {"timings", "tiles"}:
        assert two[key] == one[key], key


def test_tile_counts_are_even_and_the_tiles_equal():
    from vorobound.tiling.engine import MAX_TILE_SHARE, TILE_BALLS, tile_count, tile_size

    for balls in (100_000, 187_500, 187_501, 450_000, 1_001_674, 1_350_000, 10**7, 10**8):
        count = tile_count(balls)
        assert count == 1 or count % 2 == 0, balls
        assert balls / count <= MAX_TILE_SHARE * TILE_BALLS, balls
        assert tile_size(balls) * count >= balls
    # The planner makes exactly that many tiles of equal size from a subsample of the centers.
    centers = np.random.default_rng(5).uniform(-1, 1, (40_000, 3)) * [3.0, 2.0, 1.0]
    for balls in (1_001_674, 10**7):
        count, size = tile_count(balls), tile_size(balls)
        plan = tiles.plan_tiles(centers, balls, size, np.full(3, -3.0), np.full(3, 3.0), count)
        assert plan.count == count, balls
        sizes = np.bincount(plan.owner(centers))
        assert sizes.max() - sizes.min() <= 2, balls  # equal up to the rounding
    # 10⁶ balls: 6 tiles for any number of workers (it was 7 for 1 worker, 11 for 2).
    assert tile_count(1_001_674) == 6 and tile_count(10**5) == 1 and tile_count(10**7) == 66


MEMORY_PROBE = """
import resource, sys
from vorobound.bounds.params import QualityParams, SamplingParams
from vorobound.reports.check_outputs import CheckOutputs
from vorobound.reports.check_tiled import check_ball_file
from vorobound.tiling import plan as tiles
tiles.MAX_SUBSAMPLE = 2000
base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
check_ball_file(sys.argv[1], SamplingParams(float(sys.argv[2]), QualityParams(lipschitz=1.0)),
                tile_balls=3000, chunk_rows=4096)
print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - base)
"""


@pytest.mark.slow
def test_memory_does_not_grow_with_the_number_of_balls(tmp_path):
    """Peak resident memory of a whole tiled run (driver and tiles in one process) above its
    imports, tiles of the same size, for N and 4N balls: the driver keeps chunks, a bounded
    subsample and tallies, a tile its own balls."""
    import subprocess
    import sys

    growth = {}
    for eps in (0.1, 0.05):  # about 4 times as many balls at half the spacing
        path = _row_balls(tmp_path / f"rows-{eps}.npz", eps)
        done = subprocess.run(
            [sys.executable, "-c", MEMORY_PROBE, str(path), str(eps)],
            capture_output=True,
            text=True,
            check=True,
        )
        growth[eps] = int(done.stdout.split()[-1]) * 1024
    small, large = growth[0.1], growth[0.05]
    assert large < 1.25 * small + 20e6, (small, large)


def test_a_folder_joins_a_set_of_files(tmp_path):
    from vorobound.errors import WriteError
    from vorobound.files import TEMP_PREFIX, temporary_folder, write_set

    final = tmp_path / "rows"
    final.mkdir()
    (final / "old.txt").write_text("old")
    staged = temporary_folder(final)
    (staged / "new.txt").write_text("new")

    def fail(path):
        raise OSError(28, "No space left on device")

    with pytest.raises(WriteError, match="No space left"):
        write_set({tmp_path / "summary.json": fail}, {final: staged})
    assert (final / "old.txt").read_text() == "old"  # the failed set changed nothing
    written = write_set({tmp_path / "summary.json": lambda p: p.write_text("{}")}, {final: staged})
    assert written == [tmp_path / "summary.json", final]
    assert sorted(p.name for p in final.iterdir()) == ["new.txt"]
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(TEMP_PREFIX)]


def test_row_sample_is_sparse_and_covers():
    from vorobound.sampling.sampler import conditions
    from vorobound.sampling.sampler.torus_rows import torus_row_count

    eps = 0.05  # 126 rows: two chunks
    parts = list(torus_rows(3.0, 1.0, eps))
    centers = np.concatenate([c for c, _ in parts])
    assert len(centers) == torus_row_count(3.0, 1.0, eps) and len(parts) > 1
    lfs = np.ones(len(centers))  # L = r = 1 on the torus (3, 1)
    assert conditions.sparsity(centers, lfs, eps, 0.75).extreme >= 1
    probes, probe_lfs = TorusShape(3.0, 1.0).random_points(50_000, np.random.default_rng(1))
    assert conditions.coverage(centers, eps, probes, probe_lfs)[0] < 1
    assert np.allclose(np.concatenate([r for _, r in parts]), 2 * eps)


def test_a_local_pool_never_starts_more_processes_than_cpus():
    """--workers sets the tiling; the pool itself is capped at the CPU count (a typo such as
    --workers 1000 must not start a thousand processes)."""
    import os

    from vorobound.parallel import task_executor

    with task_executor(64) as (executor, slots):
        assert slots == 64
        assert executor._max_workers == min(64, os.cpu_count() or 1)
        assert sorted(executor.map(abs, [-3, -1, -2])) == [1, 2, 3]


@pytest.mark.parametrize("workers", [None, 1], ids=["whole", "tiled"])
def test_the_summary_is_built_once_per_run(workers, tmp_path, monkeypatch):
    """One check with outputs, its JSON, verdict and frame: the summary is assembled once
    (the whole and the tiled check share one builder, and the report caches it)."""
    import vorobound
    import vorobound.reports.check as whole
    import vorobound.reports.check_tiled as tiled

    built = []

    def counted(*args, **kwargs):
        built.append(1)
        return whole_fields(*args, **kwargs)

    whole_fields = whole.summary_fields
    monkeypatch.setattr(whole, "summary_fields", counted)
    monkeypatch.setattr(tiled, "summary_fields", counted)
    path = _surface_balls(TorusShape(1.5, 1.0), 0.3, tmp_path / "t.npz")
    result = vorobound.check(balls=path, eps=0.3, workers=workers, out=tmp_path / "out")
    result.to_dict(), result.verdict, result.ok, result.failures
    saved = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert saved["n_guide_triangles"] == result.n_guide_triangles > 0
    assert len(built) == 1
