"""The second certificate checker: written from the paper's definitions, sharing no code with
the prover (``vorobound.bounds.certify``) or with the constraint module it uses.

It parses the certificate file itself (:func:`check_file_independently`), rebuilds from the
parameters alone the domain that holds every feasible configuration for every ε ≤ ε_max,
requires the certificate's root box to contain it, replays the bisection tree at exact
midpoints (Python ``Fraction``), and re-checks every leaf with its own ball arithmetic
(python-flint ``arb``, :mod:`.quantities`): an infeasible leaf's constraint must fail on all of
its box, a bound leaf's enclosure of the target's fraction must lie below the stored bound, and
that bound must be a finite float ≤ 1.

It imports only the base layer (errors, input checks, the progress callback) and python-flint;
``tests/bounds/test_independent_check.py`` asserts that.

References
----------
Theorem 1, eq. (33)–(37), (54)–(55), property H3; docs/tight.md, "The independent checker".
"""

from __future__ import annotations

import contextlib
import json
import math
import time
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path

from flint import arb, ctx

from ...checks import (
    DELTA_RATIO_RANGE,
    EPS_RANGE,
    RHO_F_MAX,
    SIGMA_RANGE,
    brief,
    checked_lipschitz,
    checked_number,
)
from ...errors import CertificateError, VoroboundError
from ...progress import Progress, silent
from .quantities import (
    COORDINATES,
    TARGET_ENCLOSURES,
    Parameters,
    Triangle,
    ball,
    fails_everywhere,
    fraction_enclosure,
)

CHECKER_NAME = "independent"
"""How ``certify --check`` names this checker (the prover's own re-check is ``prover``)."""
FORMAT = "vorobound-certificate"
VERSIONS = (1, 2)
"""Format versions read; version 1 predates targets and certifies the additive one."""
DEEPEST = 480
"""Deepest box replayed (the prover's search stops at 120 levels by default); a deeper tree is
refused before its exact rationals cost memory."""
PRECISION_RANGE = (53, 4096)
PROGRESS_EVERY = 4096
PROGRESS_TASK = "checking (independent)"

Box = tuple[tuple[Fraction, Fraction], ...]


@dataclass(frozen=True)
class IndependentReport:
    """What a certificate that passed :func:`check_independently` certifies."""

    eps_max: float
    """Every ε in (0, eps_max] is certified."""
    target: str
    sigma: float
    delta_ratio: float
    rho_f: float
    lipschitz: float | None
    boxes: int
    leaves: int
    max_depth: int
    largest_bound: float
    """Largest stored bound of the target's fraction over the bound leaves (≤ 1)."""
    seconds: float


@dataclass(frozen=True)
class _Claim:
    target: str
    sigma: float
    delta_ratio: float
    rho_f: float
    lipschitz: float | None
    eps_max: float
    precision: int

    def domain(self) -> Box:
        """Every feasible configuration at every ε ∈ (0, ε_max], in box coordinates.

        (34)–(35): σ ≤ b/(εL_i), c/(εL_i) ≤ 2/(1−ε); (33): 0 ≤ ℓ ≤ 2/(1−ε); with λ also
        ℓ_j ≤ λ·c/(εL_i) ≤ λ·2/(1−ε). 2/(1−ε) grows with ε, so its value at ε_max bounds all.
        """
        eps = Fraction(self.eps_max)
        longest = 2 / (1 - eps)
        excess = (
            longest if self.lipschitz is None else min(longest, Fraction(self.lipschitz) * longest)
        )
        sigma = Fraction(self.sigma)
        return (
            (Fraction(0), eps),
            (sigma, longest),
            (sigma, longest),
            (Fraction(-1), Fraction(1)),
            (Fraction(0), excess),
            (Fraction(0), excess),
        )

    def parameters(self) -> Parameters:
        lam = self.lipschitz
        return Parameters(
            ball(Fraction(self.sigma)),
            ball(Fraction(self.delta_ratio)),
            ball(Fraction(self.rho_f)),
            None if lam is None else ball(Fraction(lam)),
            self.target,
        )


