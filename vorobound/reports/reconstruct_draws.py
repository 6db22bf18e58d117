"""M̂ over many draws of the sampler: at each ε, how often M̂ has the right topology and how
far its measurements spread, and the ε band where M̂ goes from always right to never right.

One random sample says little about a property of the sampling: the same ε can give the right
M̂ in one draw and the wrong one in the next. Draw ``k`` of ``repeats`` samples with the seed
``seed + k`` (so every draw can be repeated alone with ``--seed``).

References
----------
The sampling conditions of Section 4.1; the ε* of every mode and target, eq. (33)–(55).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..bounds.params import QualityParams
from ..errors import InputError
from ..progress import Counter, Progress
from ..sampling.surfaces.base import ExpectedTopology
from .reconstruct import MhatOptions
from .reconstruct_sweep import SWEEP_COLUMNS, EpsMark, SweepRow, bound_marks, csv_line, sweep_rows

DRAWS_CSV = "draws.csv"
"""File name of the table with one line per draw and ε."""


@dataclass(frozen=True)
class Spread:
    """Median and largest value of one measurement over the draws that have it."""

    median: float | None
    max: float | None
    count: int
    """Draws with a value (a draw without M̂ has none)."""

    @classmethod
    def of(cls, values) -> Spread:
        kept = np.array([v for v in values if v is not None], dtype=float)
        kept = kept[np.isfinite(kept)]
        if len(kept) == 0:
            return cls(None, None, 0)
        return cls(float(np.median(kept)), float(kept.max()), len(kept))


@dataclass(frozen=True)
class DrawsRow:
    """One ε over every draw."""

    eps: float
    draws: tuple[SweepRow, ...]
    """One row per draw, in the order of their seeds."""
    seeds: tuple[int, ...]

    @property
    def correct(self) -> int:
        """Draws whose M̂ has the surface's topology."""
        return sum(row.ok for row in self.draws)

    @property
    def share_correct(self) -> float:
        return self.correct / len(self.draws)

    @property
    def hausdorff(self) -> Spread:
        """Hausdorff distance over ε·L (measured), over the draws with M̂."""
        return Spread.of(row.hausdorff for row in self.draws)

    @property
    def normal_deviation_max(self) -> Spread:
        """Largest normal deviation (degrees) of each draw, over the draws with M̂."""
        return Spread.of(row.normal_deviation_max for row in self.draws)

    def summary(self) -> dict:
        return {
            "eps": self.eps,
            "draws": len(self.draws),
            "correct": self.correct,
            "share_correct": self.share_correct,
            "hausdorff": vars(self.hausdorff),
            "normal_deviation_max": vars(self.normal_deviation_max),
            "samples_median": Spread.of(row.samples for row in self.draws).median,
            "per_draw": [
                {"seed": seed} | vars(row) for seed, row in zip(self.seeds, self.draws, strict=True)
            ],
        }


@dataclass(frozen=True)
class ReconstructDraws:
    """M̂ of one surface over ``repeats`` draws at each ε, and every bound's ε*."""

    source: str
    quality: QualityParams
    seed: int
    """Seed of the first draw (draw k has seed + k)."""
    repeats: int
    expected: ExpectedTopology | None
    rows: list[DrawsRow]
    marks: list[EpsMark]

    @property
    def largest_all_correct_eps(self) -> float | None:
        """The largest ε at which every draw gave the right M̂ (None: no such ε)."""
        return max((r.eps for r in self.rows if r.correct == len(r.draws)), default=None)

    @property
    def smallest_none_correct_eps(self) -> float | None:
        """The smallest ε at which no draw gave the right M̂ (None: no such ε)."""
        return min((r.eps for r in self.rows if r.correct == 0), default=None)

    def summary(self) -> dict:
        return {
            "source": self.source,
            "params": {"sigma": self.quality.sigma, "delta_ratio": self.quality.delta_ratio},
            "repeats": self.repeats,
            "seed_range": [self.seed, self.seed + self.repeats - 1],
            "expected_euler_characteristic": None
            if self.expected is None
            else self.expected.euler_characteristic,
            "expected_components": None if self.expected is None else self.expected.components,
            "rows": [row.summary() for row in self.rows],
            "largest_all_correct_eps": self.largest_all_correct_eps,
            "smallest_none_correct_eps": self.smallest_none_correct_eps,
            "eps_star": [vars(mark) for mark in self.marks],
        }


def reconstruct_draws(
    shape,
    eps_values: list[float],
    quality: QualityParams,
    seed: int = 0,
    repeats: int = 8,
    options: MhatOptions = MhatOptions(),
    progress: Progress | None = None,
) -> ReconstructDraws:
    """:func:`vorobound.reports.reconstruct_sweep.sweep_row` at each ε for each of
    ``repeats`` draws (draw k with seed ``seed + k``), and every bound's ε*.

    Parameters
    ----------
    shape
        A surface of :mod:`vorobound.sampling.surfaces`.
    eps_values : list of float
        The ε of the sweep (one value: the draws at that ε).
    quality : QualityParams
        σ and δ/ε.
    seed : int
        Seed of the first draw.
    repeats : int
        Draws per ε.
    options, progress
        As for :func:`vorobound.reports.reconstruct.reconstruct_surface`.

    References
    ----------
    Section 4.1 (the sampling conditions); eq. (33)–(55) (the marked ε*).
    """
    if shape.expected_topology is None:
        raise InputError(
            f"{shape.name}: repeats counts the draws whose M̂ has the surface's topology, and "
            "this surface gives none to compare with (a mesh that is not closed); run without "
            "repeats"
        )
    counter = Counter(progress, "draws × ε values", repeats * len(eps_values))
    seeds = tuple(seed + k for k in range(repeats))
    per_eps: list[list[SweepRow]] = [[] for _ in eps_values]
    for draw_seed in seeds:
        drawn = sweep_rows(shape, eps_values, quality, draw_seed, options, progress, counter)
        for rows, row in zip(per_eps, drawn, strict=True):
            rows.append(row)
    return ReconstructDraws(
        source=shape.name,
        quality=quality,
        seed=seed,
        repeats=repeats,
        expected=shape.expected_topology,
        rows=[DrawsRow(rows[0].eps, tuple(rows), seeds) for rows in per_eps],
        marks=bound_marks(quality),
    )


def draws_csv(draws: ReconstructDraws) -> str:
    """One line per draw and ε: the seed, then the columns of sweep.csv."""
    lines = [f"seed,{','.join(SWEEP_COLUMNS)}"]
    for row in draws.rows:
        for seed, draw in zip(row.seeds, row.draws, strict=True):
            lines.append(f"{seed},{csv_line(draw)}")
    return "\n".join(lines) + "\n"


def draws_writers(draws: ReconstructDraws, out_dir: str | Path) -> dict[Path, Callable]:
    """The writer of draws.csv (summary.json and the figure join it in the API)."""
    text = draws_csv(draws)
    return {Path(out_dir) / DRAWS_CSV: lambda path: path.write_text(text, encoding="utf-8")}
