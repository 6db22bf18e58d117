"""Interval certificates: enclosures contain the true values, search, checker, tampering, CLI."""

import copy
import json
import math

import numpy as np
import pytest
from flint import arb
from hypothesis import given, settings
from hypothesis import strategies as st

from vorobound.bounds.certify import NotCertified, certify, check_certificate, interval
from vorobound.bounds.certify.interval import (
    DIMENSIONS,
    ENCLOSURES,
    Setting,
    exact_rational,
    nearest_float,
)
from vorobound.bounds.certify.search import absolute_configuration, counterexample_at
from vorobound.bounds.configurations import feasible_mask, sample_feasible
from vorobound.bounds.independent import check_independently
from vorobound.bounds.params import QualityParams
from vorobound.errors import CertificateError

FAST = (1.2, 0.5, 1.5, None)
"""σ, δ/ε, ρ_f, λ whose certificate at 0.99·ε* takes ~5·10³ boxes (under a second)."""
FAST_LIPSCHITZ = (1.5, 1.0, 1.38, 3.0)
"""λσ above 2/(1−ε): the Lipschitz conditions are checked but do not bind at the worst vertex."""
LIPSCHITZ_BINDS = (1.6, 1.0, 1.38, 0.5)
"""λσ below 2/(1−ε): L_j − L_i = λc at the worst vertex (~10⁴ boxes at 0.9·ε*, ~6·10⁴ at 0.99)."""
PLATEAU = (0.75, 3.0, 1.38, None)
"""δ/ε = 3: ε* is decided by R̂ = 0, and one box closes everything below it."""
PARAMETER_KEYS = ("sigma", "delta_ratio", "rho_f", "lipschitz", "eps_max")
FLOAT_RTOL = 1e-9
"""Float64 values of R − R̂ (geometry core) against interval enclosures."""


def _quality(sigma, ratio, rho_f, lam, target="additive") -> QualityParams:
    """The parameter tuples of this module as the solvers take them."""
    return QualityParams(sigma, ratio, rho_f, lipschitz=lam, target=target)


@pytest.fixture(scope="module")
def fast_certificate():
    result = certify(_quality(*FAST), fraction=0.99)
    return result, result.certificate()


def _point_of(tri, index: int, eps: float) -> tuple[float, ...]:
    """Box coordinates of one configuration (L_i = 1)."""
    return (
        eps,
        float(tri.b[index]) / eps,
        float(tri.c[index]) / eps,
        math.cos(float(tri.theta[index])),
        float(tri.excess_j[index]) / eps,
        float(tri.excess_k[index]) / eps,
    )


@settings(max_examples=60, deadline=None)
@given(
    st.sampled_from([(0.75, 2.0, 1.38, None), (0.75, 2.0, 1.38, 1.0), FAST, (0.5, 3.0, 1.2, 0.2)]),
    st.floats(0.05, 1.0),
    st.integers(0, 2**32 - 1),
    st.lists(st.floats(1e-6, 0.3), min_size=12, max_size=12),
)
def test_enclosures_contain_the_float_value_at_points_of_random_boxes(params, share, seed, widths):
    sigma, ratio, rho_f, lam = params
    eps_max = 0.05
    eps = share * eps_max
    quality = _quality(sigma, ratio, rho_f, lam)
    sampling = quality.at(eps)
    tri = sample_feasible(sampling, 4, np.random.default_rng(seed))
    setting = Setting.of(quality, eps_max)
    root = setting.root_box()
    gaps = tri.radius_gap(sampling) / sampling.gap_allowance
    with interval.working_precision():
        for index in range(len(tri)):
            point = _point_of(tri, index, eps)
            box = []
            for dim, x in enumerate(point):
                lo_root, hi_root = (nearest_float(v) for v in root[dim])
                span = hi_root - lo_root
                lo = max(lo_root, x - widths[2 * dim] * span)
                hi = min(hi_root, x + widths[2 * dim + 1] * span)
                box.append((exact_rational(min(lo, x)), exact_rational(max(hi, x))))
            scaled = interval.scaled(interval.balls(tuple(box)))
            assert interval.violated_constraint(scaled, setting) is None
            values = interval.enclosures(scaled, setting)
            for name in ENCLOSURES:
                assert float(values[name].upper()) >= gaps[index] * (1 - FLOAT_RTOL) - 1e-15
            exact = interval.exact_ratio_at([arb(x) for x in point], setting)
            tolerance = FLOAT_RTOL * abs(gaps[index]) + 1e-15
            assert float(exact.lower()) - tolerance <= gaps[index]
            assert gaps[index] <= float(exact.upper()) + tolerance


