"""Interval certificates that the tight bound meets a target (additive or ratio, eq. (54)) for
every ε up to ε_max.

``certify`` runs the branch-and-bound of :mod:`.search` over boxes enclosed with
:mod:`.interval` (python-flint ``arb``, outward rounded) and returns the tree;
:mod:`.certificate` writes it as JSON and re-checks a file independently of the search.
"""

from __future__ import annotations

from dataclasses import dataclass

from ...checks import EPS_RANGE, checked_count, checked_number
from ...errors import InputError, NotCertified, VoroboundError
from ...progress import Progress
from ..params import QualityParams
from .certificate import CertificateReport, certificate_payload, check_certificate
from .interval import Setting, nearest_float
from .search import MAX_BOXES, MAX_DEPTH, Counterexample, SearchResult, search

DEFAULT_FRACTION = 0.999
"""Without an explicit ε_max, certify this fraction of the tight ε* (what ``solve`` prints)."""
FRACTION_RANGE = (1e-6, 1.5)
"""Accepted fractions of ε* (above 1 the search is expected to find a counterexample)."""
MAX_DEPTH_LIMIT = 10_000
MAX_BOXES_LIMIT = 10**10


@dataclass(frozen=True)
class CertifyRequest:
    """What to certify: validated parameters, the target, ε_max and the tight ε* it is
    compared with."""

    setting: Setting
    eps_star_tight: float | None
    """The tight ε* of :func:`~vorobound.bounds.tight.method.tight_eps_star` for the same
    target (the closed form where it is proven exact, else the optimizer); None when there is
    none and ``eps`` was given explicitly."""
    eps_star_status: str
    """How strong that ε* is (proven exact, or numerical with the closed form's proven lower
    bound), or why there is none."""

    @property
    def target(self) -> str:
        return self.setting.target

    @classmethod
    def of(
        cls,
        quality: QualityParams,
        *,
        eps: float | None = None,
        fraction: float = DEFAULT_FRACTION,
        progress: Progress | None = None,
    ) -> CertifyRequest:
        """Fix ε_max for ``quality`` (its target and λ): ``eps``, else ``fraction``·ε*."""
        if not isinstance(quality, QualityParams):
            raise InputError(f"quality must be QualityParams, got {type(quality).__name__}")
        if eps is None:
            fraction = checked_number(fraction, "fraction", *FRACTION_RANGE)
            star, status, base = _tight_eps_star(quality, progress)
            assert base is not None, "with the default, no base raises InputError"
            eps = min(fraction * base, EPS_RANGE[1])
        else:
            # An explicit ε_max needs no ε*: the search proves the claim or finds a
            # counterexample (there may be no ε* at these parameters).
            eps = checked_number(eps, "eps", *EPS_RANGE)
            try:
                star, status, _ = _tight_eps_star(quality, progress, default=False)
            except VoroboundError as exc:
                star, status = None, f"none: {exc}"
        if quality.sigma * (1 - eps) >= 2:
            raise InputError(
                f"sigma*(1 - eps) must be below 2, got sigma={quality.sigma:g}, eps={eps:g}"
            )
        return cls(Setting.of(quality, eps), star, status)


def _tight_eps_star(
    quality: QualityParams, progress, default: bool = True
) -> tuple[float, str, float | None]:
    """(ε*, its status, the ε* a default certificate covers a fraction of), from the one tight
    solver ``solve`` uses too.

    A proven ε* is certified as such. Where it is numerical, the default certifies the closed
    form's proven lower bound when there is one (the search is fast there); beyond it the
    bisection must resolve a maximizer that no closed form describes, which can exhaust the
    box limit (``--eps`` asks for it explicitly). Without a proven lower bound there is no
    default: the search at the numerical ε* can run for many minutes and still fail (measured
    at σ = 1.9, ratio target), so the user must name the ε to try.

    Raises
    ------
    InputError
        When ε* is numerical and has no proven lower bound.
    """
    from ..claims import PROVEN
    from ..tight.method import tight_eps_star

    result = tight_eps_star(quality, progress=progress)
    if result.claim == PROVEN:
        return result.eps_star, "proven exact (closed form)", result.eps_star
    lower = result.proven_lower_bound
    if lower is None and not default:
        return result.eps_star, "numerical (optimizer; no proven lower bound)", None
    if lower is None:
        raise InputError(
            f"the tight {quality.target.value} eps* = {result.eps_star:.6g} here is numerical "
            "and has no proven lower bound, so there is no default to certify: certifying a "
            "numerical eps* can take many minutes and still fail; give --eps to try a value"
        )
    status = f"numerical (optimizer); the default certifies its proven lower bound {lower:.12g}"
    return result.eps_star, status, lower


