"""``vorobound figure``: regenerate the figures (Figure 3 of the paper, comparison of modes,
the ratio target)."""

from __future__ import annotations

from ..api.figures import DEFAULT_OUT
from .command import grouped, invoke
from .options import (
    FigureFormat,
    FigureFormatOpt,
    Json,
    NoTight,
    Out,
    QualityOptions,
)


@grouped
def figure(
    out: Out = DEFAULT_OUT,
    figure_format: FigureFormatOpt = FigureFormat.png,
    quality: QualityOptions = QualityOptions(),
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
