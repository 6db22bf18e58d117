"""The compiled walk of the Lipschitz envelope (numba) against the numpy descent, the reference:
on many random queries it returns the minimum over every site's cone as the numpy path
computes each cone, never above the numpy path's value (equal on every query drawn here)."""

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vorobound.errors import VoroboundWarning
from vorobound.sampling.lfs.lipschitz import DistanceCap, Envelope, compiled_envelope

pytestmark = pytest.mark.skipif(
    compiled_envelope() is None, reason="needs numba (the compiled envelope)"
)


def _both(make, queries, monkeypatch, upper=None):
    """(compiled, numpy) values of the envelope ``make()`` at ``queries``."""
    fast = make()
    got = fast(queries, upper=upper)
    assert fast._flat is not None  # the compiled walk ran
    monkeypatch.setenv("VOROBOUND_PURE_NUMPY", "1")
    reference = make()
    expected = reference(queries, upper=upper)
    assert reference._flat is None
    monkeypatch.delenv("VOROBOUND_PURE_NUMPY")
    return got, expected


def _every_cone(envelope, queries, upper=None):
    """min over all sites of their cones, each computed by the numpy path's own arithmetic."""
    tree = envelope.tree
    out = np.full(len(queries), np.inf)
    if upper is not None:
        np.minimum(out, upper, out=out)
    for start in range(0, len(queries), 256):
        block = queries[start : start + 256]
        sites = np.arange(len(tree.sites))[None, :]
        cones = tree.cones(block[:, None, :], sites, envelope.slope).min(axis=1)
        np.minimum(out[start : start + 256], cones, out=out[start : start + 256])
    return out


