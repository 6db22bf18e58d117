"""``vorobound certify``: an interval certificate of the tight bound, or the re-check of one."""

from __future__ import annotations

import os
import typing
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from ..bounds.params import QualityParams, Target, checked_target
from ..bounds.targets import H3_STATUS
from ..constants import PAPER_DELTA_RATIO, PAPER_RHO_F, PAPER_SIGMA
from ..progress import Progress
from .arguments import checked_arguments
from .result import Result, params_json

if TYPE_CHECKING:
    from ..bounds.certify import Certification
    from ..bounds.certify.certificate import CertificateReport
    from ..bounds.independent import IndependentReport
    from ..errors import NotCertified

DEFAULT_FRACTION = 0.999


@dataclass(frozen=True, repr=False)
class CertifyResult(Result):
    """A finished certification: certified up to ``eps_certified``, or not (with why)."""

    command = "certify"
    certified: bool
    target: str
    eps_max: float
    """The largest ε asked for (``eps``, or ``fraction`` × the tight ε*)."""
    eps_certified: float | None
    """Every ε in (0, eps_certified] meets the target for every feasible guide triangle."""
    eps_star_tight: float | None
    ratio: float | None
    """eps_certified / eps_star_tight."""
    boxes: int | None
    reason: str
    """Empty when certified; else why not (a counterexample, or a limit of the search)."""
    certificate: str | None = None
    """Where the certificate was written (``output``), if anywhere."""
    quality: QualityParams = field(repr=False, kw_only=True)
    detail: Certification | NotCertified = field(repr=False, kw_only=True)
    """The bounds layer's CertifyResult, or the NotCertified failure."""

    @property
    def ok(self) -> bool:
        return self.certified

    @property
    def verdict(self) -> str:
        return f"not certified: {self.reason}"

    premise = H3_STATUS
    """What the certificate rests on (property H3)."""

    @property
    def certification(self) -> Certification:
        """The search that certified (only when ``certified``)."""
        if not self.certified:
            raise AttributeError("not certified: no certification")
        return typing.cast("Certification", self.detail)

    @property
    def statement(self) -> str:
        """What the certificate proves (certified results only)."""
        return self.certification.certificate()["statement"]

    def payload(self) -> dict:
        out = {
            "params": params_json(self.quality, eps=self.eps_max, mode="tight"),
            "certified": self.certified,
            "claim": "certified" if self.certified else "not certified",
            "target": self.target,
        }
        if not self.certified:
            return out | {"reason": self.reason} | _failure_payload(self.detail, self.target)
        result = self.certification
        search = result.search
        return out | {
            "statement": self.statement,
            "eps_certified": self.eps_certified,
            "eps_star_tight": self.eps_star_tight,
            "eps_star_tight_status": result.request.eps_star_status,
            "ratio": self.ratio,
            "boxes": search.boxes,
            "max_depth": search.max_depth,
            "seconds": search.seconds,
            "certificate": self.certificate,
            "premise": self.premise,
        }


def _failure_payload(failure, target: str) -> dict:
    """The counterexample (feasible, checked in intervals and floats) or the unresolved box."""
    from ..bounds.certify.interval import DIMENSIONS, nearest_float
    from ..bounds.certify.search import absolute_configuration

    out: dict = {}
    found = failure.counterexample
    if found is not None:
        tri = absolute_configuration(found.point)
        out["counterexample"] = {
            "eps": found.point[0],
            "b": float(tri.b[0]),
            "c": float(tri.c[0]),
            "theta": float(tri.theta[0]),
            "lfs_j": 1 + float(tri.excess_j[0]),
            "lfs_k": 1 + float(tri.excess_k[0]),
            "excess_j": float(tri.excess_j[0]),
            "excess_k": float(tri.excess_k[0]),
            "ratio_interval": [found.ratio_lower, found.ratio_upper],
            "ratio_float": found.ratio_float,
            "units": "L_i = 1; ratio = "
            + (
                "((R - R^)/R)/(1 - 1/rho_f), above 1 exactly where R > rho_f R^"
                if target == Target.ratio.value
                else "(R - R^)/((rho_f - 1) delta L_i)"
            ),
            # the exact point that interval arithmetic checked
            "coordinates": dict(zip(DIMENSIONS, found.point, strict=True)),
        }
    if failure.box is not None:
        out["box"] = [[nearest_float(lo), nearest_float(hi)] for lo, hi in failure.box]
    return out


