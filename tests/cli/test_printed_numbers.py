"""Every printed number a guarantee rests on errs toward safety (issue 29).

An admissible or certified ε printed in the README, in docs/*.md or by a command is never above
the exact value; a printed bound on R − R̂ or R/R̂ is never below it. The exact values of the
tight closed forms come from mpmath at 50 digits (docs/tight.md); the chains' values and the
certified ε are the floats the code computes (a chain has no closed form to evaluate in
mpmath, and a certificate's ε is exactly the float it certifies).

The scanner finds every decimal in the text with at least four significant digits that is a
rounding of a reference value (it differs from it by less than one unit in its own last
place) and checks the direction of that rounding.
"""

from __future__ import annotations

import math
import re
from decimal import Decimal
from pathlib import Path

import mpmath as mp
import pytest

from vorobound.rounding import DOWN, UP, format_down, format_toward, format_up, round_down, round_up

ROOT = Path(__file__).resolve().parents[2]
SIGMA, RATIO, RHO_F = mp.mpf(3) / 4, mp.mpf(2), mp.mpf("1.38")
PAPER_EPS, BASELINE_EPS = mp.mpf("0.0047"), mp.mpf(1) / 500


def _mu(eps, lam):
    """μ*(ε) = (δ/ε)²·X(2 + X)/σ², X = 2ε/(1 − ε), or min(that, λσε) (docs/tight.md)."""
    x = 2 * eps / (1 - eps)
    if lam is not None:
        x = min(x, lam * SIGMA * eps)
    return RATIO**2 * x * (2 + x) / SIGMA**2


def _gap(eps, lam):
    """sup (R − R̂)/(ε L_i) over the constraint set: min(1, μ*)/(1 − ε)."""
    return min(1, _mu(eps, lam)) / (1 - eps)


def _root(f, lo, hi):
    with mp.workdps(50):
        return mp.findroot(f, (mp.mpf(lo), mp.mpf(hi)), solver="anderson")


def _exact_references() -> list[tuple[mp.mpf, str, str]]:
    """(exact value, direction, what it is)."""
    refs = []
    with mp.workdps(50):
        for lam in (None, mp.mpf(1)):
            name = "" if lam is None else ", λ = 1"
            ratio = _root(lambda e, lam=lam: _mu(e, lam) - (1 - 1 / RHO_F), 1e-4, 0.3)
            additive = _root(lambda e, lam=lam: _gap(e, lam) - (RHO_F - 1) * RATIO, 1e-4, 0.3)
            refs += [
                (ratio, DOWN, "tight ratio ε*" + name),
                (additive, DOWN, "tight additive ε*" + name),
                (ratio / BASELINE_EPS, DOWN, "tight ratio ε* / (1/500)" + name),
                (additive / BASELINE_EPS, DOWN, "tight additive ε* / (1/500)" + name),
                (_gap(PAPER_EPS, lam), UP, "tight gap bound at 0.0047" + name),
                (_gap(BASELINE_EPS, lam), UP, "tight gap bound at 1/500" + name),
                (1 + _gap(PAPER_EPS, lam) / RATIO, UP, "implied ρ_f at 0.0047" + name),
                (1 / (1 - _mu(PAPER_EPS, lam)), UP, "tight R/R̂ bound at 0.0047" + name),
            ]
        refs.append((1 - 1 / (RHO_F * RATIO), DOWN, "H3 alone gives (55)"))
    return refs


def _computed_references() -> list[tuple[float, str, str]]:
    from vorobound.bounds.certify import certify
    from vorobound.bounds.guarantee import bound_at, eps_star
    from vorobound.bounds.params import QualityParams

    quality = QualityParams()
    refs = []
    for mode in ("paper", "rigorous"):
        for target in ("additive", "ratio"):
            star = eps_star(quality.but(target=target), mode).eps_star
            refs.append((star, DOWN, f"{mode} {target} ε*"))
            refs.append((star / float(BASELINE_EPS), DOWN, f"{mode} {target} ε* / (1/500)"))
        additive = quality.but(target="additive")
        for eps in (float(PAPER_EPS), float(BASELINE_EPS)):
            gap = bound_at(additive.at(eps), mode).value / eps
            refs.append((gap, UP, f"{mode} gap bound at {eps}"))
            refs.append((1 + gap / 2, UP, f"{mode} implied ρ_f at {eps}"))
    for lam in (None, 1.0):
        for target in ("additive", "ratio"):
            asked = quality.but(target=target, lipschitz=lam)
            refs.append((certify(asked).eps_certified, DOWN, f"certified {target} λ={lam}"))
    return refs


@pytest.fixture(scope="module")
def references():
    exact = [(float(v), d, n, v) for v, d, n in _exact_references()]
    computed = [(v, d, n, mp.mpf(v)) for v, d, n in _computed_references()]
    return exact + computed


PARAMETERS = {"1.38", "0.0047", "0.002", "0.75"}
"""The paper's inputs (ρ_f, its ε, 1/500, σ): printed as given, not results."""
NUMBER = re.compile(r"(?<![\w.])(\d+\.\d+)(?![\w.])")


