"""The compiled kernel (numba) against the numpy path and the mpmath reference."""

import numpy as np
import pytest
from hard_triangles import families
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from mp_reference import reference, relative_error

from vorobound import theorem1_from_edges, weighted_triangles
from vorobound.geometry import triangle as triangle_module

pytest.importorskip("numba")
from vorobound.geometry import compiled  # noqa: E402
from vorobound.geometry.precision import EPS64, ERROR_GROWTH, REFINE_TOLERANCE  # noqa: E402

DELTA_RTOL = 1e-12
REFINE_TEST = (ERROR_GROWTH * EPS64, REFINE_TOLERANCE)


def _stress_batch(dim: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Ordinary, hard and bad rows mixed: every branch of the kernel and of the fallback."""
    parts = [(p, w) for p, w in families(seed=dim).values() if p.shape[-1] == dim]
    n = 5000
    scales = 10.0 ** rng.integers(-150, 150, (n, 1, 1))
    points = rng.standard_normal((n, 3, dim)) * scales
    weights = rng.uniform(-0.3, 0.3, (n, 3)) * scales[:, :, 0] ** 2
    weights[::5] = rng.random((n // 5, 3)) * 1e-14 * scales[::5, :, 0] ** 2
    weights[1::7] = 4.0 * scales[1::7, :, 0] ** 2  # equal and large: orthoradius_sq < 0
    points[2::11, 2] = points[2::11, 1]  # coincident vertices
    points[3::13, 2] = 2 * points[3::13, 1] - points[3::13, 0]  # collinear
    points[4::17, 0, 0] = np.nan
    weights[5::19, 1] = np.inf
    huge, tiny = slice(6, None, 23), slice(7, None, 29)
    points[huge] = rng.standard_normal(points[huge].shape) * 1e200  # overflows once squared
    weights[huge] = 0.1
    points[tiny] = rng.standard_normal(points[tiny].shape) * 1e-200  # underflows once squared
    weights[tiny] = 1e-401
    parts.append((points, weights))
    return np.concatenate([p for p, _ in parts]), np.concatenate([w for _, w in parts])


def _assert_same_bits(value: np.ndarray, expected: np.ndarray, name: str) -> None:
    """Equal dtype, shape and bits (the sign of a zero included); any NaN matches any NaN."""
    assert value.dtype == expected.dtype, name
    assert value.shape == expected.shape, name
    if value.dtype.kind != "f":
        np.testing.assert_array_equal(value, expected, err_msg=name)
        return
    nan = np.isnan(value)
    np.testing.assert_array_equal(nan, np.isnan(expected), err_msg=name)
    np.testing.assert_array_equal(
        value[~nan].view(np.uint64), expected[~nan].view(np.uint64), err_msg=name
    )


def _fields(result):
    return {
        name: getattr(result, name)
        for name in result.__dataclass_fields__
        if getattr(result, name) is not None
    }


@pytest.mark.parametrize("dim", [2, 3])
def test_compiled_kernel_matches_numpy_path_bit_for_bit(dim, monkeypatch):
    monkeypatch.setattr(triangle_module, "COMPILED_MIN_ROWS", 1)
    points, weights = _stress_batch(dim, np.random.default_rng(dim))
    fast = _fields(weighted_triangles(points, weights))
    monkeypatch.setenv("VOROBOUND_PURE_NUMPY", "1")
    slow = _fields(weighted_triangles(points, weights))
    assert fast.keys() == slow.keys()
    for name, value in fast.items():
        _assert_same_bits(value, slow[name], name)
    # The batch really exercised both outcomes, and both paths.
    assert fast["valid"].sum() > len(points) // 2
    assert (~fast["valid"]).sum() > 100
    _, rest, refine = compiled.run_compiled(points, weights, *REFINE_TEST)
    assert rest.size > 0 and refine.size > 0
    assert rest.size + refine.size < len(points) // 2  # the kernel did most rows itself


def _edge_lengths(points: np.ndarray) -> np.ndarray:
    """Edge i opposite vertex i, as a user would measure them."""
    with np.errstate(all="ignore"):
        return np.stack(
            [
                np.linalg.norm(points[:, (i + 2) % 3] - points[:, (i + 1) % 3], axis=1)
                for i in range(3)
            ],
            axis=1,
        )


def test_compiled_edges_kernel_matches_numpy_path_bit_for_bit(monkeypatch):
    monkeypatch.setattr(triangle_module, "COMPILED_MIN_ROWS", 1)
    rng = np.random.default_rng(5)
    points, weights = _stress_batch(3, rng)
    lengths = _edge_lengths(points)
    lengths[8::31, 0] = lengths[8::31, 1] + lengths[8::31, 2] * 1.5  # triangle inequality fails
    lengths[9::37, 2] = -lengths[9::37, 2]  # negative edge
    lengths[10::41, 1] = 0.0
    fast = _fields(theorem1_from_edges(lengths, weights))
    monkeypatch.setenv("VOROBOUND_PURE_NUMPY", "1")
    slow = _fields(theorem1_from_edges(lengths, weights))
    assert fast.keys() == slow.keys()
    assert "circumcenter" not in fast and "radius_gap_direct" not in fast
    for name, value in fast.items():
        _assert_same_bits(value, slow[name], name)
    assert fast["valid"].sum() > len(lengths) // 2
    assert (~fast["valid"]).sum() > 100
    _, rest, refine = compiled.run_compiled_edges(lengths, weights, *REFINE_TEST)
    assert 0 < rest.size + refine.size < len(lengths) // 2  # the kernel did most rows itself


def test_large_batches_use_the_compiled_kernel(monkeypatch):
    calls = []
    real = compiled.triangles_kernel

    def spy(points, weights, start, stop, *args):
        calls.append((start, stop))
        return real(points, weights, start, stop, *args)

    monkeypatch.setattr(compiled, "triangles_kernel", spy)
    rng = np.random.default_rng(0)
    n = triangle_module.COMPILED_MIN_ROWS
    weighted_triangles(rng.standard_normal((n - 1, 3, 3)), [0.0, 0.1, 0.2])
    assert calls == []
    weighted_triangles(rng.standard_normal((n, 3, 3)), [0.0, 0.1, 0.2])
    # Chunks that tile the batch exactly, one kernel call each.
    covered = sorted(calls)
    assert covered[0][0] == 0 and covered[-1][1] == n
    assert all(a[1] == b[0] for a, b in zip(covered, covered[1:], strict=False))
    calls.clear()
    monkeypatch.setenv("VOROBOUND_PURE_NUMPY", "1")
    weighted_triangles(rng.standard_normal((n, 3, 3)), [0.0, 0.1, 0.2])
    assert calls == []


@pytest.mark.parametrize("name", sorted(families()))
def test_compiled_path_matches_mpmath_on_hard_triangles(name, monkeypatch):
    monkeypatch.setattr(triangle_module, "COMPILED_MIN_ROWS", 1)
    points, weights = families()[name]
    result = weighted_triangles(points, weights)
    assert result.valid.all()
    for i in range(0, len(points), 4):
        ref = reference(points[i], weights[i])
        assert relative_error(result.radius_gap[i], ref["delta"]) <= DELTA_RTOL


def _batch_delta_sum(seed: int) -> float:
    rng = np.random.default_rng(seed)
    points = rng.standard_normal((triangle_module.COMPILED_MIN_ROWS, 3, 3))
    return float(weighted_triangles(points, [0.0, 0.1, 0.2]).radius_gap.sum())


def test_a_process_that_used_the_kernel_can_fork_and_use_it_again():
    # An OpenMP runtime in the parent would abort the forked child; plain threads do not.
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    expected = [_batch_delta_sum(seed) for seed in (1, 2)]
    fork = multiprocessing.get_context("fork")
    # A child that aborts breaks the pool (an error here), rather than hanging the test.
    with ProcessPoolExecutor(2, mp_context=fork) as pool:
        assert list(pool.map(_batch_delta_sum, [1, 2])) == expected


def test_concurrent_calls_from_threads_agree():
    from concurrent.futures import ThreadPoolExecutor

    expected = [_batch_delta_sum(seed) for seed in range(4)]
    with ThreadPoolExecutor(4) as pool:
        assert list(pool.map(_batch_delta_sum, range(4))) == expected


def test_batch_shapes_and_broadcast_weights_on_the_compiled_path(monkeypatch):
    monkeypatch.setattr(triangle_module, "COMPILED_MIN_ROWS", 1)
    rng = np.random.default_rng(3)
    points = rng.standard_normal((4, 5, 3, 3))
    fast = weighted_triangles(points, [0.0, 0.01, 0.02])
    assert fast.radius_gap.shape == (4, 5)
    assert fast.circumcenter.shape == (4, 5, 3)
    assert fast.edges.shape == (4, 5, 3)
    monkeypatch.setenv("VOROBOUND_PURE_NUMPY", "1")
    slow = weighted_triangles(points, [0.0, 0.01, 0.02])
    for name, value in _fields(fast).items():
        _assert_same_bits(value, getattr(slow, name), name)


def test_a_kernel_that_cannot_load_falls_back_with_a_warning(monkeypatch):
    import sys

    import vorobound.geometry

    monkeypatch.setattr(triangle_module, "COMPILED_MIN_ROWS", 1)
    monkeypatch.delattr(vorobound.geometry, "compiled")
    monkeypatch.setitem(sys.modules, "vorobound.geometry.compiled", None)  # import fails
    triangle_module._load_compiled.cache_clear()
    try:
        with pytest.warns(RuntimeWarning, match="numpy path"):
            assert not triangle_module.compiled_available()
        result = weighted_triangles([[0, 0], [1, 0], [0, 1]], [0.0, 0.1, 0.2])
        assert result.valid.all()
    finally:
        triangle_module._load_compiled.cache_clear()


def _any_float(width=64):
    return st.floats(allow_nan=True, allow_infinity=True, width=width)


@settings(
    max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    st.integers(2, 3).flatmap(
        lambda dim: arrays(
            np.float64,
            st.tuples(st.integers(1, 40), st.just(3), st.just(dim)),
            elements=st.one_of(st.floats(-1e3, 1e3), _any_float()),
        )
    ),
    st.data(),
)
def test_compiled_and_numpy_paths_agree_on_arbitrary_input(monkeypatch, points, data):
    weights = data.draw(
        arrays(
            np.float64,
            (points.shape[0], 3),
            elements=st.one_of(st.floats(-1e2, 1e2), _any_float()),
        )
    )
    monkeypatch.setattr(triangle_module, "COMPILED_MIN_ROWS", 1)
    monkeypatch.delenv("VOROBOUND_PURE_NUMPY", raising=False)
    fast = _fields(weighted_triangles(points, weights))
    lengths = np.abs(points[:, :, 0])
    fast_edges = _fields(theorem1_from_edges(lengths, weights))
    monkeypatch.setenv("VOROBOUND_PURE_NUMPY", "1")
    slow = _fields(weighted_triangles(points, weights))
    slow_edges = _fields(theorem1_from_edges(lengths, weights))
    for got, want in ((fast, slow), (fast_edges, slow_edges)):
        for name, value in got.items():
            _assert_same_bits(value, want[name], name)


@pytest.mark.parametrize(
    "points, weights",
    [
        ([[0, 0], [0, 1], [1, 1.0]], [1, 0, 0.5]),  # right angle at the apex: cos θ = ±0
        ([[0, 0], [0, 1], [1, -1.0]], [0.0, -0.0, -0.0]),  # tied ±0 weights: k = ±0
    ],
)
def test_signed_zeros_agree(points, weights, monkeypatch):
    monkeypatch.setattr(triangle_module, "COMPILED_MIN_ROWS", 1)
    fast = _fields(weighted_triangles([points], [weights]))
    fast_edges = _fields(theorem1_from_edges(_edge_lengths(np.array([points])), [weights]))
    monkeypatch.setenv("VOROBOUND_PURE_NUMPY", "1")
    slow = _fields(weighted_triangles([points], [weights]))
    slow_edges = _fields(theorem1_from_edges(_edge_lengths(np.array([points])), [weights]))
    for got, want in ((fast, slow), (fast_edges, slow_edges)):
        for name, value in got.items():
            _assert_same_bits(value, want[name], name)