@checked_arguments
def certify(
    *,
    sigma: float = PAPER_SIGMA,
    delta_ratio: float = PAPER_DELTA_RATIO,
    rho_f: float = PAPER_RHO_F,
    lipschitz: float | None = None,
    target: Target | str = "ratio",
    eps: float | None = None,
    fraction: float = DEFAULT_FRACTION,
    output: str | os.PathLike | None = None,
    max_depth: int | None = None,
    max_boxes: int | None = None,
    progress: Progress | None = None,
) -> CertifyResult:
    """Prove with interval arithmetic that ``target`` holds for every ε ≤ ``eps`` (default
    ``fraction`` × the tight ε*) and every guide triangle of the constraint set.

    Returns a result with ``certified`` True (and the certificate written to ``output`` if
    given), or False with a feasible counterexample or the box the search could not resolve.

    References
    ----------
    Theorem 1, eq. (33)–(37), (54)–(55), property H3; docs/tight.md.
    """
    from ..bounds.certify import CertifyRequest, NotCertified, certify_request, search_limits
    from ..bounds.certify.interval import nearest_float
    from ..files import checked_destination

    quality = QualityParams(
        sigma, delta_ratio, rho_f, lipschitz=lipschitz, target=checked_target(target)
    )
    limits = search_limits(max_depth, max_boxes)
    if output is not None:
        checked_destination(output)
    request = CertifyRequest.of(quality, eps=eps, fraction=fraction, progress=progress)
    eps_max = nearest_float(request.setting.eps_max)
    try:
        result = certify_request(request, **limits, progress=progress)
    except NotCertified as failure:
        return CertifyResult(
            certified=False,
            target=quality.target.value,
            eps_max=eps_max,
            eps_certified=None,
            eps_star_tight=request.eps_star_tight,
            ratio=None,
            boxes=None,
            reason=str(failure),
            quality=quality,
            detail=failure,
        )
    written = None
    if output is not None:
        from ..bounds.certify.certificate import write_certificate

        write_certificate(output, result.certificate())
        written = os.fspath(output)
    return CertifyResult(
        certified=True,
        target=quality.target.value,
        eps_max=eps_max,
        eps_certified=result.eps_certified,
        eps_star_tight=request.eps_star_tight,
        ratio=result.ratio,
        boxes=result.search.boxes,
        reason="",
        certificate=written,
        quality=quality,
        detail=result,
    )


CHECKERS = ("prover", "independent")
"""The two checkers ``certify --check`` runs: the prover's own re-check
(:func:`vorobound.bounds.certify.check_certificate`, which shares the prover's enclosures and
constraint code) and :func:`vorobound.bounds.independent.check_independently`, written apart
from it. A certificate is valid only when both accept it and agree on what it certifies."""
AGREED_FIELDS = (
    "eps_max",
    "target",
    "sigma",
    "delta_ratio",
    "rho_f",
    "lipschitz",
    "boxes",
    "leaves",
    "max_depth",
    "largest_bound",
)
"""What the two checkers' reports must agree on."""


@dataclass(frozen=True)
class CheckerVerdict:
    """One checker's answer on a certificate."""

    name: str
    valid: bool
    reason: str
    """Empty when valid; else why the checker rejects the certificate."""
    seconds: float
    report: CertificateReport | IndependentReport | None = field(repr=False, default=None)