def check_independently(payload, progress: Progress | None = None) -> IndependentReport:
    """Re-verify a certificate (its JSON object) without the prover's code.

    Parameters
    ----------
    payload : dict
        The certificate as ``json.load`` returns it.
    progress : Progress, optional
        Receives (:data:`PROGRESS_TASK`, nodes done, nodes).

    Returns
    -------
    IndependentReport

    Raises
    ------
    CertificateError
        Malformed, the root box misses part of the domain, the tree does not replay, or a leaf
        fails its re-check.

    References
    ----------
    Theorem 1, eq. (33)–(37), (54)–(55), property H3.
    """
    start = time.perf_counter()
    if not isinstance(payload, dict):
        raise CertificateError("a certificate is a JSON object")
    claim = _claim(payload)
    root = _root_box(payload.get("root_box"), claim.domain())
    nodes = payload.get("nodes")
    if not isinstance(nodes, list) or not nodes:
        raise CertificateError("certificate has no nodes")
    report = progress or silent
    stack: list[tuple[Box, int]] = [(root, 0)]
    leaves = deepest = 0
    largest = 0.0
    with _precision(claim.precision):
        params = claim.parameters()
        for index, node in enumerate(nodes):
            if not stack:
                raise CertificateError(f"node {index}: the tree is complete before it")
            box, depth = stack.pop()
            deepest = max(deepest, depth)
            if depth > DEEPEST:
                raise CertificateError(f"node {index}: deeper than {DEEPEST} bisections")
            if isinstance(node, int) and not isinstance(node, bool):
                if not 0 <= node < len(COORDINATES):
                    raise CertificateError(f"node {index}: split coordinate {brief(node)}")
                lower, upper = _halves(box, node)
                stack += [(upper, depth + 1), (lower, depth + 1)]
            else:
                largest = max(largest, _leaf(index, node, box, params))
                leaves += 1
            if index % PROGRESS_EVERY == 0:
                report(PROGRESS_TASK, index, len(nodes))
    if stack:
        raise CertificateError(
            f"the leaves do not cover the domain: {len(stack)} box(es) left without a node"
        )
    report(PROGRESS_TASK, len(nodes), len(nodes))
    return IndependentReport(
        claim.eps_max,
        claim.target,
        claim.sigma,
        claim.delta_ratio,
        claim.rho_f,
        claim.lipschitz,
        len(nodes),
        leaves,
        deepest,
        largest,
        time.perf_counter() - start,
    )


def check_file_independently(path, progress: Progress | None = None) -> IndependentReport:
    """:func:`check_independently` on a certificate file, read and parsed here (Python's
    ``json``), not by the prover's reader. CertificateError if it is not a JSON file."""
    path = Path(path)
    try:
        if not path.is_file():
            raise CertificateError(f"cannot read {path}: not a regular file")
        with open(path, encoding="utf-8") as handle:
            payload = json.load(handle, object_pairs_hook=_unique_keys)
    except (OSError, ValueError, RecursionError) as exc:
        raise CertificateError(f"cannot read {path} as JSON ({type(exc).__name__})") from None
    return check_independently(payload, progress)


def _halves(box: Box, coordinate: int) -> tuple[Box, Box]:
    lo, hi = box[coordinate]
    middle = (lo + hi) / 2
    return (
        box[:coordinate] + ((lo, middle),) + box[coordinate + 1 :],
        box[:coordinate] + ((middle, hi),) + box[coordinate + 1 :],
    )


def _leaf(index: int, node, box: Box, params: Parameters) -> float:
    """Re-check one leaf; its stored bound (0 for an infeasible leaf)."""
    triangle = Triangle.of(box)
    if isinstance(node, str):
        if not fails_everywhere(node, triangle, params):
            raise CertificateError(
                f"node {index}: {brief(node)} is not a constraint that fails on all of its box"
            )
        return 0.0
    names = TARGET_ENCLOSURES[params.target]
    if not (isinstance(node, list) and len(node) == 2 and node[0] in names):
        raise CertificateError(
            f"node {index}: neither a split, a constraint nor [enclosure, bound] with an "
            f"enclosure of the {params.target} target ({', '.join(names)})"
        )
    name, stored = node
    bound = _finite(stored)
    if bound is None or bound > 1:
        raise CertificateError(f"node {index}: bound {brief(stored)} is not a finite float <= 1")
    value = fraction_enclosure(name, triangle, params)
    if not value <= arb(bound):
        top = float(value.upper()) if value.is_finite() else math.inf
        raise CertificateError(
            f"node {index}: the {name} enclosure reaches {top:.17g}, above its bound {bound!r}"
        )
    return bound


