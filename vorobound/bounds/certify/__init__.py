"""Interval certificates that the tight bound meets the target for every ε up to ε_max.

``certify`` runs the branch-and-bound of :mod:`.search` over boxes enclosed with
:mod:`.interval` (python-flint ``arb``, outward rounded) and returns the tree;
:mod:`.certificate` writes it as JSON and re-checks a file independently of the search.
"""

from __future__ import annotations

from dataclasses import dataclass

from ...checks import checked_count, checked_number
from ...errors import InputError, VoroboundError
from ...progress import Progress
from ..params import DELTA_RATIO_RANGE, EPS_RANGE, RHO_F_MAX, SIGMA_RANGE, checked_lipschitz
from .certificate import CheckReport, certificate_payload, check_certificate
from .interval import Setting, nearest_float
from .search import MAX_BOXES, MAX_DEPTH, Counterexample, NotCertified, SearchResult, search

DEFAULT_FRACTION = 0.999
"""Without an explicit ε_max, certify this fraction of the tight ε* (closed form)."""
FRACTION_RANGE = (1e-6, 1.5)
"""Accepted fractions of ε* (above 1 the search is expected to find a counterexample)."""
MAX_DEPTH_LIMIT = 10_000
MAX_BOXES_LIMIT = 10**10


@dataclass(frozen=True)
class Target:
    """What to certify: validated parameters, ε_max and the tight ε* it is compared with."""

    setting: Setting
    eps_star_tight: float | None
    """The tight ε* of :func:`~vorobound.bounds.tight.closed_form.tight_eps_star_closed_form`;
    None when there is none (the bound never or always exceeds the target) and ``eps`` was
    given explicitly."""
    eps_star_status: str
    """Whether that ε* is the tight one (proven exact) or a proven lower bound on it, or why
    there is none."""

    @classmethod
    def of(
        cls,
        sigma: float,
        delta_ratio: float,
        rho_f: float,
        lipschitz: float | None = None,
        *,
        eps: float | None = None,
        fraction: float = DEFAULT_FRACTION,
    ) -> Target:
        """Validate the parameters (InputError) and fix ε_max: ``eps``, else ``fraction``·ε*."""
        from ..tight.closed_form import tight_eps_star_closed_form

        sigma = checked_number(sigma, "sigma", *SIGMA_RANGE)
        delta_ratio = checked_number(delta_ratio, "delta_ratio", *DELTA_RATIO_RANGE)
        rho_f = checked_number(rho_f, "rho_f", 1.0, RHO_F_MAX, open_low=True)
        lipschitz = checked_lipschitz(lipschitz)
        if eps is None:
            tight = tight_eps_star_closed_form(sigma, delta_ratio, rho_f, lipschitz)
            fraction = checked_number(fraction, "fraction", *FRACTION_RANGE)
            eps = min(fraction * tight.eps_star, EPS_RANGE[1])
            star, status = tight.eps_star, tight.status.value
        else:
            # An explicit ε_max needs no ε*: the search proves the claim or finds a
            # counterexample (the closed form may have no root at these parameters).
            eps = checked_number(eps, "eps", *EPS_RANGE)
            try:
                tight = tight_eps_star_closed_form(sigma, delta_ratio, rho_f, lipschitz)
                star, status = tight.eps_star, tight.status.value
            except VoroboundError as exc:
                star, status = None, f"none: {exc}"
        if sigma * (1 - eps) >= 2:
            raise InputError(f"sigma*(1 - eps) must be below 2, got sigma={sigma:g}, eps={eps:g}")
        setting = Setting.of(sigma, delta_ratio, rho_f, lipschitz, eps)
        return cls(setting, star, status)


@dataclass(frozen=True)
class CertifyResult:
    """A finished certification: every ε in (0, eps_certified] meets the target."""

    target: Target
    search: SearchResult

    @property
    def eps_certified(self) -> float:
        return nearest_float(self.target.setting.eps_max)

    @property
    def ratio(self) -> float | None:
        """eps_certified / eps_star_tight (None when there is no tight ε*)."""
        star = self.target.eps_star_tight
        return None if star is None else self.eps_certified / star

    def certificate(self) -> dict:
        """The certificate as a JSON-ready dict."""
        return certificate_payload(self.search)


def certify(
    sigma: float,
    delta_ratio: float,
    rho_f: float,
    lipschitz: float | None = None,
    *,
    eps: float | None = None,
    fraction: float = DEFAULT_FRACTION,
    max_depth: int = MAX_DEPTH,
    max_boxes: int = MAX_BOXES,
    progress: Progress | None = None,
) -> CertifyResult:
    """Prove R − R̂ ≤ (ρ_f − 1)δL_i for every ε ≤ ε_max and every feasible guide triangle.

    Parameters
    ----------
    sigma, delta_ratio, rho_f : float
        σ, δ/ε and ρ_f of Section 4.1.
    lipschitz : float, optional
        λ of the optional Lipschitz conditions.
    eps : float, optional
        ε_max; by default ``fraction`` times the closed-form tight ε*.
    fraction : float
        Used when ``eps`` is not given.
    max_depth, max_boxes : int
        Limits of the search.
    progress : Progress, optional
        Progress callback.

    Returns
    -------
    CertifyResult
        ε_max, the tight ε* it is compared with, and the bisection tree.

    Raises
    ------
    NotCertified
        With a counterexample (ε_max above the true ε*) or an unresolved box.

    References
    ----------
    Theorem 1, eq. (33)–(37), (54)–(55), property H3; docs/tight.md.
    """
    target = Target.of(sigma, delta_ratio, rho_f, lipschitz, eps=eps, fraction=fraction)
    return certify_target(target, max_depth=max_depth, max_boxes=max_boxes, progress=progress)


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


def certify_target(
    target: Target,
    *,
    max_depth: int = MAX_DEPTH,
    max_boxes: int = MAX_BOXES,
    progress: Progress | None = None,
) -> CertifyResult:
    """:func:`certify` for parameters already validated by :meth:`Target.of`."""
    limits = search_limits(max_depth, max_boxes)
    return CertifyResult(target, search(target.setting, **limits, progress=progress))


__all__ = [
    "CertifyResult",
    "CheckReport",
    "Counterexample",
    "NotCertified",
    "Target",
    "certificate_payload",
    "check_certificate",
    "certify",
    "certify_target",
    "search_limits",
]
