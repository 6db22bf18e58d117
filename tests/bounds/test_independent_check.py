"""The independent certificate checker: it imports nothing of the prover, accepts every genuine
certificate the prover's checker accepts, agrees with it, rejects each forgery on its own, and
its enclosures contain R − R̂ computed from scratch (mpmath). ``certify --check`` runs both."""

import ast
import copy
import json
import math
from fractions import Fraction
from pathlib import Path

import mpmath
import numpy as np
import pytest
from helpers import assert_one_line_error

import vorobound
from vorobound.api.certify import AGREED_FIELDS
from vorobound.bounds.certify import certify
from vorobound.bounds.certify.certificate import check_certificate
from vorobound.bounds.independent import check_independently, quantities
from vorobound.bounds.params import QualityParams
from vorobound.errors import CertificateError

PACKAGE = Path(vorobound.__file__).parent
INDEPENDENT = PACKAGE / "bounds" / "independent"
ALLOWED_VOROBOUND = {"vorobound.errors", "vorobound.checks", "vorobound.progress"}
"""The base layer: exceptions, input range checks, the progress callback type."""
ALLOWED_OTHERS = {"__future__", "contextlib", "dataclasses", "fractions", "json", "math"}
ALLOWED_OTHERS |= {"pathlib", "time", "flint"}
"""The standard library modules it needs, and python-flint."""
CHECKERS = {"prover": check_certificate, "independent": check_independently}
GENUINE = [
    ("ratio", None, None),
    ("ratio", 1.0, None),
    ("ratio", 0.0, 0.5),
    ("additive", None, None),
    pytest.param(("additive", 1.0, None), marks=pytest.mark.slow),
    ("additive", 0.0, 0.5),
]
"""(target, λ, ε_max) at the paper's σ, δ/ε, ρ_f; ε_max None: 0.999 × the tight ε*. λ = 0 has
no ε* (every L is equal, R̂ = R, the target holds at every ε), so ε_max = 0.5 is certified.
The additive λ = 1 certificate (1.5 CPU-s) is slow: the ratio λ = 1 one and the additive
λ = None one cover its target and its λ by default."""
ORACLE_DIGITS = 40
ORACLE_RTOL = 1e-12
"""Relative slack between the mpmath value at a point and the enclosure's top end."""


def _imports(path: Path, package: str) -> set[str]:
    """Every module ``path`` imports (function-level ones too), relative ones resolved."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            found |= {alias.name for alias in node.names}
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                found.add(".".join(base + ([node.module] if node.module else [])))
            else:
                found.add(node.module)
    return found


def test_the_independent_checker_imports_nothing_of_the_prover():
    files = sorted(INDEPENDENT.glob("*.py"))
    assert {f.name for f in files} >= {"__init__.py", "quantities.py"}
    for path in files:
        for module in _imports(path, "vorobound.bounds.independent"):
            inside = module.startswith("vorobound.bounds.independent")
            assert inside or module in ALLOWED_VOROBOUND | ALLOWED_OTHERS, (path.name, module)
            assert not module.startswith("vorobound.geometry"), (path.name, module)


@pytest.fixture(scope="module", params=GENUINE, ids=lambda g: f"{g[0]}-lambda{g[1]}")
def genuine(request):
    target, lam, eps = request.param
    result = certify(QualityParams(lipschitz=lam, target=target), eps=eps)
    return result, json.loads(json.dumps(result.certificate()))


def test_both_checkers_accept_genuine_certificates_and_agree(genuine):
    result, payload = genuine
    prover = check_certificate(payload)
    independent = check_independently(payload)
    for key in AGREED_FIELDS:
        assert getattr(prover, key) == getattr(independent, key), key
    assert independent.eps_max == result.eps_certified
    assert independent.boxes == result.search.boxes and 0 <= independent.largest_bound <= 1


def test_both_implementations_give_the_same_enclosure_at_every_leaf(paper_certificate):
    """The enclosures are one documented formula implemented twice: at every bound leaf of the
    paper's certificate the two top ends are the same float (the stored bound's margin is
    for other FLINT versions, not for a second formula)."""
    from vorobound.bounds.certify import interval

    result, payload = paper_certificate
    setting = result.request.setting
    params = _parameters_of(payload)
    stack, compared = [setting.root_box()], 0
    with interval.working_precision():
        for node in payload["nodes"]:
            box = stack.pop()
            if isinstance(node, int):
                stack += reversed(interval.split(box, node))
            elif isinstance(node, list):
                prover = interval.enclosures(interval.scaled(interval.balls(box)), setting)
                exact = tuple(
                    (Fraction(int(lo.p), int(lo.q)), Fraction(int(hi.p), int(hi.q)))
                    for lo, hi in box
                )
                mine = quantities.fraction_enclosure(node[0], quantities.Triangle.of(exact), params)
                assert float(mine.upper()) == float(prover[node[0]].upper())
                compared += 1
    assert compared == sum(payload["summary"]["bound"].values()) > 100


def _parameters_of(payload) -> quantities.Parameters:
    given = payload["parameters"]
    lam = given["lipschitz"]
    return quantities.Parameters(
        *(quantities.ball(Fraction(given[k])) for k in ("sigma", "delta_ratio", "rho_f")),
        None if lam is None else quantities.ball(Fraction(lam)),
        payload["target"],
    )


# --- forgeries, each rejected by each checker alone --------------------------------------


@pytest.fixture(scope="module", params=["ratio", "additive"])
def paper_certificate(request):
    """0.999 × the tight ε* at the paper's parameters (~10³ boxes)."""
    result = certify(QualityParams(target=request.param))
    return result, result.certificate()


