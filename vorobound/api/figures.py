"""``vorobound figure`` and ``vorobound reproduce``: the paper's numbers beside this project's,
and the figures (Figure 3 of the paper, the comparison of modes)."""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

from ..bounds.params import QualityParams, Target
from ..constants import PAPER_DELTA_RATIO, PAPER_RHO_F, PAPER_SIGMA
from ..progress import Progress
from .arguments import checked_arguments
from .result import Result, checked_outputs, params_json

DEFAULT_OUT = Path("vorobound-figures")
"""Default output folder (not the repository's committed figures/)."""


def target_stars(quality: QualityParams, tight: bool = True, progress=None) -> list:
    """The ε* of both targets for paper, rigorous and (with ``tight``) each tight setting of
    :data:`vorobound.reports.figure_data.TIGHT_SETTINGS`, as the figures mark them; a mode
    and target without an ε* in the supported range are left out."""
    from ..bounds.guarantee import eps_star
    from ..errors import NoAdmissibleEps
    from ..reports.figure_data import TIGHT_SETTINGS

    asked: list[tuple[str, float | None]] = [(mode, None) for mode in ("paper", "rigorous")]
    asked += [("tight", lam) for lam in TIGHT_SETTINGS] if tight else []
    stars = []
    for mode, lam in asked:
        for target in (Target.additive, Target.ratio):
            try:
                stars.append(
                    eps_star(quality.but(target=target, lipschitz=lam), mode, progress=progress)
                )
            except NoAdmissibleEps:
                continue
    return stars


FIGURES = ("figure3", "comparison", "ratio")
"""The figures `vorobound figure` and `vorobound reproduce` write, by file stem."""


def write_figures(
    quality: QualityParams, out, figure_format: str, stars: list, tight: bool = True
) -> list[Path]:
    """Figure 3, the comparison of modes (both targets) and the ratio figure, written as one
    set (all files or none)."""
    from ..plotting import plot_comparison, plot_figure3, plot_ratio, save_set
    from ..reports.figure_data import figure_set_data

    checked_outputs(out, figure_format)
    figure3, targets = figure_set_data(quality, stars, tight)
    figures = {
        "figure3": plot_figure3(figure3),
        "comparison": plot_comparison(targets),
        "ratio": plot_ratio(targets),
    }
    return save_set(figures, out, figure_format)


@dataclass(frozen=True, repr=False)
class FigureResult(Result):
    """The figures written."""

    command = "figure"
    written: tuple[str, ...]
    quality: QualityParams = field(repr=False)

    def payload(self) -> dict:
        params = params_json(self.quality)
        params["target"] = [t.value for t in (Target.additive, Target.ratio)]
        return {"params": params, "figures": list(self.written)}


@checked_arguments
def figure(
    *,
    out: str | os.PathLike = DEFAULT_OUT,
    figure_format: str = "png",
    sigma: float = PAPER_SIGMA,
    delta_ratio: float = PAPER_DELTA_RATIO,
    lfs: float = 1.0,
    rho_f: float = PAPER_RHO_F,
    tight: bool = True,
    progress: Progress | None = None,
) -> FigureResult:
    """Regenerate every figure: Figure 3 of the paper, the comparison of modes (both targets)
    and the ratio target's figure (R/R̂ per mode), as one set in ``out``: if anything fails,
    the previous files stay as they were."""
    quality = QualityParams(sigma, delta_ratio, rho_f, lfs)
    stars = target_stars(quality, tight, progress)
    paths = write_figures(quality, out, figure_format, stars, tight)
    return FigureResult(tuple(os.fspath(p) for p in paths), quality)


@dataclass(frozen=True, repr=False)
class ReproduceResult(Result):
    """Every number the paper states beside this project's value for each mode."""

    command = "reproduce"
    paper_eps_star: float
    """The printed chain's ε* (the paper's 0.0047, additive target)."""
    tight_eps_star: float | None
    """The tight ε* of the ratio target, eq. (54) (None without the tight modes)."""
    written: tuple[str, ...] = field(repr=False)
    summaries: tuple = field(repr=False)
    rows: tuple = field(repr=False)
    quality: QualityParams = field(repr=False)

    def payload(self) -> dict:
        params = params_json(self.quality)
        del params["target"], params["lipschitz"]
        return {
            "params": params,
            "eps_star": {s.mode: s.star.eps_star for s in self.summaries},
            "eps_star_ratio": {s.mode: s.ratio_star.eps_star for s in self.summaries},
            "claims": {s.mode: s.star.claim for s in self.summaries},
            "rows": [
                {"quantity": r.quantity, "paper": r.paper, "values": r.values} for r in self.rows
            ],
            "figures": list(self.written),
        }


@checked_arguments
def reproduce(
    *,
    out: str | os.PathLike = DEFAULT_OUT,
    sigma: float = PAPER_SIGMA,
    delta_ratio: float = PAPER_DELTA_RATIO,
    lfs: float = 1.0,
    rho_f: float = PAPER_RHO_F,
    tight: bool = True,
    progress: Progress | None = None,
) -> ReproduceResult:
    """Every number the paper states beside this project's value for each mode; writes the
    figures into ``out``.

    Modes: paper (the printed chain: invalid), rigorous (the corrected chain: proven), tight
    (the supremum over the constraint set: proven in closed form, docs/tight.md) and tight with
    the 1-Lipschitz condition (λ = 1). The tight modes are certified by interval arithmetic up
    to 0.999·ε* for both targets.
    """
    from ..reports.reproduce import reproduce as run

    quality = QualityParams(sigma, delta_ratio, rho_f, lfs)
    summaries, rows = run(quality, tight=tight, progress=progress)
    stars = [star for s in summaries for star in (s.star, s.ratio_star)]
    paths = write_figures(quality, out, "png", stars, tight)
    tight_ratio = next((s.ratio_star.eps_star for s in summaries if s.mode == "tight"), None)
    return ReproduceResult(
        paper_eps_star=summaries[0].star.eps_star,
        tight_eps_star=tight_ratio,
        written=tuple(os.fspath(p) for p in paths),
        summaries=tuple(summaries),
        rows=tuple(rows),
        quality=quality,
    )
