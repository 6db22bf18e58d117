"""``vorobound solve``: the largest admissible ε of one mode, for one target."""

from __future__ import annotations

from dataclasses import dataclass, field

from ..bounds.eps_star import EpsStar
from ..bounds.params import Mode, QualityParams, Target, checked_target
from ..bounds.targets import H3_STATUS, STATEMENT, H3Route
from ..constants import BASELINE_EPS, PAPER_DELTA_RATIO, PAPER_RHO_F, PAPER_SIGMA
from ..progress import Progress
from .arguments import checked_arguments
from .result import Result, params_json

H3_ROUTE_STATEMENT = "H3 alone gives R <= rho_f*delta*L_i (eq. (55)) for every eps up to eps_star"


@dataclass(frozen=True, repr=False)
class SolveResult(Result):
    """ε* of one mode for one target, how strong it is, and what H3 alone gives."""

    command = "solve"
    eps_star: float
    mode: str
    target: str
    claim: str
    """proven, certified, numerical or invalid."""
    method: str
    proven_lower_bound: float | None
    """When the claim is numerical: an ε proven admissible by the closed form, if any."""
    h3_eps_star: float
    """The ε up to which H3 alone gives eq. (55)."""
    detail: EpsStar = field(repr=False)
    h3: H3Route = field(repr=False)

    @property
    def quality(self) -> QualityParams:
        return self.detail.quality

    @property
    def target_statement(self) -> str:
        return STATEMENT[Target(self.target)]

    @property
    def eps_star_over_baseline(self) -> float:
        return self.eps_star / BASELINE_EPS

    @property
    def ball_radius(self) -> float:
        """δ·L_i at ε*."""
        return self.detail.params.delta * self.quality.lfs

    premise = H3_STATUS
    """What every answer rests on (property H3)."""

    def payload(self) -> dict:
        star = self.detail
        out = {
            "params": params_json(self.quality, mode=self.mode),
            "mode": self.mode,
            "target": self.target,
            "target_statement": self.target_statement,
            "eps_star": self.eps_star,
            "claim": self.claim,
            "method": self.method,
            "proven_lower_bound": self.proven_lower_bound,
            "eps_star_over_baseline": self.eps_star_over_baseline,
            "ball_radius": self.ball_radius,
            "residual": star.residual,
            "iterations": star.iterations,
            "bracket": list(star.bracket),
            "premise": self.premise,
            "h3_route": {
                "eps_star": self.h3.eps_star,
                "claim": self.h3.claim,
                "statement": H3_ROUTE_STATEMENT,
            },
        }
        if self.target == Target.additive.value:
            out["gap_allowance_at_eps_star"] = star.params.gap_allowance
        if star.maximizer is not None:
            out["maximizer"] = star.maximizer
        return out


@checked_arguments
def solve(
    *,
    sigma: float = PAPER_SIGMA,
    delta_ratio: float = PAPER_DELTA_RATIO,
    lfs: float = 1.0,
    rho_f: float = PAPER_RHO_F,
    mode: Mode | str = "tight",
    target: Target | str = "ratio",
    lipschitz: float | None = None,
    method: str = "auto",
    progress: Progress | None = None,
) -> SolveResult:
    """The largest ε at which ``mode``'s bound meets ``target``, and how strong that is.

    Parameters
    ----------
    sigma, delta_ratio, lfs, rho_f : float
        σ, δ/ε, L_i and ρ_f of Section 4.1 (paper: 0.75, 2, 1, 1.38).
    mode : {"tight", "rigorous", "paper"}
        The supremum over the constraint set (proven in closed form where docs/tight.md says
        so, else numerical), the corrected chain (proven), or the printed chain (invalid).
    target : {"ratio", "additive"}
        R ≤ ρ_f·R̂ (eq. (54)), or R − R̂ ≤ (ρ_f − 1)·δ·L_i (gives (55), not (54)).
    lipschitz : float, optional
        Tight mode: λ of |L_x − L_y| ≤ λ|p_x − p_y| between the vertices.
    method : {"auto", "optimize"}
        Tight mode: the closed form where proven, or always the numerical optimizer.
    progress : callable, optional
        ``(task, done, total)`` callback.

    Returns
    -------
    SolveResult
        ``eps_star`` (a float), its ``claim`` and ``method``, and H3's own route to (55).

    References
    ----------
    Eq. (29)–(30), (33)–(55), property H3.
    """
    from ..bounds.guarantee import eps_star
    from ..bounds.targets import h3_route

    quality = QualityParams(sigma, delta_ratio, rho_f, lfs, lipschitz, checked_target(target))
    star = eps_star(quality, mode, method, progress)
    h3 = h3_route(quality)
    return SolveResult(
        eps_star=float(star.eps_star),
        mode=star.mode,
        target=star.target,
        claim=star.claim,
        method=star.method,
        proven_lower_bound=star.proven_lower_bound,
        h3_eps_star=h3.eps_star,
        detail=star,
        h3=h3,
    )