def _leaves(p, kind):
    return [i for i, node in enumerate(p["nodes"]) if isinstance(node, kind)]


def _split_with_two_leaves(p) -> int:
    nodes = p["nodes"]
    return next(
        i
        for i in range(len(nodes) - 2)
        if isinstance(nodes[i], int) and not isinstance(nodes[i + 1], int)
        if not isinstance(nodes[i + 2], int)
    )


def _raise_eps_above_eps_star(p, star):
    """ε_max 1 % above the true ε*: false; the root box is written for the new ε_max."""
    p["parameters"]["eps_max"] = 1.01 * star
    p["root_box"] = None


def _raise_eps_keep_root_box(p, star):
    p["parameters"]["eps_max"] *= 1.0001


def _lower_rho_f(p, star):
    p["parameters"]["rho_f"] = 1.37  # ε* at 1.37 is below the certified 0.999 ε*(1.38)


def _every_bound_one(p):
    p["nodes"] = [[n[0], 1.0] if isinstance(n, list) else n for n in p["nodes"]]


def _raise_eps_and_every_bound(p, star):
    """False claim with every stored bound at 1: only the target itself can reject it."""
    _raise_eps_above_eps_star(p, star)
    _every_bound_one(p)


def _lower_rho_f_and_every_bound(p, star):
    _lower_rho_f(p, star)
    _every_bound_one(p)


def _drop_bound_leaf(p, star):
    del p["nodes"][_leaves(p, list)[0]]


def _drop_subtree(p, star):
    """A split and its two leaves: the tree stays well formed, one box is left uncovered."""
    index = _split_with_two_leaves(p)
    del p["nodes"][index : index + 3]


def _collapse_subtree(p, star):
    """A split and its two leaves replaced by one leaf at the largest bound allowed."""
    index = _split_with_two_leaves(p)
    name = next(n[0] for n in p["nodes"][index + 1 : index + 3] if isinstance(n, list))
    p["nodes"][index : index + 3] = [[name, 1.0]]


def _collapse_tree(p, star):
    p["nodes"] = [["chord", 1.0]]


def _nan_bound(p, star):
    p["nodes"][_leaves(p, list)[0]][1] = math.nan


def _inf_bound(p, star):
    p["nodes"][_leaves(p, list)[0]][1] = -math.inf


def _nan_eps(p, star):
    p["parameters"]["eps_max"] = math.nan


def _permute_dimensions(p, star):
    """ε and cos θ swapped in the coordinate list and in every split (self-consistent)."""
    swap = {0: 3, 3: 0}
    p["dimensions"] = [p["dimensions"][swap.get(i, i)] for i in range(6)]
    p["nodes"] = [swap.get(n, n) if type(n) is int else n for n in p["nodes"]]


def _permute_splits(p, star):
    swap = {0: 3, 3: 0}
    p["nodes"] = [swap.get(n, n) if type(n) is int else n for n in p["nodes"]]


def _shrink_root_box(p, star):
    p["root_box"][1][1] = p["root_box"][1][0]


def _garbled_root_box(p, star):
    p["root_box"][0] = ["0", "1/0"]


def _bad_precision(p, star):
    p["precision_bits"] = 8


FORGERIES = [
    _garbled_root_box,
    _bad_precision,
    _raise_eps_above_eps_star,
    _raise_eps_keep_root_box,
    _lower_rho_f,
    _raise_eps_and_every_bound,
    _lower_rho_f_and_every_bound,
    _drop_bound_leaf,
    _drop_subtree,
    _collapse_subtree,
    _collapse_tree,
    _nan_bound,
    _inf_bound,
    _nan_eps,
    _permute_dimensions,
    _permute_splits,
    _shrink_root_box,
]


