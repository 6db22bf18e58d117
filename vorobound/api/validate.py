"""``vorobound validate``: audit every printed step and every mode's bound on sampled feasible
guide triangles."""

from __future__ import annotations

from dataclasses import dataclass, field

from ..bounds.claims import CHAIN_CLAIM, INVALID
from ..bounds.params import QualityParams, SamplingParams
from ..constants import PAPER_DELTA_RATIO, PAPER_RHO_F, PAPER_SIGMA
from ..progress import Progress
from ..reports.validate import ValidationReport
from .arguments import checked_arguments
from .result import Result, params_json


@dataclass(frozen=True, repr=False)
class ValidateResult(Result):
    """The printed chain's steps and every mode's bound against sampled feasible triangles."""

    command = "validate"
    eps: float
    samples: int
    seed: int
    max_radius_gap: float
    failing_steps: int
    """Printed inequalities with at least one violation (the paper's invalid steps)."""
    exceeded_proven_bounds: int
    """Proven bounds (rigorous, tight) exceeded by a sampled triangle: 0 unless there is a bug."""
    report: ValidationReport = field(repr=False)
    params: SamplingParams = field(repr=False)

    @property
    def ok(self) -> bool:
        return self.exceeded_proven_bounds == 0

    @property
    def verdict(self) -> str:
        return (
            f"{self.exceeded_proven_bounds} proven bound(s) exceeded by a sampled feasible "
            "guide triangle (a bug: please report it)"
        )

    def payload(self) -> dict:
        return {
            "params": params_json(
                self.params.quality, self.eps, samples=self.samples, seed=self.seed
            ),
            "max_radius_gap": self.max_radius_gap,
            "inequalities": self.report.inequalities,
            "modes": self.report.modes,
            "failing_steps": self.failing_steps,
            "exceeded_proven_bounds": self.exceeded_proven_bounds,
            "ok": self.ok,
        }


@checked_arguments
def validate(
    *,
    eps: float,
    samples: int = 20_000,
    seed: int = 0,
    lipschitz: float | None = None,
    sigma: float = PAPER_SIGMA,
    delta_ratio: float = PAPER_DELTA_RATIO,
    lfs: float = 1.0,
    rho_f: float = PAPER_RHO_F,
    tight: bool = True,
    progress: Progress | None = None,
) -> ValidateResult:
    """Sample feasible guide triangles (uniform and biased to the boundary) and check every
    printed inequality of (33)–(53) and every mode's bound on R − R̂.

    A printed step with violations is wrong (docs/errata.md); a proven bound exceeded would be
    a bug (``ok`` is then False).

    References
    ----------
    Eq. (33)–(53).
    """
    from ..reports.validate import validate as run

    params = QualityParams(sigma, delta_ratio, rho_f, lfs, lipschitz).at(eps)
    if progress is not None:
        progress("sampling and auditing", 0, None)
    report = run(params, samples, seed, tight=tight)
    proven = [m for m in report.modes if CHAIN_CLAIM.get(m) != INVALID]
    return ValidateResult(
        eps=params.eps,
        samples=report.samples,
        seed=report.seed,
        max_radius_gap=report.max_radius_gap,
        failing_steps=sum(a.violations > 0 for a in report.inequalities.values()),
        exceeded_proven_bounds=sum(report.modes[m] > 1 for m in proven),
        report=report,
        params=params,
    )
