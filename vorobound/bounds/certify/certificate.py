"""Certificates: the bisection tree as JSON, and a checker that re-verifies it from scratch.

A certificate states: for every ε in (0, ε_max] and every guide triangle of the constraint set
of :mod:`vorobound.bounds.constraints` at σ, δ/ε, ρ_f (and λ), its target holds:
R − R̂ ≤ (ρ_f − 1)·δ·L_i (``additive``) or R ≤ ρ_f·R̂ (``ratio``, eq. (54)). It stores the
parameters and the bisection tree of the root box in pre-order: a split is the index of the
halved coordinate, a leaf is the name of a constraint that fails on all of the box, or
``[enclosure, bound]`` with a float ``bound ≤ 1`` above that enclosure of the target's
fraction. Format version 1 (before targets) is read as the additive target.

:func:`check_certificate` trusts nothing but the parameters: it rebuilds the root box from them
(the box every feasible configuration lies in), replays the splits at exact rational midpoints
(so the leaves tile the root box exactly; a missing or extra node breaks the replay), and
re-evaluates every leaf in interval arithmetic. A removed leaf, a changed split, a bound lowered
below its enclosure or raised above 1, or a false infeasibility claim is rejected.
"""

from __future__ import annotations

import json
import math
import platform
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from flint import arb

from ... import __version__
from ...checks import EPS_RANGE, brief, checked_number
from ...errors import CertificateError, ReadError
from ...files import write_text
from ...progress import Progress, silent
from .. import constraints
from ..params import QualityParams, Target
from . import interval
from .interval import DIMENSIONS, Setting, nearest_float
from .search import MAX_DEPTH, Leaf, SearchResult

FORMAT = "vorobound-certificate"
FORMAT_VERSION = 2
READABLE_VERSIONS = (1, 2)
"""Versions the checker reads (version 1 has no target: it is the additive one)."""
CHECK_PROGRESS_EVERY = 4096
"""Nodes between two progress reports of the checker."""
STATEMENT = (
    "For every eps in (0, eps_max] and every guide triangle satisfying the constraint set "
    "(33)-(36), H3, pairwise sparsity (and the Lipschitz conditions if lipschitz is given) at "
    "sigma, delta_ratio: {target}, with R^ the orthoradius after subtracting the minimum "
    "weight (Theorem 1). H3 is an assumption taken from the VoroCrust literature."
)
TARGET_STATEMENTS = {
    "additive": "R - R^ <= (rho_f - 1) * delta * L_i",
    "ratio": "R <= rho_f * R^ (eq. (54))",
}
ENCLOSURE_REASONS = {
    "additive": {
        "circumradius": "R - R^ <= R <= eps/(1-eps) L_i (R^ >= 0 and H3)",
        "chord": "R - R^ = R (a - a^)/a <= R |d|/a (triangle inequality on the chord B^C^)",
        "exact": "Theorem 1: a - a^ = (2 a.d - |d|^2)/(a + a^)",
    },
    "ratio": {
        "chord": "1 - R^/R = (a - a^)/a <= |d|/a (triangle inequality on the chord B^C^)",
        "exact": "Theorem 1: a - a^ = (2 a.d - |d|^2)/(a + a^), over a",
    },
}


def certificate_payload(result: SearchResult) -> dict:
    """The certificate of a finished search, as a JSON-ready dict (see the module docstring)."""
    setting = result.setting
    nodes: list = []
    infeasible: dict[str, int] = {}
    bounded: dict[str, int] = {}
    largest = 0.0
    for node in result.nodes:
        if isinstance(node, Leaf):
            if node.reason == "infeasible":
                nodes.append(node.name)
                infeasible[node.name] = infeasible.get(node.name, 0) + 1
            else:
                assert node.bound is not None, "a bound leaf carries its bound"
                nodes.append([node.name, node.bound])
                bounded[node.name] = bounded.get(node.name, 0) + 1
                largest = max(largest, node.bound)
        else:
            nodes.append(node)
    leaves = sum(infeasible.values()) + sum(bounded.values())
    return {
        "format": FORMAT,
        "format_version": FORMAT_VERSION,
        "statement": STATEMENT.format(target=TARGET_STATEMENTS[setting.target]),
        "target": setting.target,
        "parameters": _parameters(setting),
        "dimensions": list(DIMENSIONS),
        "root_box": [[str(lo), str(hi)] for lo, hi in setting.root_box()],
        "precision_bits": interval.PRECISION_BITS,
        "enclosures": ENCLOSURE_REASONS[setting.target],
        "summary": {
            "boxes": result.boxes,
            "leaves": leaves,
            "max_depth": result.max_depth,
            "infeasible": infeasible,
            "bound": bounded,
            "largest_bound": largest,
        },
        "versions": library_versions(),
        "search_seconds": result.seconds,
        "nodes": nodes,
    }


