"""The numbers the paper states, beside this project's value for each mode."""

from __future__ import annotations

from dataclasses import dataclass

from ..bounds.chain import chain_bounds
from ..bounds.eps_star import EpsStar, solve_eps_star
from ..bounds.params import QualityParams
from ..constants import BASELINE_EPS, PAPER_EPS
from ..progress import Progress


@dataclass(frozen=True)
class ModeSummary:
    """One mode's answers to the paper's claims."""

    mode: str
    star: EpsStar
    bound_at_paper_eps: float
    """Bound on R − R̂ at ε = 0.0047 (absolute, L_i = quality.lfs)."""
    bound_at_baseline: float
    """Bound on R − R̂ at ε = 1/500."""
    certified: float | None = None
    """Largest ε of an interval certificate (``vorobound certify``), for the tight modes."""


@dataclass(frozen=True)
class ReproductionRow:
    quantity: str
    paper: str
    values: dict[str, float | None]
    """Mode name → this project's value (None: not applicable to that mode)."""


def summarize_chain(quality: QualityParams, mode: str) -> ModeSummary:
    """A chain's ε* and its bound at ε = 0.0047 and at ε = 1/500."""
    chain = chain_bounds(quality.at(PAPER_EPS), mode, eps=[PAPER_EPS, BASELINE_EPS])
    return ModeSummary(
        mode, solve_eps_star(quality, mode), float(chain.bound[0]), float(chain.bound[1])
    )


def summarize_tight(
    quality: QualityParams,
    lipschitz: float | None,
    star: EpsStar,
    certify: bool = True,
    progress: Progress | None = None,
) -> ModeSummary:
    """The tight mode's summary: its ε*, the tight bound at ε = 0.0047 and 1/500, and (with
    ``certify``) the largest ε an interval certificate covers (0.999·ε*, a second or so)."""
    from ..bounds.tight.method import tight_bound

    at = [tight_bound(quality.at(e), lipschitz).value for e in (PAPER_EPS, BASELINE_EPS)]
    certified = None
    if certify:
        from ..bounds.certify import certify as run_certify

        result = run_certify(
            quality.sigma, quality.delta_ratio, quality.rho_f, lipschitz, progress=progress
        )
        certified = result.eps_certified
    name = "tight" if lipschitz is None else f"tight λ={lipschitz:g}"
    return ModeSummary(name, star, at[0], at[1], certified)


def reproduction_rows(
    quality: QualityParams, summaries: list[ModeSummary]
) -> list[ReproductionRow]:
    """Each number the paper states (ε* = 0.0047 vs 1/500, |R − R̂| ≤ 0.76ε, ρ_f < 1.38)."""

    def per_mode(fn):
        return {s.mode: fn(s) for s in summaries}

    ratio = quality.delta_ratio
    return [
        ReproductionRow("largest admissible ε (ε*)", "0.0047", per_mode(lambda s: s.star.eps_star)),
        ReproductionRow(
            "ε* / (1/500)",
            "2.35 (0.0047 vs 0.002)",
            per_mode(lambda s: s.star.eps_star / BASELINE_EPS),
        ),
        ReproductionRow(
            "bound on |R − R̂| / (ε L_i) at ε = 0.0047",
            "≤ 0.76",
            per_mode(lambda s: s.bound_at_paper_eps / (PAPER_EPS * quality.lfs)),
        ),
        ReproductionRow(
            "implied ρ_f = 1 + bound/(δ L_i) at ε = 0.0047",
            "< 1.38",
            per_mode(lambda s: 1 + s.bound_at_paper_eps / (ratio * PAPER_EPS * quality.lfs)),
        ),
        ReproductionRow(
            "bound on |R − R̂| / (ε L_i) at ε = 1/500",
            "(not stated)",
            per_mode(lambda s: s.bound_at_baseline / (BASELINE_EPS * quality.lfs)),
        ),
        ReproductionRow(
            "ε covered by an interval certificate",
            "(not stated)",
            per_mode(lambda s: s.certified),
        ),
    ]