@pytest.mark.parametrize(
    "params, fraction",
    [(FAST, 0.99), (FAST_LIPSCHITZ, 0.99), (PLATEAU, 0.99), (LIPSCHITZ_BINDS, 0.9)],
)
def test_certifies_below_and_refutes_above_the_tight_eps_star(params, fraction):
    result = certify(_quality(*params), fraction=fraction)
    assert result.ratio == pytest.approx(fraction, rel=1e-12)
    assert result.search.boxes >= 1
    independent = check_independently(result.certificate())  # λ binding or not, plateau
    assert (independent.eps_max, independent.leaves) == (
        result.eps_certified,
        check_certificate(result.certificate()).leaves,
    )
    with pytest.raises(NotCertified) as info:
        certify(_quality(*params), fraction=1.01)
    found = info.value.counterexample
    assert found is not None and found.ratio_lower > 1 and found.ratio_float > 1
    sampling = _quality(*params).at(found.point[0])
    tri = absolute_configuration(found.point)
    assert feasible_mask(tri, sampling).all()
    assert tri.radius_gap(sampling)[0] > sampling.gap_allowance


def test_limits_stop_the_search_with_the_unresolved_box():
    with pytest.raises(NotCertified) as info:
        certify(_quality(*FAST), fraction=0.99, max_depth=3)
    assert info.value.counterexample is None and info.value.box is not None


def test_checker_accepts_the_certificate_after_a_json_round_trip(fast_certificate):
    result, payload = fast_certificate
    report = check_certificate(json.loads(json.dumps(payload)))
    assert report.eps_max == result.eps_certified
    assert report.boxes == result.search.boxes == len(payload["nodes"])
    assert 0 < report.largest_bound <= 1
    assert payload["summary"]["leaves"] == report.leaves
    assert set(payload["versions"]) >= {"vorobound", "python-flint"}


def _leaf_indices(payload, kind):
    return [i for i, n in enumerate(payload["nodes"]) if isinstance(n, kind)]