@pytest.mark.parametrize("checker", CHECKERS)
@pytest.mark.parametrize("forge", FORGERIES, ids=lambda f: f.__name__.strip("_"))
def test_each_checker_alone_rejects_each_forgery(paper_certificate, forge, checker):
    result, payload = paper_certificate
    forged = copy.deepcopy(payload)
    forge(forged, result.request.eps_star_tight)
    assert forged != payload
    with pytest.raises(CertificateError):
        CHECKERS[checker](json.loads(json.dumps(forged)))


def test_the_lowered_rho_f_claim_is_false():
    """So rejecting it is right, not an artefact of the stored bounds."""
    lowered = certify(QualityParams(rho_f=1.37)).request.eps_star_tight
    assert lowered < 0.999 * certify(QualityParams()).request.eps_star_tight


# --- the enclosures against R − R̂ computed from scratch ---------------------------------


def _fraction_at(point, sigma, ratio, rho_f, target) -> mpmath.mpf:
    """The target's fraction at a configuration (L_i = 1), from the weighted triangle: the
    orthocenter z solves |z − X|² − w_X = |z − A|² for X = B, C (A has weight 0)."""
    eps, beta, gamma, cos_t, ell_j, ell_k = (mpmath.mpf(x) for x in point)
    sin_t = mpmath.sqrt(1 - cos_t**2)
    b_pt = mpmath.matrix([eps * gamma, 0])  # B = p_j at distance c
    c_pt = mpmath.matrix([eps * beta * cos_t, eps * beta * sin_t])  # C = p_k at distance b
    delta = ratio * eps
    w_b = delta**2 * ((1 + eps * ell_j) ** 2 - 1)
    w_c = delta**2 * ((1 + eps * ell_k) ** 2 - 1)

    def center(wb, wc):
        rows = mpmath.matrix([[2 * b_pt[0], 2 * b_pt[1]], [2 * c_pt[0], 2 * c_pt[1]]])
        rhs = mpmath.matrix([b_pt[0] ** 2 + b_pt[1] ** 2 - wb, c_pt[0] ** 2 + c_pt[1] ** 2 - wc])
        z = mpmath.lu_solve(rows, rhs)
        return mpmath.sqrt(z[0] ** 2 + z[1] ** 2)

    radius, ortho = center(0, 0), center(w_b, w_c)
    if target == "ratio":
        return (radius - ortho) / radius / (1 - 1 / mpmath.mpf(rho_f))
    return (radius - ortho) / ((rho_f - 1) * delta)


def _feasible(triangle, params) -> bool:
    names = ["lfs_j_min", "lfs_j_max", "lfs_k_min", "lfs_k_max", "c_min", "c_max", "b_min"]
    names += ["b_max", "a_min", "a_max", "circumradius_max"]
    names += ["lipschitz_ij", "lipschitz_ik", "lipschitz_jk"] if params.lipschitz else []
    return all(
        (sides := quantities.constraint_sides(n, triangle, params))[0] <= sides[1] for n in names
    )


@pytest.mark.parametrize("target", ["ratio", "additive"])
@pytest.mark.parametrize("lam", [None, 1.0])
def test_enclosures_contain_the_fraction_computed_from_scratch(target, lam):
    sigma, ratio, rho_f, eps_max = 0.75, 2.0, 1.38, 0.05
    rng = np.random.default_rng(29)
    params = quantities.Parameters(
        *(quantities.ball(Fraction(v)) for v in (sigma, ratio, rho_f)),
        None if lam is None else quantities.ball(Fraction(lam)),
        target,
    )
    top = 2 / (1 - eps_max)
    checked = 0
    mpmath.mp.dps = ORACLE_DIGITS
    while checked < 40:
        point = [eps_max * rng.uniform(0.05, 1), *rng.uniform(sigma, top, 2), rng.uniform(-1, 1)]
        point += list(rng.uniform(0, top, 2) * (1 if lam is None else rng.uniform(0, 1)))
        exact = tuple(Fraction(x) for x in point)
        triangle = quantities.Triangle.of(tuple((x, x) for x in exact))
        if not _feasible(triangle, params):
            continue
        value = _fraction_at(point, sigma, ratio, rho_f, target)
        widths = rng.uniform(0, 0.01, 6) * np.array([eps_max, top, top, 2, top, top])
        box = tuple((x - Fraction(w), x + Fraction(w)) for x, w in zip(exact, widths, strict=True))
        for name in quantities.TARGET_ENCLOSURES[target]:
            for region in (tuple((x, x) for x in exact), box):
                enclosure = quantities.fraction_enclosure(
                    name, quantities.Triangle.of(region), params
                )
                assert mpmath.mpf(float(enclosure.upper())) >= value - ORACLE_RTOL * abs(value), (
                    name
                )
        checked += 1


# --- certify --check: both checkers, and what happens when they disagree -------------------