def _draw(rng, count, kind):
    """Sites, values, radii and gradients of one kind of field."""
    scale = rng.choice([1e-3, 1.0, 1e3])
    if kind == "clusters":  # coinciding and tied sites
        centre = rng.normal(size=(count // 20, 3))
        sites = np.repeat(centre, 20, axis=0)
        sites = np.vstack([sites, rng.normal(size=(count - len(sites), 3))])
        sites += 1e-13 * rng.normal(size=(count, 3))
    elif kind == "bar":  # a long thin box of constant L, like the bar (ties everywhere)
        sites = rng.uniform([0, 0, 0], [100, 1, 1], (count, 3))
    else:
        sites = rng.normal(size=(count, 3)) * rng.uniform(0.1, 3, 3)
    sites = sites * scale
    if kind == "bar":
        values = np.full(count, 0.5) * scale
        values[rng.uniform(size=count) < 0.1] -= 1e-14 * scale
    else:
        values = rng.uniform(-1, 10, count) * scale
    radii = rng.uniform(0, 1, count) * scale * rng.choice([0.0, 0.3, 3.0])
    gradients = rng.normal(size=(count, 3))
    gradients /= np.linalg.norm(gradients, axis=1)[:, None]
    return sites, values, radii, gradients, scale


@pytest.mark.parametrize("kind", ["spread", "clusters", "bar"])
@pytest.mark.parametrize("field", ["cones", "planes", "cap"])
# Seed 1 draws other sites for the same nine cases: with the slow marker (about 2.5 CPU-s).
@pytest.mark.parametrize("seed", [0, pytest.param(1, marks=pytest.mark.slow)])
def test_compiled_envelope_is_the_minimum_of_every_cone(kind, field, seed, monkeypatch):
    """20 000 queries per case, near the sites and far away, with and without upper bounds:
    the compiled value is never above the numpy descent's value, and (at every tenth query)
    the minimum over every site's cone (the numpy path's arithmetic)."""
    rng = np.random.default_rng(seed)
    count = int(rng.integers(1, 2000))
    sites, values, radii, gradients, scale = _draw(rng, count, kind)
    slope = float(rng.choice([0.0, 0.3, 1.0, 2.5]))
    gradients = gradients * (slope * rng.uniform(0, 1, count))[:, None]
    gradients[rng.uniform(size=count) < 0.3] = 0.0
    near = sites[rng.integers(0, count, 15_000)] + 0.1 * scale * rng.normal(size=(15_000, 3))
    queries = np.vstack([near, sites[:100], rng.normal(size=(4900, 3)) * 5 * scale])
    upper = None
    if field == "cap":
        upper = np.where(rng.uniform(size=len(queries)) < 0.5, np.inf, rng.uniform(0, 3 * scale))

        def make():
            return DistanceCap(sites, np.abs(values), radii)

    elif field == "planes":

        def make():
            return Envelope(sites, values, slope, radii, gradients=gradients)

    else:

        def make():
            return Envelope(sites, values, slope, radii)

    got, expected = _both(make, queries, monkeypatch, upper)
    assert (got <= expected).all()
    some = slice(None, None, 10)
    bound = None if upper is None else upper[some]
    assert np.array_equal(got[some], _every_cone(make(), queries[some], bound))
    # The numpy descent keeps a minimum over a subset: at most rounding above.
    assert np.allclose(got, expected, rtol=1e-12, atol=1e-300)


@settings(max_examples=30, deadline=None)
@given(
    count=st.integers(1, 400),
    slope=st.floats(0, 3),
    seed=st.integers(0, 2**31),
    planes=st.booleans(),
)
def test_compiled_envelope_never_exceeds_the_numpy_descent(count, slope, seed, planes):
    rng = np.random.default_rng(seed)
    sites, values, radii, gradients, scale = _draw(rng, count, "spread")
    gradients = gradients * (slope * rng.uniform(0, 1, count))[:, None] if planes else None
    queries = np.vstack([sites[:5], rng.normal(size=(500, 3)) * scale])
    envelope = Envelope(sites, values, slope, radii, gradients=gradients)
    got = envelope(queries)
    expected = envelope._start(queries)
    envelope.tree.envelope(queries, envelope.slope, expected)
    assert (got <= expected).all()
    assert np.array_equal(got, _every_cone(envelope, queries))


def test_the_estimate_of_a_cad_part_is_the_same_by_both_paths(monkeypatch):
    """The bar of issue 32 (L estimated from the mesh): L at 200 000 surface points in the
    order of a lattice (sorted along the bar, as the sampler visits them) is the same to the
    last bit by both paths."""
    from vorobound.mesh import TriangleMesh
    from vorobound.sampling.lfs.estimate import estimate_lfs
    from vorobound.sampling.surfaces.cad_meshes import bar
    from vorobound.sampling.surfaces.mesh import points_on_mesh

    part = bar()
    mesh = TriangleMesh(part.points, part.triangles, "bar")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", VoroboundWarning)  # its sharp edges
        estimate = estimate_lfs(mesh)
    field = estimate._field
    points = points_on_mesh(mesh, 200_000, np.random.default_rng(0))
    points = points[np.argsort(points[:, 0])]

    def make():
        return Envelope(field.tree.sites, field.tree.values, field.slope, field.tree.radii)

    got, expected = _both(make, points, monkeypatch)
    assert np.array_equal(got, expected)
    assert np.array_equal(got, estimate.at(points))


def _tree_depth(count):
    from vorobound.sampling.lfs.lipschitz import LEAF_SIZE

    return max(0, int(np.ceil(np.log2(max(count / LEAF_SIZE, 1)))))


def _numpy_order(sites, depth):
    """The numpy path's order of the tree of ``sites`` (a sort per node)."""
    from vorobound.sampling.lfs.lipschitz import _ConeTree

    tree = _ConeTree.__new__(_ConeTree)
    tree.depth = depth
    return tree._numpy_order(sites)


def _assert_split_at_every_node(sites, order, depth):
    """At every level, each node (the slice of the order between the tree's bounds) holds in
    its first child only sites at most every site of its second child along the node's first
    widest axis (as np.argmax)."""
    from vorobound.sampling.lfs.lipschitz import _ConeTree

    count = len(sites)
    placed = sites[order]
    for level in range(depth):
        parent = _ConeTree._bounds(level, count)
        child = _ConeTree._bounds(level + 1, count)
        extent = np.maximum.reduceat(placed, parent[:-1]) - np.minimum.reduceat(placed, parent[:-1])
        axis = np.argmax(extent, axis=1)
        along = placed[np.arange(count), np.repeat(axis, np.diff(parent))]
        first_max = np.maximum.reduceat(along, child[:-1])[0::2]
        second_min = np.minimum.reduceat(along, child[:-1])[1::2]
        assert (first_max <= second_min).all(), f"level {level}"


@settings(max_examples=40, deadline=None)
@given(
    count=st.integers(1, 3000),
    grid=st.sampled_from([0, 1, 4, 64]),
    flat=st.integers(0, 3),
    seed=st.integers(0, 2**31),
)
def test_the_compiled_tree_order_splits_every_node_along_its_widest_axis(count, grid, flat, seed):
    # Ties along an axis (sites on a coarse grid, or flat in some coordinates) are where a
    # selection may loop or split at the wrong place.
    sites = np.random.default_rng(seed).random((count, 3))
    if grid:
        sites = np.round(sites * grid) / grid
    sites[:, :flat] = 0.5
    depth = _tree_depth(count)
    order = compiled_envelope().tree_order(sites, depth)
    np.testing.assert_array_equal(np.sort(order), np.arange(count))
    _assert_split_at_every_node(sites, order, depth)
    _assert_split_at_every_node(sites, _numpy_order(sites, depth), depth)
    if not grid and flat < 3:
        # No ties along any widest axis: every leaf holds the same sites as the numpy path's
        # leaf (in some order), so every node does.
        bounds = np.arange(2**depth + 1) * count // 2**depth
        leaf = np.repeat(np.arange(2**depth), np.diff(bounds)) * count
        np.testing.assert_array_equal(
            np.sort(leaf + order), np.sort(leaf + _numpy_order(sites, depth))
        )


@pytest.mark.parametrize("field", ["cones", "planes", "cap"])
def test_the_envelope_is_the_same_for_the_compiled_and_the_numpy_order(field, monkeypatch):
    """Two trees of the same sites, one in the selection's order and one in the numpy path's
    sorted order, give the compiled walk the same value at every query, bit for bit (it
    returns the minimum over all sites' cones whatever the tree). The sites lie on a coarse
    grid: without ties the two orders put the same sites in each leaf."""
    module = compiled_envelope()
    rng = np.random.default_rng(7)
    count = 5000
    sites, values, radii, gradients, scale = _draw(rng, count, "spread")
    sites = np.round(sites / scale * 4) * scale / 4
    slope = 0.7
    gradients = gradients * (slope * rng.uniform(0, 1, count))[:, None]
    near = sites[rng.integers(0, count, 20_000)] + 0.1 * scale * rng.normal(size=(20_000, 3))
    queries = np.vstack([near, rng.normal(size=(5000, 3)) * 5 * scale])

    def make():
        if field == "cap":
            return DistanceCap(sites, np.abs(values), radii)
        planes = gradients if field == "planes" else None
        return Envelope(sites, values, slope, radii, gradients=planes)

    selected = make()
    got = selected(queries)
    monkeypatch.setattr(module, "tree_order", _numpy_order)
    sorted_ = make()
    expected = sorted_(queries)
    assert sorted_._flat is not None  # the compiled walk, on the sorted tree
    assert not np.array_equal(selected.tree.order, sorted_.tree.order)
    np.testing.assert_array_equal(got, expected)


@pytest.mark.parametrize("field", ["cones", "planes"])
def test_a_cutoff_changes_nothing_above_it(field):
    """With a cutoff per query, the walk may stop at the first cone at most the cutoff: where
    the envelope is above the cutoff the value is the same to the last bit, elsewhere it lies
    between the envelope and the cutoff; so max(value, cutoff) never changes."""
    rng = np.random.default_rng(3)
    count = 3000
    sites, values, radii, gradients, scale = _draw(rng, count, "spread")
    slope = 0.5
    gradients = (
        None if field == "cones" else gradients * (slope * rng.uniform(0, 1, count))[:, None]
    )
    queries = sites[rng.integers(0, count, 20_000)] + 0.1 * scale * rng.normal(size=(20_000, 3))
    envelope = Envelope(sites, values, slope, radii, gradients=gradients)
    exact = envelope(queries)
    cutoff = np.quantile(exact, 0.5) + scale * rng.normal(size=len(queries))
    got = envelope(queries, cutoff=cutoff)
    above = exact > cutoff
    assert 0.2 < above.mean() < 0.8  # both cases are tried
    assert np.array_equal(got[above], exact[above])
    assert (exact[~above] <= got[~above]).all() and (got[~above] <= cutoff[~above]).all()
    assert np.array_equal(np.maximum(got, cutoff), np.maximum(exact, cutoff))
    assert (got[~above] > exact[~above]).any()  # some walks did stop early