def _significant(text: str) -> tuple[int, Decimal]:
    """Significant digits of a printed decimal and one unit in its last place."""
    number = Decimal(text)
    digits = len(text.replace(".", "").lstrip("0"))
    return digits, Decimal(1).scaleb(number.as_tuple().exponent)


def _misrounded(text: str, references) -> list[str]:
    found = []
    for match in NUMBER.finditer(text):
        printed = match.group(1)
        digits, ulp = _significant(printed)
        if digits < 4 or printed in PARAMETERS:
            continue
        value = mp.mpf(printed)
        for _, direction, name, exact in references:
            if abs(value - exact) >= mp.mpf(str(ulp)):
                continue
            if (direction == DOWN and value > exact) or (direction == UP and value < exact):
                line = text.count("\n", 0, match.start()) + 1
                found.append(f"line {line}: {printed} for {name} = {mp.nstr(exact, 12)}")
    return found


DOCUMENTS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
COINCIDENCES = {
    ("scale.md", "1.067"): "a measured sparsity, not the implied ρ_f 1.0678",
    ("samples.md", "0.0094977"): "the ε a measured run was asked for (issue 32), not ε*",
    ("reconstruct.md", "0.0094977"): "the ε a measured run was asked for (issue 32), not ε*",
    ("performance.md", "0.0094977"): "the ε a measured run was asked for (issue 35), not ε*",
}
"""Numbers that happen to lie within one printed unit of a reference but mean something else."""


@pytest.mark.parametrize("doc", DOCUMENTS, ids=[d.name for d in DOCUMENTS])
def test_documents_round_toward_safety(doc, references):
    found = _misrounded(doc.read_text(encoding="utf-8"), references)
    found = [f for f in found if (doc.name, f.split(": ")[1].split()[0]) not in COINCIDENCES]
    assert not found


def test_the_scanner_catches_a_number_rounded_to_nearest(references):
    """The README's old text: ε* rounded up, the certified ε rounded up."""
    old = "ε ≤ 0.0094977 … certified up to 0.0094882; λ = 1 additive 0.065031"
    assert len(_misrounded(old, references)) == 3
    assert not _misrounded("ε ≤ 0.0094976, certified up to 0.0094881", references)


@pytest.mark.parametrize(
    "args",
    [
        ["reproduce", "--out", "{tmp}"],
        ["advise", "--sphere", "1"],
        ["advise", "--sphere", "1", "--lipschitz", "1"],
        ["solve"],
        ["solve", "--target", "additive", "--lipschitz", "1"],
        ["bounds", "--eps", "0.0047"],
        ["bounds", "--eps", "0.0047", "--target", "additive"],
        ["sweep", "--mode", "tight,rigorous", "--target", "ratio,additive"],
    ],
)
def test_command_tables_round_toward_safety(args, references, tmp_path, capsys):
    from vorobound.cli import main

    code = main([a.format(tmp=tmp_path / "figures") for a in args])
    assert code == 0
    out = capsys.readouterr().out
    assert not _misrounded(out, references)


def test_advise_prints_its_recommended_eps_rounded_down(capsys):
    from vorobound.cli import main

    assert main(["advise", "--sphere", "1"]) == 0
    line = next(x for x in capsys.readouterr().out.splitlines() if "recommended ε" in x.lower())
    printed = re.search(r"ε = (\d+\.\d+)", line).group(1)
    with mp.workdps(50):
        exact = _root(lambda e: _mu(e, None) - (1 - 1 / RHO_F), 1e-4, 0.3)
    assert mp.mpf(printed) <= exact
    assert printed == "0.0094976"


def test_the_api_recommends_the_printed_eps():
    import vorobound

    advice = vorobound.advise(sphere=1.0)
    assert advice.eps == 0.0094976
    assert advice.eps <= vorobound.solve().eps_star


@pytest.mark.parametrize(
    "value", [0.00949769106, 1.3800005, 2.5e-320, 1.7e308, 123456.789, 1e-7, 7.0, 0.1]
)
@pytest.mark.parametrize("digits", [1, 3, 5, 12])
def test_directed_rounding_is_on_the_safe_side_and_tight(value, digits):
    low, high = float(format_down(value, digits)), float(format_up(value, digits))
    assert low <= value <= high
    assert round_down(value, digits) == low and round_up(value, digits) == high
    # no more than one unit in the last printed place apart
    assert Decimal(format_up(value, digits)) - Decimal(format_down(value, digits)) <= Decimal(
        1
    ).scaleb(Decimal(format_up(value, digits)).adjusted() - digits + 1)
    assert len(format_down(value, digits).split("e")[0].replace(".", "").lstrip("0")) <= digits


def test_special_values_and_directions():
    assert format_down(None) == format_up(math.nan) == "n/a"
    assert format_up(math.inf) == "∞" and format_down(-math.inf) == "−∞"
    assert format_toward(0.123456789, None) == "0.12346"
    assert format_toward(0.123456789, DOWN) == "0.12345"
    assert format_toward(0.123451, UP) == "0.12346"
    assert format_down(0.0) == "0"
    with pytest.raises(ValueError):
        format_toward(1.0, "sideways")
