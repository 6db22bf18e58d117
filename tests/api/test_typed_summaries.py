"""The typed fields the CLI renders (issue 30): a check's and a reconstruction's ``summary``
read their JSON field by field, so the tables show the ``--json`` numbers, and a field the JSON
lacks is an error, not a silent default."""

import dataclasses

import pytest

import vorobound
from vorobound.api.check_summary import CheckSummary
from vorobound.api.result import typed_view


@pytest.fixture(scope="module")
def checked():
    return vorobound.check(eps=0.3, sphere=1.0)


def test_the_check_summary_holds_the_json_numbers(checked):
    data, s = checked.to_dict(), checked.summary
    for name in ("source", "n_samples", "n_guide_triangles", "coverage_max", "gap_ratio_max"):
        assert getattr(s, name) == data[name]
    assert (s.params.eps, s.params.sigma) == (data["params"]["eps"], data["params"]["sigma"])
    assert [b.mode for b in s.gap_bounds] == list(data["bound"])
    assert [b.value for b in s.gap_bounds] == [e["gap_ratio"] for e in data["bound"].values()]
    assert [b.value for b in s.ratio_bounds] == [e["value"] for e in data["ratio_bound"].values()]
    assert s.smooth.n_guide_triangles + s.at_features.n_guide_triangles == s.n_guide_triangles
    assert s.smooth.quality == data["violations_smooth"]["quality"]
    assert s.realized is None and s.guarantee is None  # a check at a given ε infers nothing
    with pytest.raises(dataclasses.FrozenInstanceError):
        s.n_samples = 0  # type: ignore[misc]


def test_a_field_the_json_lacks_is_an_error(checked):
    data = checked.to_dict()
    del data["sparsity_min"]
    with pytest.raises(TypeError, match="sparsity_min"):
        CheckSummary.of(data)


def test_typed_view_takes_given_fields_over_the_json():
    @dataclasses.dataclass(frozen=True)
    class Pair:
        a: int
        b: int = 2

    assert typed_view(Pair, {"a": 1, "c": 3}) == Pair(1, 2)
    assert typed_view(Pair, {"a": 1, "b": 5}, a=7) == Pair(7, 5)


def test_the_reconstruction_summary_holds_the_json_numbers():
    result = vorobound.reconstruct(eps=0.3, sphere=1.0)
    data, s = result.to_dict(), result.summary
    assert s.eps == data["params"]["eps"] == 0.3
    for name in ("n_facets", "closed_manifold", "euler_characteristic", "topology_correct"):
        assert getattr(s, name) == data[name]
    assert s.measured and s.hausdorff_over_eps_lfs == data["hausdorff_over_eps_lfs"]
    assert s.flipped_facets == data["flipped_facets"]
