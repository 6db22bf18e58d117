"""``vorobound sample --mesh M --workers N``: the slab sampler streamed to its file, two-coloured
slabs on workers. The sample is σ-sparse and ε-dense (brute force), the same for 1 and 2
workers and for a dask cluster, the file equals the in-memory sample, and a failed run leaves
the previous file as it was."""

import warnings

import numpy as np
import pytest
from scipy.spatial import cKDTree
from scipy.spatial.distance import cdist

import vorobound
from vorobound.errors import VoroboundWarning
from vorobound.files import TEMP_PREFIX
from vorobound.sampling.io.balls import write_balls
from vorobound.sampling.sampler import conditions, slabs
from vorobound.sampling.sampler.maximal import sample_surface
from vorobound.sampling.surfaces import cad_meshes

EPS, SIGMA = 0.2, 0.75


@pytest.fixture(scope="module")
def cylinder():
    """The 2-ring CAD cylinder (long slivers, sharp rims), 10 long: its L is estimated once
    and cached on the mesh object."""
    return cad_meshes.capped_cylinder(length=10.0, rings=2)


@pytest.fixture
def thin_slabs(monkeypatch):
    """Slabs as thin as the conflict radius allows: about ten on this part."""
    monkeypatch.setattr(slabs, "MAX_SLAB_CANDIDATES", 1000.0)


def _sample(mesh, output, **options):
    totals = []

    def progress(task, done, total):
        if task == "sampling (slabs)" and done == 0:
            totals.append(total)

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", VoroboundWarning)  # the rims' sharp-edge warning
        result = vorobound.sample(mesh=mesh, eps=EPS, output=output, progress=progress, **options)
    return result, totals[0]


def _brute_sparsity(points, lfs):
    dist = cdist(points, points)
    np.fill_diagonal(dist, np.inf)
    return float((dist / (SIGMA * EPS * np.minimum.outer(lfs, lfs))).min())


def _shape(mesh):
    from vorobound.api.surfaces import Surface

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", VoroboundWarning)
        return Surface(mesh=mesh).shape()


@pytest.fixture(scope="module")
def two_workers(cylinder, tmp_path_factory):
    """One run on two worker processes with thin slabs, streamed to a CSV file (seed 4): the
    two tests below read it (a run on two processes costs about 1.5 CPU-s).
    (result, slab count, path, table)."""
    path = tmp_path_factory.mktemp("two") / "s.csv"
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(slabs, "MAX_SLAB_CANDIDATES", 1000.0)  # as thin_slabs
        result, count = _sample(cylinder, path, workers=2, seed=4)
    return result, count, path, np.loadtxt(path, delimiter=",", skiprows=1)


def test_one_and_two_workers_give_one_sparse_covering_sample(
    cylinder, thin_slabs, two_workers, tmp_path
):
    result, count = _sample(cylinder, tmp_path / "w1.npz", workers=1, seed=4)
    assert count >= 6 and result.ok and result.workers == 1
    one = dict(np.load(tmp_path / "w1.npz"))
    assert one.keys() == {"x", "y", "z", "radius", "lfs"}
    two, two_count, _, table = two_workers
    assert two_count == count and two.ok and two.workers == 2
    for column, name in enumerate(("x", "y", "z", "radius", "lfs")):  # the file's columns
        assert np.array_equal(one[name], table[:, column]), name
    points = np.column_stack([one[n] for n in "xyz"])
    lfs = one["lfs"]
    assert _brute_sparsity(points, lfs) >= 1.0  # every pair, across every slab border
    probes, probe_lfs = _shape(cylinder).random_points(300_000, np.random.default_rng(5))
    gap, _ = cKDTree(points).query(probes)
    assert float((gap / (EPS * probe_lfs)).max()) < 1.0
    assert result.n_samples == len(points)


