"""``vorobound figure``: regenerate the figures (Figure 3 of the paper, comparison of modes,
the ratio target)."""

from __future__ import annotations

from ..api.figures import DEFAULT_OUT
from ..constants import PAPER_DELTA_RATIO, PAPER_RHO_F, PAPER_SIGMA
from .command import invoke
from .options import (
    DeltaRatio,
    FigureFormat,
    FigureFormatOpt,
    Json,
    Lfs,
    NoTight,
    Out,
    RhoF,
    Sigma,
)


def figure(
    out: Out = DEFAULT_OUT,
    figure_format: FigureFormatOpt = FigureFormat.png,
    sigma: Sigma = PAPER_SIGMA,
    delta_ratio: DeltaRatio = PAPER_DELTA_RATIO,
    lfs: Lfs = 1.0,
    rho_f: RhoF = PAPER_RHO_F,
    no_tight: NoTight = False,
    as_json: Json = False,
) -> int:
    """Regenerate all figures: Figure 3 of the paper, the comparison of modes (both targets)
    and the ratio target R ≤ ρ_f·R̂ per mode.

    The set is replaced as a whole: if anything fails, the previous files stay as they were.
    Python: vorobound.figure(out=...).
    """
    return invoke("figure", _show, locals())


def _show(result) -> None:
    for path in result.written:
        print(f"wrote {path}")
