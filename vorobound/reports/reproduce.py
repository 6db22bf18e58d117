"""The numbers the paper states, beside this project's value for each mode and both targets.

The paper's own target is the additive one, R − R̂ ≤ (ρ_f − 1)δL_i, so its rows come first;
the ratio target R ≤ ρ_f·R̂ (eq. (54), the form of VoroCrust's Lemma 9) and the ε up to which
H3 alone gives (55) follow (:mod:`vorobound.bounds.targets`).
"""

from __future__ import annotations

from dataclasses import dataclass

from ..bounds.eps_star import EpsStar
from ..bounds.guarantee import bound_at, eps_star
from ..bounds.params import QualityParams
from ..bounds.targets import h3_route
from ..constants import BASELINE_EPS, PAPER_EPS
from ..progress import Progress
from ..rounding import DOWN, UP
from .figure_data import TIGHT_SETTINGS

CHAIN_MODES = ("paper", "rigorous")


@dataclass(frozen=True)
class ModeSummary:
    """One mode's answers to the paper's claims, for both targets."""

    mode: str
    star: EpsStar
    """ε* of the additive target (the paper's)."""
    bound_at_paper_eps: float
    """Bound on R − R̂ at ε = 0.0047 (absolute, L_i = quality.lfs)."""
    bound_at_baseline: float
    """Bound on R − R̂ at ε = 1/500."""
    ratio_star: EpsStar
    """ε* of the ratio target R ≤ ρ_f·R̂."""
    ratio_at_paper_eps: float
    """Bound on R/R̂ at ε = 0.0047 (inf: none)."""
    certified: float | None = None
    """Largest ε of an additive interval certificate (``vorobound certify``), tight modes."""
    ratio_certified: float | None = None
    """Largest ε of a ratio certificate, tight modes."""


@dataclass(frozen=True)
class ReproductionRow:
    quantity: str
    paper: str
    values: dict[str, float | None]
    """Mode name → this project's value (None: not applicable to that mode)."""
    rounding: str
    """How a printed value is rounded (:mod:`vorobound.rounding`): DOWN for an admissible ε
    and what grows with it, UP for a bound."""


def summarize(
    quality: QualityParams,
    mode: str,
    certify: bool = False,
    progress: Progress | None = None,
) -> ModeSummary:
    """One column: ε* of both targets, the bounds at ε = 0.0047 and 1/500, and (tight mode
    with ``certify``) the largest ε interval certificates cover (0.999·ε*, about a second).
    ``quality.lipschitz`` is the tight mode's λ; the target is each of the two in turn."""
    additive, ratio_q = (quality.but(target=t) for t in ("additive", "ratio"))
    stars = {
        "additive": eps_star(additive, mode, progress=progress),
        "ratio": eps_star(ratio_q, mode, progress=progress),
    }
    gaps = [bound_at(additive.at(e), mode).value for e in (PAPER_EPS, BASELINE_EPS)]
    ratio = bound_at(ratio_q.at(PAPER_EPS), mode).value
    lipschitz = quality.lipschitz
    certified = {}
    if certify and mode == "tight":
        from ..bounds.certify import certify as run_certify

        for target, asked in (("additive", additive), ("ratio", ratio_q)):
            certified[target] = run_certify(asked, progress=progress).eps_certified
    name = mode if lipschitz is None else f"{mode} λ={lipschitz:g}"
    return ModeSummary(
        name,
        stars["additive"],
        gaps[0],
        gaps[1],
        stars["ratio"],
        ratio,
        certified.get("additive"),
        certified.get("ratio"),
    )


def reproduce(
    quality: QualityParams, tight: bool = True, certify: bool = True, progress=None
) -> tuple[list[ModeSummary], list[ReproductionRow]]:
    """Every column (paper, rigorous, and the tight settings) and the rows of the table."""
    summaries = [summarize(quality, mode, progress=progress) for mode in CHAIN_MODES]
    if tight:
        summaries += [
            summarize(quality.but(lipschitz=lam), "tight", certify, progress)
            for lam in TIGHT_SETTINGS
        ]
    return summaries, reproduction_rows(quality, summaries)


def reproduction_rows(
    quality: QualityParams, summaries: list[ModeSummary]
) -> list[ReproductionRow]:
    """Each number the paper states (ε* = 0.0047 vs 1/500, |R − R̂| ≤ 0.76ε, ρ_f < 1.38), then
    the ratio target and the H3 route."""

    def per_mode(fn):
        return {s.mode: fn(s) for s in summaries}

    ratio = quality.delta_ratio
    h3 = h3_route(quality).eps_star
    return [
        ReproductionRow(
            "largest admissible ε (ε*), additive target",
            "0.0047",
            per_mode(lambda s: s.star.eps_star),
            DOWN,
        ),
        ReproductionRow(
            "ε* / (1/500)",
            "2.35 (0.0047 vs 0.002)",
            per_mode(lambda s: s.star.eps_star / BASELINE_EPS),
            DOWN,
        ),
        ReproductionRow(
            "bound on |R − R̂| / (ε L_i) at ε = 0.0047",
            "≤ 0.76",
            per_mode(lambda s: s.bound_at_paper_eps / (PAPER_EPS * quality.lfs)),
            UP,
        ),
        ReproductionRow(
            "implied ρ_f = 1 + bound/(δ L_i) at ε = 0.0047",
            "< 1.38",
            per_mode(lambda s: 1 + s.bound_at_paper_eps / (ratio * PAPER_EPS * quality.lfs)),
            UP,
        ),
        ReproductionRow(
            "bound on |R − R̂| / (ε L_i) at ε = 1/500",
            "(not stated)",
            per_mode(lambda s: s.bound_at_baseline / (BASELINE_EPS * quality.lfs)),
            UP,
        ),
        ReproductionRow(
            "ε covered by an interval certificate, additive target",
            "(not stated)",
            per_mode(lambda s: s.certified),
            DOWN,
        ),
        ReproductionRow(
            "ε*, ratio target R ≤ ρ_f·R̂ (eq. (54))",
            "(not stated)",
            per_mode(lambda s: s.ratio_star.eps_star),
            DOWN,
        ),
        ReproductionRow(
            "bound on R/R̂ at ε = 0.0047",
            "(not stated)",
            per_mode(lambda s: s.ratio_at_paper_eps),
            UP,
        ),
        ReproductionRow(
            "ε covered by an interval certificate, ratio target",
            "(not stated)",
            per_mode(lambda s: s.ratio_certified),
            DOWN,
        ),
        ReproductionRow(
            "ε up to which H3 alone gives (55), any mode",
            "(not stated)",
            per_mode(lambda s: h3),
            DOWN,
        ),
    ]