def _parameters(setting: Setting) -> dict:
    lam = setting.lipschitz
    return {
        "sigma": nearest_float(setting.sigma),
        "delta_ratio": nearest_float(setting.delta_ratio),
        "rho_f": nearest_float(setting.rho_f),
        "lipschitz": None if lam is None else nearest_float(lam),
        "eps_max": nearest_float(setting.eps_max),
    }


def library_versions() -> dict:
    """Versions of what produced or checked a certificate."""
    import flint

    return {
        "vorobound": __version__,
        "python-flint": flint.__version__,
        "flint": getattr(flint, "__FLINT_VERSION__", "unknown"),
        "python": platform.python_version(),
    }


def write_certificate(path, payload: dict) -> None:
    """Write ``payload`` as JSON (atomically, via :mod:`vorobound.files`)."""
    write_text(path, json.dumps(payload, separators=(",", ":")) + "\n")


MAX_CERTIFICATE_BYTES = 4 << 30
"""Largest certificate file read (a search within its box limit writes far less)."""
MAX_CHECK_DEPTH = 4 * MAX_DEPTH
"""Deepest box a checked certificate may have (the search stops at ``MAX_DEPTH`` by default);
deeper trees are refused before they cost memory."""


def read_certificate(path) -> dict:
    """Load a certificate file; ReadError if it is missing, not a regular file or not JSON."""
    path = Path(path)
    try:
        if not path.is_file():
            raise ReadError(f"cannot read {path}: not a regular file")
        if path.stat().st_size > MAX_CERTIFICATE_BYTES:
            raise ReadError(f"{path} is larger than {MAX_CERTIFICATE_BYTES >> 30} GiB")
        with open(path, encoding="utf-8") as handle:
            payload = json.load(handle, object_pairs_hook=_unique_keys)
    except OSError as exc:
        raise ReadError(f"cannot read {path}: {exc.strerror or exc}") from None
    except (UnicodeDecodeError, json.JSONDecodeError, RecursionError, ValueError) as exc:
        message = " ".join(str(exc).split())[:200] or type(exc).__name__
        raise ReadError(f"{path} is not a JSON certificate: {message}") from None
    if not isinstance(payload, dict):
        raise ReadError(f"{path} is not a JSON certificate (top level is not an object)")
    return payload


@dataclass(frozen=True)
class CertificateReport:
    """A certificate that passed :func:`check_certificate`."""

    eps_max: float
    """Every ε in (0, eps_max] is certified."""
    target: str
    """additive or ratio (what is certified)."""
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


def check_certificate(payload: dict, progress: Progress | None = None) -> CertificateReport:
    """Re-verify a certificate independently of how it was found.

    Parameters
    ----------
    payload : dict
        A certificate as read by :func:`read_certificate`.
    progress : Progress, optional
        Receives ("checking", nodes done, nodes).

    Returns
    -------
    CertificateReport
        What is certified.

    Raises
    ------
    CertificateError
        If the certificate is malformed, does not cover the root box, or a leaf fails.

    References
    ----------
    Theorem 1, eq. (33)–(37), (55), property H3.
    """
    start = time.perf_counter()
    setting = _setting(payload)
    nodes = payload.get("nodes")
    if not isinstance(nodes, list) or not nodes:
        raise CertificateError("certificate has no nodes")
    root = setting.root_box()
    if payload.get("root_box") is not None and payload["root_box"] != [
        [str(lo), str(hi)] for lo, hi in root
    ]:
        raise CertificateError("certificate's root box does not match its parameters")
    precision = payload.get("precision_bits", interval.PRECISION_BITS)
    if isinstance(precision, bool) or not isinstance(precision, int) or not 53 <= precision <= 4096:
        raise CertificateError(
            f"precision_bits must be an integer in [53, 4096], got {brief(precision)}"
        )
    report = progress or silent
    names = {c.name for c in constraints.CONSTRAINTS}
    stack = [(root, 0)]
    leaves = deepest = 0
    largest = 0.0
    with interval.working_precision(precision):
        for index, node in enumerate(nodes):
            if not stack:
                raise CertificateError(f"node {index}: extra nodes after the tree is complete")
            box, depth = stack.pop()
            deepest = max(deepest, depth)
            if depth > MAX_CHECK_DEPTH:
                raise CertificateError(
                    f"node {index}: deeper than {MAX_CHECK_DEPTH} levels of bisection"
                )
            if _is_split(node):
                left, right = interval.split(box, node)
                stack += [(right, depth + 1), (left, depth + 1)]
            else:
                largest = max(largest, _check_leaf(index, node, box, setting, names))
                leaves += 1
            if index % CHECK_PROGRESS_EVERY == 0:
                report("checking", index, len(nodes))
    if stack:
        raise CertificateError(
            f"certificate does not cover the domain: {len(stack)} box(es) have no node"
        )
    report("checking", len(nodes), len(nodes))
    params = _parameters(setting)
    return CertificateReport(
        eps_max=params["eps_max"],
        target=setting.target,
        sigma=params["sigma"],
        delta_ratio=params["delta_ratio"],
        rho_f=params["rho_f"],
        lipschitz=params["lipschitz"],
        boxes=len(nodes),
        leaves=leaves,
        max_depth=deepest,
        largest_bound=largest,
        seconds=time.perf_counter() - start,
    )