@dataclass(frozen=True)
class Certification:
    """A finished certification: every ε in (0, eps_certified] meets the target."""

    request: CertifyRequest
    search: SearchResult

    @property
    def eps_certified(self) -> float:
        return nearest_float(self.request.setting.eps_max)

    @property
    def ratio(self) -> float | None:
        """eps_certified / eps_star_tight (None when there is no tight ε*)."""
        star = self.request.eps_star_tight
        return None if star is None else self.eps_certified / star

    def certificate(self) -> dict:
        """The certificate as a JSON-ready dict."""
        return certificate_payload(self.search)


def certify(
    quality: QualityParams,
    *,
    eps: float | None = None,
    fraction: float = DEFAULT_FRACTION,
    max_depth: int = MAX_DEPTH,
    max_boxes: int = MAX_BOXES,
    progress: Progress | None = None,
) -> Certification:
    """Prove the target for every ε ≤ ε_max and every feasible guide triangle.

    Parameters
    ----------
    quality : QualityParams
        σ, δ/ε and ρ_f of Section 4.1, λ of the optional Lipschitz conditions, and the
        target: R − R̂ ≤ (ρ_f − 1)δL_i (additive), or R ≤ ρ_f·R̂ (ratio, eq. (54)).
    eps : float, optional
        ε_max; by default ``fraction`` times the tight ε* of the same target.
    fraction : float
        Used when ``eps`` is not given.
    max_depth, max_boxes : int
        Limits of the search.
    progress : Progress, optional
        Progress callback.

    Returns
    -------
    Certification
        ε_max, the tight ε* it is compared with, and the bisection tree.

    Raises
    ------
    NotCertified
        With a counterexample (ε_max above the true ε*) or an unresolved box.

    References
    ----------
    Theorem 1, eq. (33)–(37), (54)–(55), property H3; docs/tight.md.
    """
    request = CertifyRequest.of(quality, eps=eps, fraction=fraction, progress=progress)
    return certify_request(request, max_depth=max_depth, max_boxes=max_boxes, progress=progress)


def search_limits(max_depth: int | None = None, max_boxes: int | None = None) -> dict:
    """Validated search limits (None: the defaults), as keyword arguments of the search."""
    return {
        "max_depth": checked_count(
            MAX_DEPTH if max_depth is None else max_depth, "max_depth", 1, MAX_DEPTH_LIMIT
        ),
        "max_boxes": checked_count(
            MAX_BOXES if max_boxes is None else max_boxes, "max_boxes", 1, MAX_BOXES_LIMIT
        ),
    }


def certify_request(
    request: CertifyRequest,
    *,
    max_depth: int = MAX_DEPTH,
    max_boxes: int = MAX_BOXES,
    progress: Progress | None = None,
) -> Certification:
    """:func:`certify` for parameters already validated by :meth:`CertifyRequest.of`."""
    limits = search_limits(max_depth, max_boxes)
    return Certification(request, search(request.setting, **limits, progress=progress))


__all__ = [
    "Certification",
    "CertificateReport",
    "Counterexample",
    "NotCertified",
    "CertifyRequest",
    "certificate_payload",
    "check_certificate",
    "certify",
    "certify_request",
    "search_limits",
]
