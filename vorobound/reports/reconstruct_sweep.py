"""M̂ over several ε of one surface, with every bound's ε* beside it.

References
----------
The ε* of every mode and target, eq. (33)–(55), and property H3.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from ..bounds.params import Mode, QualityParams, SamplingParams
from ..errors import NoAdmissibleEps, NoGuideTriangles
from ..progress import Counter, Progress
from ..sampling.surfaces.base import ExpectedTopology
from .reconstruct import MhatOptions, ReconstructReport, reconstruct_surface

SWEEP_FIGURE_STEM = "sweep"
"""File name (without extension) of the sweep's figure."""


@dataclass(frozen=True)
class EpsMark:
    """One bound's ε*: the largest ε at which it guarantees its target."""

    label: str
    """Mode (and λ) as printed, e.g. "tight, λ = 1"."""
    target: str
    """additive, ratio, or (55) for H3 alone."""
    eps_star: float
    claim: str


@dataclass(frozen=True)
class SweepRow:
    """What the sweep keeps of one reconstruction."""

    eps: float
    samples: int | None
    facets: int
    closed_manifold: bool
    euler_characteristic: int
    components: int
    topology_correct: bool | None
    """None: no reference surface (a mesh that is not closed)."""
    hausdorff: float | None
    """Two-sided Hausdorff distance over ε·L (measured)."""
    normal_deviation_max: float | None
    """Degrees."""
    edge_ratio_min: float | None
    min_angle_min: float | None
    """Degrees."""
    sheet_disagreements: int | None
    sheet_note: str | None = None
    note: str | None = None
    lfs_range: tuple[float, float] | None = None
    """Smallest and largest L of the sample's balls (None without M̂)."""

    @property
    def ok(self) -> bool:
        """M̂ has the surface's topology (a closed 2-manifold when there is no reference)."""
        return self.closed_manifold if self.topology_correct is None else self.topology_correct

    @classmethod
    def of(cls, report: ReconstructReport) -> SweepRow:
        assert report.eps is not None, "a sweep row is of a sampled surface, which has an ε"
        s = report.summary()
        return cls(
            eps=report.eps,
            samples=s["n_samples"],
            facets=s["n_facets"],
            closed_manifold=s["closed_manifold"],
            euler_characteristic=s["euler_characteristic"],
            components=s["components"],
            topology_correct=s["topology_correct"],
            hausdorff=s.get("hausdorff_over_eps_lfs"),
            normal_deviation_max=s.get("normal_deviation_max_deg"),
            edge_ratio_min=s["edge_ratio_min"],
            min_angle_min=s["min_angle_min_deg"],
            sheet_disagreements=s["sheet_label_disagreements"],
            sheet_note=s["sheet_label_note"],
            note=s.get("note"),
            lfs_range=None if report.sample is None else report.sample.lfs_range,
        )

    @classmethod
    def failed(cls, eps: float, note: str) -> SweepRow:
        """A row without M̂ (no guide triangle at this ε)."""
        return cls(eps, None, 0, False, 0, 0, False, None, None, None, None, None, None, note)


@dataclass(frozen=True)
class ReconstructSweep:
    """M̂ over several ε of one surface, and every bound's ε*."""

    source: str
    quality: QualityParams
    seed: int
    expected: ExpectedTopology | None
    rows: list[SweepRow]
    marks: list[EpsMark]

    def summary(self) -> dict:
        return {
            "source": self.source,
            "params": {"sigma": self.quality.sigma, "delta_ratio": self.quality.delta_ratio},
            "seed": self.seed,
            "expected_euler_characteristic": None
            if self.expected is None
            else self.expected.euler_characteristic,
            "expected_components": None if self.expected is None else self.expected.components,
            "rows": [vars(row) for row in self.rows],
            "eps_star": [vars(mark) for mark in self.marks],
            "all_correct": all(row.ok for row in self.rows),
        }


MARKED_MODES = (
    ("paper", None, "paper"),
    ("rigorous", None, "rigorous"),
    ("tight", None, "tight"),
    ("tight", 1.0, "tight, λ = 1"),
)
"""(mode, λ, label) of the bounds whose ε* the sweep marks, for each target."""