def _finite(value) -> float | None:
    if isinstance(value, bool) or not isinstance(value, int | float):
        return None
    try:
        number = float(value)
    except OverflowError:
        return None
    return number if math.isfinite(number) else None


def _claim(payload: dict) -> _Claim:
    """Target, parameters and precision of a certificate (CertificateError if malformed)."""
    version = payload.get("format_version")
    if (
        payload.get("format") != FORMAT
        or isinstance(version, bool)
        or not isinstance(version, int)
        or version not in VERSIONS
    ):
        raise CertificateError(
            f"not a {FORMAT} file of version 1 or 2: format {brief(payload.get('format'))}, "
            f"version {brief(version)}"
        )
    target = payload.get("target") if version >= 2 else "additive"
    if target not in TARGET_ENCLOSURES:
        raise CertificateError(f"certificate target must be additive or ratio, got {brief(target)}")
    if payload.get("dimensions", list(COORDINATES)) != list(COORDINATES):
        raise CertificateError(f"certificate coordinates must be {list(COORDINATES)} in order")
    given = payload.get("parameters")
    if not isinstance(given, dict):
        raise CertificateError("certificate has no parameters")
    bits = payload.get("precision_bits", 64)
    low, high = PRECISION_RANGE
    if isinstance(bits, bool) or not isinstance(bits, int) or not low <= bits <= high:
        raise CertificateError(f"precision_bits must be an integer in [{low}, {high}]")
    try:
        claim = _Claim(
            target,
            checked_number(given.get("sigma"), "sigma", *SIGMA_RANGE),
            checked_number(given.get("delta_ratio"), "delta_ratio", *DELTA_RATIO_RANGE),
            checked_number(given.get("rho_f"), "rho_f", 1.0, RHO_F_MAX, open_low=True),
            checked_lipschitz(given.get("lipschitz")),
            checked_number(given.get("eps_max"), "eps_max", *EPS_RANGE),
            bits,
        )
    except VoroboundError as exc:
        raise CertificateError(f"certificate parameters: {exc}") from None
    if Fraction(claim.sigma) * (1 - Fraction(claim.eps_max)) >= 2:
        raise CertificateError(
            "certificate parameters: sigma*(1 - eps_max) must be below 2 ((34) leaves no room)"
        )
    return claim


def _root_box(stored, domain: Box) -> Box:
    """The certificate's root box if it contains ``domain`` (absent: the domain itself)."""
    if stored is None:
        return domain
    try:
        if not (isinstance(stored, list) and len(stored) == len(COORDINATES)):
            raise ValueError
        root = []
        for pair in stored:
            if not (isinstance(pair, list) and len(pair) == 2):
                raise ValueError
            if not all(isinstance(end, str) for end in pair):
                raise ValueError
            root.append((Fraction(pair[0]), Fraction(pair[1])))
    except (ValueError, ZeroDivisionError):
        raise CertificateError(
            "root_box must be six [lo, hi] pairs of rationals written as strings"
        ) from None
    for name, (lo, hi), (need_lo, need_hi) in zip(COORDINATES, root, domain, strict=True):
        if not (lo <= need_lo and need_hi <= hi):
            raise CertificateError(
                f"the root box misses part of the domain its parameters define: {name} spans "
                f"[{float(lo):.17g}, {float(hi):.17g}], the domain "
                f"[{float(need_lo):.17g}, {float(need_hi):.17g}]"
            )
    return tuple(root)


@contextlib.contextmanager
def _precision(bits: int):
    saved = ctx.prec
    ctx.prec = bits
    try:
        yield
    finally:
        ctx.prec = saved


def _unique_keys(pairs: list) -> dict:
    """A JSON object whose keys are all different (a repeated key would make the file say two
    things: ``json`` keeps the last, a reader may see the first)."""
    out = dict(pairs)
    if len(out) != len(pairs):
        seen: set = set()
        key = None
        for key, _ in pairs:
            if key in seen:
                break
            seen.add(key)
        raise ValueError(f"key {key!r} appears twice in one object")
    return out