def test_the_streamed_file_and_measures_equal_the_in_memory_sample(
    two_workers, cylinder, thin_slabs, tmp_path
):
    result, _, streamed, table = two_workers  # two workers, thin slabs, seed 4
    shape = _shape(cylinder)
    whole = sample_surface(shape, EPS, SIGMA, seed=4)  # in memory, in this process
    assert np.array_equal(table[:, :3], whole.points) and np.array_equal(table[:, 4], whole.lfs)
    # The same text as the whole-array writer gives.
    write_balls(tmp_path / "w.csv", _balls(whole, result.quality.at(EPS).delta), {"lfs": whole.lfs})
    assert streamed.read_text() == (tmp_path / "w.csv").read_text()
    # Block-wise measures equal the whole-set ones (same probes).
    sparse = conditions.sparsity(whole.points, whole.lfs, EPS, SIGMA)
    assert result.sparsity_min == sparse.extreme and result.sparsity_violations == 0
    coverage, _, probes = conditions.surface_coverage(shape, whole.points, EPS, 4)
    assert result.coverage_max == coverage and result.coverage_probes == probes


def _balls(sample, delta):
    from vorobound.sampling.balls import make_balls

    return make_balls(sample.points, delta * sample.lfs)


def test_a_vtu_holds_the_same_sample(cylinder, tmp_path):
    import meshio

    _sample(cylinder, tmp_path / "s.vtu")
    _sample(cylinder, tmp_path / "s.npz")
    vtu, npz = meshio.read(tmp_path / "s.vtu"), np.load(tmp_path / "s.npz")
    assert np.array_equal(vtu.points[:, 0], npz["x"])
    assert np.array_equal(vtu.point_data["lfs"], npz["lfs"])


def test_a_dask_cluster_gives_the_same_sample(cylinder, thin_slabs, tmp_path):
    distributed = pytest.importorskip("distributed")
    _sample(cylinder, tmp_path / "one.npz")
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None
    ) as cluster:
        _sample(cylinder, tmp_path / "dask.npz", scheduler=cluster.scheduler_address)
    one, remote = np.load(tmp_path / "one.npz"), np.load(tmp_path / "dask.npz")
    assert all(np.array_equal(one[n], remote[n]) for n in one.files)


def test_a_failed_run_leaves_the_previous_file(cylinder, thin_slabs, tmp_path, monkeypatch):
    target = tmp_path / "s.npz"
    target.write_bytes(b"previous")
    calls = []
    real = slabs.run_slab

    def failing(job):
        calls.append(job.slab)
        if len(calls) == 4:
            raise RuntimeError("slab failed")
        return real(job)

    monkeypatch.setattr(slabs, "run_slab", failing)
    with pytest.raises(RuntimeError, match="slab failed"):
        _sample(cylinder, target)
    assert target.read_bytes() == b"previous"
    assert not [p.name for p in tmp_path.iterdir() if p.name.startswith(TEMP_PREFIX)]


@pytest.mark.parametrize(
    "args, message",
    [
        (["--workers", "0"], "workers"),
        (["--workers", "99999999"], "workers"),
        (["--workers", "two"], "workers"),
    ],
)
def test_bad_workers_are_one_line(run_cli, tmp_path, args, message):
    code, out, err = run_cli(
        "sample", "--sphere", "1", "--eps", "0.2", "-o", str(tmp_path / "s.npz"), *args
    )
    assert code == 2 and not out
    assert len(err.strip().splitlines()) == 1 and message in err


def test_workers_go_with_a_mesh(run_cli, tmp_path):
    code, _, err = run_cli(
        "sample", "--sphere", "1", "--eps", "0.2", "-o", str(tmp_path / "s.npz"), "--workers", "2"
    )
    assert code == 2 and err.count("\n") == 1 and "mesh" in err
    assert not (tmp_path / "s.npz").exists()