def bound_marks(quality: QualityParams) -> list[EpsMark]:
    """ε* of every mode for both targets (R − R̂ ≤ (ρ_f − 1)δL_i and R ≤ ρ_f·R̂, eq. (54)),
    and the ε up to which H3 alone gives (55); bounds without an ε* are left out.

    References
    ----------
    Eq. (33)–(55), property H3.
    """
    from ..bounds.guarantee import eps_star
    from ..bounds.targets import Target, h3_route

    marks = []
    for target in (Target.additive, Target.ratio):
        for mode, lam, label in MARKED_MODES:
            try:
                star = eps_star(quality.but(target=target, lipschitz=lam), Mode(mode))
            except NoAdmissibleEps:
                continue
            marks.append(EpsMark(label, target.value, star.eps_star, star.claim))
    try:
        route = h3_route(quality)
        marks.append(EpsMark("H3 alone", "(55)", route.eps_star, "given H3"))
    except NoAdmissibleEps:
        pass
    return marks


def reconstruct_sweep(
    shape,
    eps_values: list[float],
    quality: QualityParams,
    seed: int = 0,
    options: MhatOptions = MhatOptions(),
    progress: Progress | None = None,
) -> ReconstructSweep:
    """:func:`reconstruct_surface` at each ε (a row per ε; an ε without guide triangles is a
    row without M̂), and every bound's ε* (:func:`bound_marks`)."""
    counter = Counter(progress, "ε values", len(eps_values))
    rows = sweep_rows(shape, eps_values, quality, seed, options, progress, counter)
    return ReconstructSweep(
        source=shape.name,
        quality=quality,
        seed=seed,
        expected=shape.expected_topology,
        rows=rows,
        marks=bound_marks(quality),
    )


def sweep_rows(
    shape,
    eps_values: list[float],
    quality: QualityParams,
    seed: int,
    options: MhatOptions,
    progress: Progress | None,
    counter: Counter,
) -> list[SweepRow]:
    """:func:`sweep_row` at each ε with one seed, a step of ``counter`` each."""
    rows = []
    for eps in eps_values:
        rows.append(sweep_row(shape, eps, quality, seed, options, progress))
        counter.step()
    return rows


def sweep_row(
    shape,
    eps: float,
    quality: QualityParams,
    seed: int = 0,
    options: MhatOptions = MhatOptions(),
    progress: Progress | None = None,
) -> SweepRow:
    """What a sweep keeps of :func:`reconstruct_surface` at one ε and seed (a row without M̂
    when there is no guide triangle)."""
    try:
        report = reconstruct_surface(shape, eps, quality, seed, options, progress)
    except NoGuideTriangles as exc:
        return SweepRow.failed(SamplingParams(eps, quality).eps, str(exc))
    return SweepRow.of(report)


SWEEP_COLUMNS = (
    "eps",
    "samples",
    "facets",
    "closed_manifold",
    "euler_characteristic",
    "components",
    "topology_correct",
    "hausdorff",
    "normal_deviation_max",
    "edge_ratio_min",
    "min_angle_min",
    "sheet_disagreements",
    "sheet_note",
    "note",
)
"""Columns of sweep.csv."""


def sweep_csv(sweep: ReconstructSweep) -> str:
    """The sweep's rows as CSV text (empty cells where a value is missing)."""
    lines = [",".join(SWEEP_COLUMNS)] + [csv_line(row) for row in sweep.rows]
    return "\n".join(lines) + "\n"


def csv_line(row: SweepRow) -> str:
    """One row's cells of sweep.csv, comma-separated (empty where a value is missing)."""
    cells = []
    for name in SWEEP_COLUMNS:
        value = getattr(row, name)
        if value is None:
            cells.append("")
        elif isinstance(value, bool):
            cells.append(str(int(value)))
        elif isinstance(value, float):
            cells.append(repr(value))
        elif isinstance(value, str):
            cells.append('"' + value.replace('"', "'") + '"')
        else:
            cells.append(str(value))
    return ",".join(cells)


def sweep_writers(sweep: ReconstructSweep, out_dir: str | Path) -> dict[Path, Callable]:
    """Writers of sweep.csv and summary.json (the figure joins them in the command line)."""
    out = Path(out_dir)
    text = sweep_csv(sweep)
    return {
        out / "sweep.csv": lambda path: path.write_text(text, encoding="utf-8"),
    }
