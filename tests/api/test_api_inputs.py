"""Library entry points refuse what is not a real number instead of guessing."""

import numpy as np
import pytest

from vorobound import theorem1_from_edges, weighted_triangles
from vorobound.errors import InputError

POINTS = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]


@pytest.mark.parametrize(
    "points",
    [
        "0,0 1,0 0,1",
        {"a": 1},
        np.array(POINTS) + 0j,
        [[0, 0], [1, 0], [0]],
    ],
)
def test_non_numeric_or_complex_points_raise_input_error(points):
    with pytest.raises(InputError):
        weighted_triangles(points, [0.0, 0.0, 0.0])


def test_complex_weights_and_edges_raise():
    with pytest.raises(InputError, match="complex"):
        weighted_triangles(POINTS, np.array([0, 0.1, 0.2]) + 1e-3j)
    with pytest.raises(InputError, match="complex"):
        theorem1_from_edges(np.array([3.0, 4.0, 5.0]) + 0j, [0, 0, 0])


def test_masked_entries_make_their_rows_invalid():
    points = np.ma.array(np.tile(np.array(POINTS), (3, 1, 1)))
    points[1, 2, 0] = np.ma.masked
    weights = np.ma.array(np.zeros((3, 3)), mask=[[0, 0, 0], [0, 0, 0], [0, 1, 0]])
    result = weighted_triangles(points, weights)
    assert result.valid.tolist() == [True, False, False]
    assert np.isnan(result.radius_gap[1:]).all()
    assert result.circumradius[0] == pytest.approx(np.sqrt(0.5))


@pytest.mark.parametrize("method", ["abc", None, 0, np.array(["auto", "optimize"])])
@pytest.mark.parametrize("mode", ["tight", "rigorous"])
def test_a_bad_method_is_an_input_error_in_every_mode(method, mode):
    """solve/bound raised a bare ValueError from the enum for a bad method (tight mode) or
    ignored it (chain modes)."""
    import vorobound

    with pytest.raises(InputError, match="method must be auto or optimize"):
        vorobound.solve(method=method, mode=mode)
    with pytest.raises(InputError, match="method must be auto or optimize"):
        vorobound.bound(eps=0.005, method=method, mode=mode)
    with pytest.raises(InputError, match="method must be auto or optimize"):
        vorobound.sweep(method=method, mode=mode)


def test_sweep_axes_take_numpy_scalars_and_refuse_empty_or_odd_values():
    """A numpy scalar axis was a TypeError ('not iterable'), an empty eps axis a
    ZeroDivisionError, a float mode a TypeError."""
    import vorobound

    plain = vorobound.sweep(sigma=0.75, rho_f=1.38, mode="tight")
    numpy = vorobound.sweep(sigma=np.float32(0.75), rho_f=np.float64(1.38), mode="tight")
    assert [r.eps_star for r in numpy.rows] == pytest.approx([r.eps_star for r in plain.rows])
    for bad in ({"eps": ()}, {"eps": []}, {"mode": float("nan")}, {"sigma": object()}):
        with pytest.raises(InputError):
            vorobound.sweep(**bad)


def test_cheng_takes_every_accepted_seed_and_refuses_an_array_dim(run_cli):
    """A seed of 2³² or more (accepted, up to 2⁶³ − 1) reached scipy's legacy RandomState
    and was an internal error (exit 70)."""
    import vorobound

    code, _, err = run_cli("cheng", "--alpha", "0.3", "--seed", str(2**32))
    assert code == 0, err
    with pytest.raises(InputError, match="dim must be 2"):
        vorobound.cheng(alpha=0.3, dim=np.array([2, 3]))


def test_check_and_reconstruct_refuse_odd_engines_and_formats_and_take_numpy_eps(tmp_path):
    """A bad engine was a bare ValueError from the enum, an array figure_format an
    'ambiguous truth value' ValueError, and reconstruct(eps=np.float64(...)) a TypeError."""
    import vorobound

    balls = tmp_path / "b.npz"
    vorobound.sample(sphere=1, eps=0.2, output=balls)
    for engine in ("abc", None, 3):
        with pytest.raises(InputError, match="engine must be"):
            vorobound.check(balls=balls, eps=0.2, engine=engine)
    with pytest.raises(InputError, match="figure_format"):
        vorobound.check(balls=balls, eps=0.2, figure_format=np.array(["png", "svg"]))
    numpy = vorobound.reconstruct(balls=balls, eps=np.float64(0.2))
    plain = vorobound.reconstruct(balls=balls, eps=0.2)
    assert numpy.n_facets == plain.n_facets and numpy.closed_manifold and numpy.ok
    assert numpy.topology_correct is None  # balls alone: no reference surface