def test_a_folder_that_refuses_files_fails_before_sampling(
    run_cli, cylinder, tmp_path, monkeypatch
):
    """Found by hand: ``-o /sys/x.npz`` (a folder that exists but takes no file) failed only
    after the whole sample was made. The folder is tried first; the previous file stays."""
    import vorobound.files

    target = tmp_path / "s.npz"
    target.write_bytes(b"previous")
    ran = []
    monkeypatch.setattr(slabs, "slab_sample", lambda *a, **k: ran.append(1))

    def refused(*args, **kwargs):
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(vorobound.files.tempfile, "mkstemp", refused)
    code, out, err = run_cli(*_sample_args(cylinder, tmp_path, "--workers", "2"))
    assert code == 2 and not out and not ran
    assert err.strip().splitlines() == [f"error: cannot write {target}: Permission denied"]
    assert target.read_bytes() == b"previous"


def _sample_args(mesh, folder, *options):
    """``sample --mesh FOLDER/mesh.stl --eps 0.2 -o FOLDER/s.npz OPTIONS``, the mesh written."""
    import meshio

    path = folder / "mesh.stl"
    meshio.write(path, meshio.Mesh(mesh.points, [("triangle", mesh.triangles)]))
    return ("sample", "--mesh", str(path), "--eps", "0.2", "-o", str(folder / "s.npz"), *options)


def test_workers_with_a_scheduler_are_one_line(run_cli, cylinder, tmp_path, monkeypatch):
    """Found by hand: ``--workers 4 --scheduler ADDRESS`` ignored the 4 and its --json said
    ``"workers": 4`` for a run on the cluster's workers."""
    ran = []
    monkeypatch.setattr(slabs, "slab_sample", lambda *a, **k: ran.append(1))
    code, out, err = run_cli(
        *_sample_args(cylinder, tmp_path, "--workers", "4", "--scheduler", "tcp://127.0.0.1:1")
    )
    assert code == 2 and not out and err.count("\n") == 1
    assert "workers" in err and "scheduler" in err and "not both" in err
    assert not ran and not (tmp_path / "s.npz").exists()


def test_an_interrupt_while_the_spill_is_removed_leaves_no_spill(cylinder, tmp_path, monkeypatch):
    """Found by hand: Ctrl-C just after the sample file was written left the spill folder
    (``.vorobound-tmp-samples.*``) in the temporary folder: the removal stopped at the
    interrupt. It is now finished first, then the interrupt goes on."""
    import shutil
    import signal
    import tempfile

    spills = tmp_path / "tmp"
    spills.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(spills))
    real, raised = shutil.rmtree, []

    def interrupted_rmtree(path, *args, **kwargs):
        if not raised and f"{TEMP_PREFIX}samples." in str(path):
            raised.append(path)
            signal.raise_signal(signal.SIGINT)  # Python's handler: KeyboardInterrupt here
        return real(path, *args, **kwargs)

    monkeypatch.setattr(shutil, "rmtree", interrupted_rmtree)
    with pytest.raises(KeyboardInterrupt):
        _sample(cylinder, tmp_path / "s.npz")
    assert raised and not list(spills.iterdir())
    assert np.load(tmp_path / "s.npz")["x"].size  # written before the interrupt


def test_a_dead_scheduler_is_told_before_the_l_estimate(run_cli, cylinder, tmp_path, monkeypatch):
    """Found by the hostile-input pass: ``sample --mesh --scheduler DEAD`` spent the whole L
    estimate (minutes on a real part) before it found that no scheduler answers."""
    pytest.importorskip("distributed")
    from vorobound.api import surfaces

    estimated = []
    monkeypatch.setattr(surfaces.Surface, "shape", lambda *a, **k: estimated.append(1))
    code, out, err = run_cli(*_sample_args(cylinder, tmp_path, "--scheduler", "tcp://127.0.0.1:9"))
    assert code == 2 and not out and err.count("\n") == 1
    assert "cannot reach the dask scheduler" in err
    assert not estimated and not (tmp_path / "s.npz").exists()
