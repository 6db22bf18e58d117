"""``vorobound cheng``: Cheng et al.'s constant, the conjectured one, and the numeric supremum."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from ..progress import Progress
from .arguments import checked_arguments
from .result import Result

if TYPE_CHECKING:
    from ..studies.cheng import ChengResult


@dataclass(frozen=True, repr=False)
class ChengOutcome(Result):
    """R/R̂ under Cheng et al.'s weight condition: their constant, the conjecture, numerics."""

    command = "cheng"
    alpha: float
    dim: int
    c_rad: float
    c_conjectured: float
    numeric_sup: float
    """The numerical supremum of R/R̂ (inf: unbounded, for tetrahedra)."""
    result: ChengResult = field(repr=False)
    seed: int = field(repr=False, default=0)

    @property
    def unbounded(self) -> bool:
        return math.isinf(self.numeric_sup)

    def payload(self) -> dict:
        r = self.result
        return {
            "params": {"alpha": self.alpha, "dim": self.dim, "seed": self.seed},
            "alpha": self.alpha,
            "dim": self.dim,
            "c_rad": self.c_rad,
            "c_conjectured": self.c_conjectured,
            "numeric_sup": self.numeric_sup,
            "unbounded": self.unbounded,
            "maximizer": r.maximizer,
            "evidence": r.evidence,
        }


@checked_arguments
def cheng(*, alpha: float, dim: int = 2, seed: int = 0, progress: Progress | None = None):
    """R/R̂ for weights in [0, α²N(s)²]: c_rad = 1/sqrt(1 − 4α²), the conjectured
    1/sqrt(1 − 3α²), and the numerically maximized ratio (docs/cheng.md)."""
    from ..studies.cheng import cheng_constants

    if progress is not None:
        progress("global search and polishes", 0, None)
    result = cheng_constants(alpha, dim=dim, seed=seed)
    return ChengOutcome(
        alpha=result.alpha,
        dim=result.dim,
        c_rad=result.c_rad,
        c_conjectured=result.c_conjectured,
        numeric_sup=result.numeric_sup,
        result=result,
        seed=seed,
    )