def _remove_bound_leaf(p):
    del p["nodes"][_leaf_indices(p, list)[len(_leaf_indices(p, list)) // 2]]


def _remove_infeasible_leaf(p):
    del p["nodes"][_leaf_indices(p, str)[0]]


def _lower_largest_bound(p):
    index = max(_leaf_indices(p, list), key=lambda i: p["nodes"][i][1])
    name, bound = p["nodes"][index]
    p["nodes"][index] = [name, bound * (1 - 1e-6)]


def _lower_a_bound_below_its_enclosure(p):
    """The smallest false claim: one float below the recomputed enclosure's upper end."""
    given = p["parameters"]
    sigma, ratio, rho_f, lam, eps_max = (given[k] for k in PARAMETER_KEYS)
    setting = Setting.of(_quality(sigma, ratio, rho_f, lam, p["target"]), eps_max)
    stack, target = [setting.root_box()], _leaf_indices(p, list)[-1]
    for index, node in enumerate(p["nodes"]):
        box = stack.pop()
        if isinstance(node, int):
            stack += reversed(interval.split(box, node))
        elif index == target:
            with interval.working_precision():
                scaled = interval.scaled(interval.balls(box))
                value = interval.enclosures(scaled, setting, (node[0],))[node[0]]
            p["nodes"][index] = [node[0], math.nextafter(float(value.upper()), 0.0)]
            return


def _raise_bound_above_target(p):
    index = _leaf_indices(p, list)[0]
    p["nodes"][index] = [p["nodes"][index][0], 1.5]


def _swap_constraint(p):
    index = _leaf_indices(p, str)[0]
    p["nodes"][index] = "b_min" if p["nodes"][index] != "b_min" else "c_min"


def _change_split(p):
    index = _leaf_indices(p, int)[0]
    p["nodes"][index] = (p["nodes"][index] + 1) % 6


def _stronger_claim(p):
    p["parameters"]["rho_f"] = 1.3
    p["root_box"] = None


@pytest.mark.parametrize(
    "tamper",
    [
        _remove_bound_leaf,
        _remove_infeasible_leaf,
        _lower_largest_bound,
        _lower_a_bound_below_its_enclosure,
        _raise_bound_above_target,
        _swap_constraint,
        _change_split,
        _stronger_claim,
        lambda p: p["nodes"].pop(),
        lambda p: p["nodes"].append(0),
        lambda p: p["parameters"].__setitem__("eps_max", p["parameters"]["eps_max"] * 1.001),
        lambda p: p.__setitem__("format_version", 99),
        lambda p: p["nodes"].__setitem__(1, [ENCLOSURES[0], "0.5"]),
        lambda p: p["nodes"].__setitem__(1, True),
        lambda p: p.__setitem__("nodes", []),
    ],
)
@pytest.mark.parametrize("checker", [check_certificate, check_independently])
def test_tampered_certificates_are_rejected(fast_certificate, tamper, checker):
    """By each checker alone: the prover's re-check and the independent one."""
    payload = copy.deepcopy(fast_certificate[1])
    tamper(payload)
    with pytest.raises(CertificateError):
        checker(payload)


def test_cli_certify_out_and_check(run_cli, tmp_path):
    path = tmp_path / "cert.json"
    sigma, ratio, rho_f, _ = FAST
    args = ["--sigma", str(sigma), "--delta-ratio", str(ratio), "--rho-f", str(rho_f)]
    code, out, err = run_cli("certify", *args, "--fraction", "0.99", "-o", str(path), "--json")
    assert code == 0, err
    payload = json.loads(out)
    keys = {"eps_certified", "eps_star_tight", "ratio", "boxes", "max_depth", "seconds"}
    assert keys | {"certificate"} <= set(payload)
    assert payload["certificate"] == str(path) and payload["ratio"] == pytest.approx(0.99)
    code, out, err = run_cli("certify", "--check", str(path), "--json")
    assert code == 0, err
    assert json.loads(out)["valid"] is True
    code, out, _ = run_cli("certify", "--check", str(path))
    assert code == 0 and "valid" in out
    tampered = json.loads(path.read_text())
    _lower_largest_bound(tampered)
    path.write_text(json.dumps(tampered))
    code, out, err = run_cli("certify", "--check", str(path))
    # (the transient progress bar of cli/progress.py may leave an empty line on stderr)
    assert code == 2 and err.strip().startswith("error:") and len(err.strip().splitlines()) == 1


def test_cli_failure_prints_a_counterexample(run_cli):
    sigma, ratio, rho_f, _ = FAST
    args = ["--sigma", str(sigma), "--delta-ratio", str(ratio), "--rho-f", str(rho_f)]
    code, out, err = run_cli("certify", *args, "--fraction", "1.01", "--json")
    assert code == 1
    payload = json.loads(out)
    assert payload["certified"] is False
    assert payload["counterexample"]["ratio_interval"][0] > 1
    point = tuple(payload["counterexample"]["coordinates"][name] for name in DIMENSIONS)
    setting = Setting.of(_quality(sigma, ratio, rho_f, None, "ratio"), point[0])  # the default
    with interval.working_precision():
        assert counterexample_at(point, setting) is not None  # re-verified from the output
    code, out, _ = run_cli("certify", *args, "--fraction", "1.01")
    assert code == 1 and "Counterexample" in out


@pytest.mark.parametrize(
    "args",
    [
        ["--sigma", "-1"],
        ["--fraction", "0"],
        ["--eps", "2"],
        ["--rho-f", "nan"],
        ["--max-depth", "0"],
        ["--check", "/nonexistent/cert.json"],
        # No proven ε* and no proven lower bound: no default to certify (it ran 20+ minutes).
        ["--sigma", "1.9", "--target", "ratio"],
    ],
)
def test_cli_bad_input_is_one_line_and_exit_2(run_cli, args):
    code, out, err = run_cli("certify", *args)
    assert code == 2 and out == ""
    assert err.startswith("error:") and len(err.strip().splitlines()) == 1


def test_progress_reports_the_closed_volume_up_to_one_million():
    calls = []
    certify(
        _quality(*FAST),
        fraction=0.9,
        progress=lambda task, done, total: calls.append((done, total)),
    )
    done = [d for d, _ in calls]
    assert done == sorted(done) and done[-1] == calls[-1][1] == 1_000_000 and len(calls) >= 2