@dataclass(frozen=True, repr=False)
class CertificateCheck(Result):
    """A certificate file re-checked by both checkers: ``valid`` when both accept it and agree
    on what it certifies, else the disagreement (``reason`` names the checker)."""

    command = "certify"
    valid: bool
    certificate: str
    target: str
    eps_certified: float | None
    """Every ε in (0, eps_certified] is certified (None unless valid)."""
    boxes: int
    leaves: int
    largest_bound: float
    """Largest stored bound of the target's fraction over the bound leaves (≤ 1)."""
    seconds: float
    """Both checkers together."""
    reason: str = ""
    """Empty when valid; else the disagreement between the checkers."""
    checkers: tuple[CheckerVerdict, ...] = ()
    report: CertificateReport | IndependentReport = field(repr=False, kw_only=True)
    versions: dict = field(repr=False, default_factory=dict)

    @property
    def ok(self) -> bool:
        return self.valid

    @property
    def verdict(self) -> str:
        return f"not valid: {self.reason}"

    def payload(self) -> dict:
        r = self.report
        return {
            "params": {
                "sigma": r.sigma,
                "delta_ratio": r.delta_ratio,
                "rho_f": r.rho_f,
                "lipschitz": r.lipschitz,
                "target": r.target,
                "eps": r.eps_max,
            },
            "valid": self.valid,
            "claim": "certified" if self.valid else "not certified",
            "checkers": [
                {"name": c.name, "valid": c.valid, "seconds": c.seconds, "reason": c.reason}
                for c in self.checkers
            ],
            "reason": self.reason,
            "certificate": self.certificate,
            "target": self.target,
            "eps_certified": self.eps_certified,
            "boxes": self.boxes,
            "leaves": self.leaves,
            "max_depth": r.max_depth,
            "largest_bound": self.largest_bound,
            "seconds": self.seconds,
            "versions": self.versions,
        }


@checked_arguments
def check_certificate(path: str | os.PathLike, progress: Progress | None = None):
    """Re-verify a certificate file with both checkers (``vorobound certify --check``).

    Returns a valid result when both accept it and agree on what it certifies; a result with
    ``valid`` False and the disagreement in ``reason`` when they do not (exit code 1). Raises
    CertificateError (the prover's checker's reason) when both reject it, ReadError when the
    file is not a JSON certificate.
    """
    from ..bounds.certify.certificate import check_certificate as prover_check
    from ..bounds.certify.certificate import library_versions, read_certificate
    from ..bounds.independent import check_file_independently
    from ..errors import CertificateError

    payload = read_certificate(path)
    verdicts = (
        _verdict(CHECKERS[0], lambda: prover_check(payload, progress)),
        # the independent checker reads and parses the file itself
        _verdict(CHECKERS[1], lambda: check_file_independently(path, progress)),
    )
    accepted = [v for v in verdicts if v.valid]
    if not accepted:
        first, second = verdicts
        raise CertificateError(f"{first.reason} (the {second.name} checker rejects it too)")
    reason = _disagreement(verdicts)
    report = accepted[0].report
    assert report is not None  # an accepting checker has its report
    return CertificateCheck(
        valid=not reason,
        certificate=os.fspath(path),
        target=report.target,
        eps_certified=None if reason else report.eps_max,
        boxes=report.boxes,
        leaves=report.leaves,
        largest_bound=report.largest_bound,
        seconds=sum(v.seconds for v in verdicts),
        reason=reason,
        checkers=verdicts,
        report=report,
        versions={"certificate": payload.get("versions"), "checker": library_versions()},
    )


def _verdict(name: str, run) -> CheckerVerdict:
    """Run one checker (a function of no arguments) and time it."""
    import time

    from ..errors import CertificateError

    start = time.perf_counter()
    try:
        report = run()
    except CertificateError as exc:
        return CheckerVerdict(name, False, str(exc), time.perf_counter() - start)
    return CheckerVerdict(name, True, "", time.perf_counter() - start, report)


def _disagreement(verdicts: tuple[CheckerVerdict, ...]) -> str:
    """Empty when both checkers accept and their reports agree; else what differs, naming
    the checker."""
    first, second = verdicts
    for rejecting, accepting in ((first, second), (second, first)):
        if not rejecting.valid:
            return (
                f"the checkers disagree: the {rejecting.name} checker rejects the certificate "
                f"({rejecting.reason}) while the {accepting.name} checker accepts it"
            )
    for key in AGREED_FIELDS:
        one, two = getattr(first.report, key), getattr(second.report, key)
        if one != two:
            return (
                f"the checkers disagree on {key}: {one!r} ({first.name} checker) against "
                f"{two!r} ({second.name} checker)"
            )
    return ""