@pytest.fixture
def certificate_file(tmp_path, paper_certificate):
    path = tmp_path / "cert.json"
    path.write_text(json.dumps(paper_certificate[1]))
    return path


def test_check_json_lists_two_checkers_that_accept(run_cli, certificate_file):
    code, out, err = run_cli("certify", "--check", str(certificate_file), "--json")
    assert code == 0, err
    payload = json.loads(out)
    names = [c["name"] for c in payload["checkers"]]
    assert len(names) == 2 and len(set(names)) == 2
    assert payload["valid"] is True and all(c["valid"] for c in payload["checkers"])
    schema = pytest.importorskip("jsonschema")
    root = Path(__file__).resolve().parents[2]
    text = (root / "docs" / "schema" / "vorobound-output.schema.json").read_text()
    schema.Draft202012Validator(json.loads(text)).validate(payload)


def test_the_independent_checker_reads_the_file_itself(certificate_file, tmp_path):
    from vorobound.bounds.independent import check_file_independently

    assert check_file_independently(certificate_file).leaves > 100
    broken = tmp_path / "broken.json"
    broken.write_text(certificate_file.read_text()[:-20])
    for path in (broken, tmp_path, tmp_path / "missing.json"):
        with pytest.raises(CertificateError):
            check_file_independently(path)


def _reject(payload, progress=None):
    raise CertificateError("node 7: forced rejection")


@pytest.mark.parametrize(
    "module, name",
    [
        ("vorobound.bounds.independent", "independent"),
        ("vorobound.bounds.certify.certificate", "prover"),
    ],
)
def test_a_disagreement_is_exit_1_naming_the_checker(
    run_cli, certificate_file, monkeypatch, module, name
):
    import importlib

    attribute = "check_independently" if name == "independent" else "check_certificate"
    monkeypatch.setattr(importlib.import_module(module), attribute, _reject)
    code, out, _ = run_cli("certify", "--check", str(certificate_file), "--json")
    payload = json.loads(out)
    assert code == 1 and payload["valid"] is False and payload["eps_certified"] is None
    assert {c["name"]: c["valid"] for c in payload["checkers"]}[name] is False
    code, out, _ = run_cli("certify", "--check", str(certificate_file))
    last = out.strip().splitlines()[-1]
    assert code == 1 and "disagree" in last and f"{name} checker rejects" in last
    result = vorobound.check_certificate(certificate_file)  # the same in Python
    assert not result.valid and not result.ok and name in result.reason


def test_reports_that_differ_are_a_disagreement(run_cli, certificate_file, monkeypatch):
    import dataclasses

    import vorobound.bounds.independent as independent

    real = independent.check_independently

    def shifted(payload, progress=None):
        report = real(payload, progress)
        return dataclasses.replace(report, eps_max=report.eps_max * 2)

    monkeypatch.setattr(independent, "check_independently", shifted)
    code, out, _ = run_cli("certify", "--check", str(certificate_file))
    assert code == 1 and "disagree on eps_max" in out.strip().splitlines()[-1]


def test_both_rejecting_is_one_line_and_exit_2(run_cli, tmp_path, paper_certificate):
    forged = copy.deepcopy(paper_certificate[1])
    _drop_bound_leaf(forged, None)
    path = tmp_path / "forged.json"
    path.write_text(json.dumps(forged))
    code, out, err = run_cli("certify", "--check", str(path), "--json")
    assert_one_line_error(code, out, err)
    assert "independent checker rejects it too" in err


def test_a_bug_shared_by_the_prover_and_its_checker_is_caught(run_cli, tmp_path, monkeypatch):
    """The reason for a second checker: enclosures 10 % too small in the prover's interval
    module let the search certify ε_max above ε* (a false certificate, with the worst-vertex
    test switched off too); the prover's checker shares the bug and accepts it, the independent
    one rejects it, so --check says the checkers disagree (exit 1)."""
    import importlib

    from vorobound.bounds.certify import interval

    search = importlib.import_module("vorobound.bounds.certify.search")
    real = interval.enclosures

    def too_small(point, setting, names=None):
        return {name: 0.9 * value for name, value in real(point, setting, names).items()}

    monkeypatch.setattr(interval, "enclosures", too_small)
    monkeypatch.setattr(search, "worst_vertex", lambda setting: None)
    path = tmp_path / "false.json"
    code, _, err = run_cli("certify", "--fraction", "1.02", "-o", str(path), "--json")
    assert code == 0, err  # the buggy prover "certifies" 1.02 ε*
    code, out, _ = run_cli("certify", "--check", str(path), "--json")
    verdicts = {c["name"]: c["valid"] for c in json.loads(out)["checkers"]}
    assert code == 1 and verdicts == {"prover": True, "independent": False}