def _is_split(node) -> bool:
    if isinstance(node, bool) or not isinstance(node, int):
        return False
    if not 0 <= node < len(DIMENSIONS):
        raise CertificateError(f"split coordinate {brief(node)} is not in 0..{len(DIMENSIONS) - 1}")
    return True


def _check_leaf(index: int, node, box, setting: Setting, names: set[str]) -> float:
    """Re-verify one leaf; return its stored bound (0 for an infeasible leaf)."""
    point = interval.scaled(interval.balls(box))
    if isinstance(node, str):
        if node not in names:
            raise CertificateError(f"node {index}: unknown constraint {node!r}")
        if not interval.constraint_fails(node, point, setting):
            raise CertificateError(
                f"node {index}: constraint {node} does not fail on the whole box"
            )
        return 0.0
    valid = interval.enclosure_names(setting.target)
    if not (isinstance(node, list) and len(node) == 2 and node[0] in valid):
        raise CertificateError(
            f"node {index}: not a split, a constraint or [enclosure, bound] with an enclosure "
            f"of the {setting.target} target ({', '.join(valid)})"
        )
    name, stored = node
    bound = _finite_float(stored)
    if bound is None:
        raise CertificateError(f"node {index}: bound {brief(stored)} is not a finite float")
    if bound > 1:
        raise CertificateError(f"node {index}: stored bound {bound!r} exceeds the target (1)")
    value = interval.enclosures(point, setting, (name,))[name]
    if not value <= arb(bound):
        raise CertificateError(
            f"node {index}: the {name} enclosure reaches {float(value.upper()):.17g}, above the "
            f"stored bound {bound!r}"
        )
    return bound


def _finite_float(value) -> float | None:
    """``value`` as a float if it is a JSON number that a finite float holds exactly enough
    (an integer of 400 digits is not one), else None."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        return None
    try:
        number = float(value)
    except OverflowError:
        return None
    return number if math.isfinite(number) else None


def _setting(payload: dict) -> Setting:
    """The parameters of a certificate, validated (CertificateError if malformed)."""
    version = payload.get("format_version")
    if (
        payload.get("format") != FORMAT
        or isinstance(version, bool)
        or not isinstance(version, int)
        or version not in READABLE_VERSIONS
    ):
        raise CertificateError(
            f"not a {FORMAT} (version {' or '.join(map(str, READABLE_VERSIONS))}) file: format "
            f"{brief(payload.get('format'))}, version {brief(version)}"
        )
    target = payload.get("target") if version >= 2 else "additive"
    if target not in interval.TARGETS:
        raise CertificateError(f"certificate target must be additive or ratio, got {brief(target)}")
    if payload.get("dimensions", list(DIMENSIONS)) != list(DIMENSIONS):
        raise CertificateError(f"certificate coordinates must be {list(DIMENSIONS)}")
    params = payload.get("parameters")
    if not isinstance(params, dict):
        raise CertificateError("certificate has no parameters")
    # JSON values, of any type: QualityParams checks each (a missing one is None, refused)
    values: dict[str, Any] = {
        name: params.get(name) for name in ("sigma", "delta_ratio", "rho_f", "lipschitz")
    }
    try:
        quality = QualityParams(**values, target=Target(target))
        eps_max = checked_number(params.get("eps_max"), "eps_max", *EPS_RANGE)
    except ValueError as exc:
        raise CertificateError(f"certificate parameters: {exc}") from None
    if quality.sigma * (1 - eps_max) >= 2:
        raise CertificateError("certificate parameters: sigma*(1 - eps_max) must be below 2")
    return Setting.of(quality, eps_max)


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
