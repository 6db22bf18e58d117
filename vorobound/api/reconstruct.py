"""``vorobound reconstruct``: VoroCrust's surface M̂ built from the seeds and measured, at one ε
or over an ε sweep."""

from __future__ import annotations

import dataclasses
import json
import os
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from numbers import Number
from typing import TYPE_CHECKING, Any

from ..bounds.params import QualityParams
from ..checks import parse_values
from ..constants import PAPER_DELTA_RATIO, PAPER_SIGMA
from ..errors import InputError
from ..progress import Progress
from .arguments import checked_arguments
from .result import Result, checked_outputs, frame, params_json, sample_lfs

if TYPE_CHECKING:
    from ..mesh import TriangleMesh
    from ..reports.reconstruct import ReconstructReport
    from ..reports.reconstruct_draws import ReconstructDraws
    from ..reports.reconstruct_sweep import ReconstructSweep
    from .reconstruct_summary import ReconstructSummary

REPEATS_MAX = 10_000
"""Most draws per ε (``repeats``)."""
SLABS_MAX = 10_000
"""Most slabs M̂'s triangulation may be cut into (``slabs``)."""


@dataclass(frozen=True, repr=False)
class ReconstructResult(Result):
    """M̂ of one seed set: its topology against the surface's, and how close and how well
    shaped it is."""

    command = "reconstruct"
    source: str
    closed_manifold: bool
    euler_characteristic: int
    n_facets: int
    topology_correct: bool | None
    """A closed 2-manifold with the surface's Euler characteristic and components (None: no
    reference surface to compare with)."""
    hausdorff_over_eps_lfs: float | None
    """Largest two-sided distance between M̂ and the surface over ε·L (None: no surface)."""
    normal_deviation_max_deg: float | None
    report: ReconstructReport = field(repr=False)
    written: tuple[str, ...] = field(repr=False, default=())
    quality: QualityParams | None = field(repr=False, default=None)
    asked: dict = field(repr=False, default_factory=dict)
    extra: dict = field(repr=False, default_factory=dict)
    """More of the JSON (a VoroCrust run: the unit of the distances)."""

    @property
    def ok(self) -> bool:
        return self.report.ok

    @property
    def verdict(self) -> str:
        skipped = self.report.facets.skipped_seeds
        if skipped:
            return f"{skipped} seeds were left out of the triangulation: M̂ misses their facets"
        if not self.closed_manifold:
            return "M̂ is not a closed 2-manifold (see the boundary and non-manifold counts)"
        return f"M̂ has the wrong topology (Euler characteristic {self.euler_characteristic})"

    @property
    def summary(self) -> ReconstructSummary:
        """M̂ as typed fields (the numbers of :meth:`to_dict`)."""
        from .reconstruct_summary import ReconstructSummary

        return ReconstructSummary.of(self.to_dict())

    def payload(self) -> dict:
        summary = self.report.summary()
        eps = summary.pop("eps")
        summary.pop("seed", None)
        summary["params"] = _mhat_params(self.quality, eps, self.asked)
        info = self.report.sample
        if info is not None and info.lfs_range is not None:
            summary |= sample_lfs(summary["params"], info.lfs_range)
        else:  # seeds alone: no ball radius, so no L of the balls
            summary["params"]["lfs"] = None
        return summary | self.extra | {"ok": self.ok, "written": list(self.written)}


def _mhat_params(quality: QualityParams | None, eps, asked: dict) -> dict:
    """The ``params`` object of M̂'s JSON (:func:`~vorobound.api.result.params_json` without
    ρ_f, λ and the target, which M̂ does not use)."""
    params = params_json(quality, eps, **asked)
    for key in ("rho_f", "lipschitz", "target"):
        params.pop(key, None)
    return params


def _rows_lfs(params: dict, rows) -> dict:
    """``params["lfs"]`` and the L range over the balls of every row with M̂
    (:func:`~vorobound.api.result.sample_lfs`)."""
    ends = [end for row in rows if row.lfs_range is not None for end in row.lfs_range]
    return sample_lfs(params, ends)


@dataclass(frozen=True, repr=False)
class ReconstructSweepResult(Result):
    """M̂ over several ε of one surface, beside every bound's ε*."""

    command = "reconstruct"
    source: str
    n_eps: int
    all_correct: bool
    largest_correct_eps: float | None
    """The largest ε of the sweep at which M̂ had the surface's topology."""
    sweep: ReconstructSweep = field(repr=False)
    """:class:`vorobound.reports.reconstruct_sweep.ReconstructSweep`."""
    written: tuple[str, ...] = field(repr=False, default=())
    asked: dict = field(repr=False, default_factory=dict)

    @property
    def ok(self) -> bool:
        return self.all_correct

    @property
    def verdict(self) -> str:
        wrong = [r.eps for r in self.sweep.rows if not r.ok]
        return f"M̂ is wrong at {len(wrong)} of {self.n_eps} eps values (first {wrong[0]:g})"

    def payload(self) -> dict:
        summary = self.sweep.summary()
        summary.pop("seed", None)
        params = _mhat_params(self.sweep.quality, [r.eps for r in self.sweep.rows], self.asked)
        summary["params"] = params
        summary |= _rows_lfs(params, self.sweep.rows)
        return summary | {"ok": self.ok, "written": list(self.written)}

    def to_frame(self):
        """One row per ε (pandas optional)."""
        return frame([vars(row) for row in self.sweep.rows])


@dataclass(frozen=True, repr=False)
class ReconstructDrawsResult(Result):
    """M̂ of one surface over ``repeats`` draws of the sampler at each ε: the share of draws
    with the right topology, the spread of the measurements, and the transition band."""

    command = "reconstruct"
    source: str
    repeats: int
    n_eps: int
    share_correct: float | None
    """Fraction of the draws whose M̂ has the surface's topology (one ε; None for a sweep,
    whose rows carry it per ε)."""
    largest_all_correct_eps: float | None
    """The largest ε at which every draw gave the right M̂ (None: no such ε)."""
    smallest_none_correct_eps: float | None
    """The smallest ε at which no draw gave the right M̂ (None: no such ε)."""
    draws: ReconstructDraws = field(repr=False)
    """:class:`vorobound.reports.reconstruct_draws.ReconstructDraws`."""
    written: tuple[str, ...] = field(repr=False, default=())
    asked: dict = field(repr=False, default_factory=dict)

    @property
    def ok(self) -> bool:
        return all(r.correct == len(r.draws) for r in self.draws.rows)

    @property
    def verdict(self) -> str:
        rows = self.draws.rows
        wrong = sum(len(r.draws) - r.correct for r in rows)
        first = next(r.eps for r in rows if r.correct < len(r.draws))
        return (
            f"M̂ is wrong in {wrong} of {self.repeats * self.n_eps} draws (first at ε = {first:g})"
        )

    def payload(self) -> dict:
        summary = self.draws.summary()
        eps = [r.eps for r in self.draws.rows]
        params = _mhat_params(self.draws.quality, eps[0] if len(eps) == 1 else eps, self.asked)
        summary["params"] = params
        summary |= _rows_lfs(params, [row for r in self.draws.rows for row in r.draws])
        if self.share_correct is not None:
            summary["share_correct"] = self.share_correct
        return summary | {"ok": self.ok, "written": list(self.written)}

    def to_frame(self):
        """One row per draw and ε (pandas optional)."""
        return frame(
            [
                {"seed": seed} | vars(draw)
                for row in self.draws.rows
                for seed, draw in zip(row.seeds, row.draws, strict=True)
            ]
        )


def _eps_values(eps) -> list[Any] | None:
    if eps is None:
        return None
    if isinstance(eps, str):
        return parse_values(eps, "eps")  # as --eps takes it: "start:stop:num" or a comma list
    if isinstance(eps, Number) or getattr(eps, "ndim", None) == 0:
        return [eps]
    if not isinstance(eps, Iterable):
        return [eps]  # for the check of eps to refuse
    values = list(eps)
    if not values:
        raise InputError("eps: give at least one value")
    return values


@checked_arguments
def reconstruct(
    *,
    eps: float | Sequence[float] | None = None,
    sphere: float | None = None,
    torus: Sequence[float] | None = None,
    mesh: str | os.PathLike | TriangleMesh | None = None,
    lfs: float | None = None,
    sizing: str | os.PathLike | None = None,
    balls: str | os.PathLike | None = None,
    seeds: str | os.PathLike | None = None,
    vorocrust: str | os.PathLike | None = None,
    half_covered: bool = False,
    compare_sheets: bool = False,
    sigma: float = PAPER_SIGMA,
    delta_ratio: float = PAPER_DELTA_RATIO,
    seed: int = 0,
    repeats: int | None = None,
    engine: str = "auto",
    slabs: int | None = None,
    out: str | os.PathLike | None = None,
    figure_format: str = "png",
    progress: Progress | None = None,
) -> ReconstructResult | ReconstructSweepResult | ReconstructDrawsResult:
    """Build VoroCrust's surface M̂ (the Voronoi facets between inside and outside seeds) and
    measure it.

    Seeds are both seeds of every guide triangle of a sample (``sphere``, ``torus`` or ``mesh``
    with ``eps``), of ``balls``, or read from ``seeds`` (VoroCrust's CSV: x, y, z, sizing,
    region id, 0 outside and 1 inside). Several ``eps`` values reconstruct a sampled surface at
    each and return a :class:`ReconstructSweepResult` beside every bound's ε*. Measured:
    whether M̂ is a closed 2-manifold, its components, Euler characteristic and genus against
    the surface's, the two-sided Hausdorff distance to the surface over ε·L, the facet
    normals' deviation and the facets' quality. ``ok`` is True when M̂ is a closed manifold
    with the surface's topology (at every ε of a sweep); without a reference surface
    ``topology_correct`` is None and ``ok`` says whether M̂ is a closed 2-manifold.

    ``repeats`` (K ≥ 1) samples the surface K times at each ε (draw k with seed
    ``seed + k``) and returns a :class:`ReconstructDrawsResult`: per ε the share of draws whose
    M̂ has the surface's topology (``share_correct``) and the median and largest Hausdorff
    distance and normal deviation over the draws, and the transition band (the largest ε at
    which every draw was right, the smallest at which none was); ``ok`` when every draw was
    right.

    ``slabs`` (N ≥ 1): triangulate the seeds in N overlapping slabs, one at a time (memory
    bounded by a slab, the same M̂, certified complete; the whole set where a check fails);
    1 the whole set at once; None (default) one slab per 400,000 seeds above 1,500,000 seeds.

    ``out``: mhat.vtu, mhat.ply, seeds.vtu, seeds.csv, summary.json and the quality figure (a
    sweep: sweep.csv, summary.json and its figure; repeated draws: draws.csv, summary.json and,
    over several ε, the sweep figure with the share of right draws), written as one set.

    References
    ----------
    Theorem 1 (the seeds of a guide triangle), Section 4.1 (VoroCrust's sampling conditions).
    """
    from ..checks import SEED_MAX, checked_count, checked_seed
    from ..reports.reconstruct import MhatOptions
    from .surfaces import Surface

    checked_outputs(out, figure_format)
    if vorocrust is not None:
        return _vorocrust(
            vorocrust,
            dict(sphere=sphere, torus=torus, mesh=mesh, lfs=lfs, sizing=sizing),
            eps is None and balls is None and seeds is None and not half_covered and not slabs,
            compare_sheets,
            seed,
            out,
            figure_format,
            progress,
        )
    if balls is not None and seeds is not None:
        raise InputError("give balls or seeds, not both")
    seed = checked_seed(seed)
    if repeats is not None:
        repeats = checked_count(repeats, "repeats", 1, REPEATS_MAX)
    if slabs is not None:
        slabs = checked_count(slabs, "slabs", 1, SLABS_MAX)
    quality = QualityParams(sigma, delta_ratio)
    values = _eps_values(eps)
    sampled = balls is None and seeds is None
    if sampled and values is None:
        raise InputError("give eps (a sample of the surface needs it)")
    if repeats is not None and not sampled:
        raise InputError("repeats draws new samples of a surface: give no balls or seeds")
    if repeats is not None and seed + repeats - 1 > SEED_MAX:
        raise InputError(f"seed + repeats - 1 must be at most {SEED_MAX} (draw k has seed + k)")
    if values is not None and len(values) > 1 and not sampled:
        raise InputError("an eps sweep samples a surface: several eps go without balls/seeds")
    shape = Surface(sphere, torus, mesh, lfs, sizing).shape(
        required=sampled, instead=("balls FILE", "seeds FILE"), progress=progress
    )
    if shape is not None and not sampled and values is None:
        raise InputError("give eps to measure against the surface (distances over ε·L)")
    asked = {"seed": seed if sampled else None, "engine": engine, "slabs": slabs}
    options = MhatOptions(half_covered, engine, compare_sheets, slabs)
    if repeats is not None:
        asked |= {"repeats": repeats}
        draws = _draws(shape, values, quality, seed, repeats, options, asked, progress)
        return _saved(draws, out, figure_format)
    if values is not None and len(values) > 1:
        sweep = _sweep(shape, values, quality, seed, options, asked, progress)
        return _saved(sweep, out, figure_format)
    params = None if values is None else quality.at(values[0])
    report = _one(shape, params, quality, seed, balls, seeds, options, progress)
    return _saved(_result(report, quality, asked), out, figure_format)


def _result(report: ReconstructReport, quality, asked: dict, extra=None) -> ReconstructResult:
    """The result of one reconstruction."""
    top = report.topology
    measures = report.summary()
    return ReconstructResult(
        source=report.source,
        closed_manifold=top.closed_manifold,
        euler_characteristic=top.euler_characteristic,
        n_facets=report.facets.surface.n_facets,
        topology_correct=report.topology_correct,
        hausdorff_over_eps_lfs=measures.get("hausdorff_over_eps_lfs"),
        normal_deviation_max_deg=measures.get("normal_deviation_max_deg"),
        report=report,
        quality=quality,
        asked=asked,
        extra=extra or {},
    )


def _vorocrust(vorocrust, surface, alone, compare, seed, out, figure_format, progress):
    """M̂ of a VoroCrust run's seeds against its mesh, distances over the local ball radius."""
    from ..checks import checked_seed
    from .vorocrust import DISTANCE_UNIT, reconstruct_run

    if not alone or compare:
        raise InputError(
            "vorocrust reads the run's seeds.csv: eps, balls, seeds, half_covered, slabs "
            "and compare_sheets do not go with it"
        )
    report = reconstruct_run(
        vorocrust=vorocrust, surface=surface, seed=checked_seed(seed), progress=progress
    )
    asked = {"seed": None, "engine": None, "vorocrust": os.fspath(vorocrust)}
    result = _result(report, None, asked, {"distance_unit": DISTANCE_UNIT})
    return _saved(result, out, figure_format)


def _one(shape, params, quality, seed, balls, seeds, options, progress):
    """The report of one reconstruction, from a sample, balls or seeds."""
    from ..reports import reconstruct as workflow

    if seeds is not None:
        from ..sampling.reconstruct.seeds import read_seed_file

        if options.half_covered or options.compare_sheets:
            raise InputError("half_covered and compare_sheets need balls, not seeds")
        return workflow.reconstruct_seeds(
            read_seed_file(seeds), shape, params, seed, progress, options.slabs
        )
    if balls is not None:
        from ..reports.vorocrust import off_surface, warn_off_surface
        from ..sampling.io.balls import read_balls

        given = read_balls(balls)
        if shape is not None:
            warn_off_surface(off_surface(given, shape), given, os.path.basename(os.fspath(balls)))
        return workflow.reconstruct_balls(
            given,
            params,
            shape,
            options.half_covered,
            options.engine,
            os.path.basename(os.fspath(balls)),
            options.compare_sheets,
            progress,
            options.slabs,
        )
    return workflow.reconstruct_surface(shape, params.eps, quality, seed, options, progress)


def _saved(result, out, figure_format: str):
    """``result`` with its output set written into ``out`` (as it is without ``out``)."""
    from ..files import ensure_folder

    if out is None:
        return result
    folder = ensure_folder(out)
    if isinstance(result, ReconstructSweepResult):
        return _write_sweep(result, folder, figure_format)
    if isinstance(result, ReconstructDrawsResult):
        return _write_draws(result, folder, figure_format)
    return _write_outputs(result, folder, figure_format)


def _write_outputs(result: ReconstructResult, folder, figure_format: str) -> ReconstructResult:
    """M̂ (VTU, PLY), the seeds (VTU, CSV), summary.json (the result's JSON) and the quality
    figure, written as one set."""
    from ..files import write_set
    from ..plotting import figure_writer, plot_reconstruct_quality
    from ..reports.reconstruct_files import (
        QUALITY_FIGURE_STEM,
        output_writers,
        quality_distributions,
    )

    report = result.report
    writers = output_writers(report, folder)
    figure = plot_reconstruct_quality(quality_distributions(report), f"M̂ of {report.source}")
    writers[folder / f"{QUALITY_FIGURE_STEM}.{figure_format}"] = figure_writer(
        figure, figure_format
    )
    result = dataclasses.replace(result, written=tuple(os.fspath(p) for p in writers))
    _summary_writer(writers, folder, result)
    write_set(writers)
    return result


def _summary_writer(writers: dict, folder, result: Result) -> None:
    text = json.dumps(result.to_dict(), indent=2, allow_nan=False) + "\n"
    writers[folder / "summary.json"] = lambda path: path.write_text(text, encoding="utf-8")


def _sweep(shape, values, quality, seed, options, asked, progress) -> ReconstructSweepResult:
    from ..reports.reconstruct_sweep import reconstruct_sweep

    sweep = reconstruct_sweep(shape, values, quality, seed, options, progress)
    correct = [r.eps for r in sweep.rows if r.ok]
    return ReconstructSweepResult(
        source=sweep.source,
        n_eps=len(sweep.rows),
        all_correct=all(r.ok for r in sweep.rows),
        largest_correct_eps=max(correct) if correct else None,
        sweep=sweep,
        asked=asked,
    )


def _write_sweep(result: ReconstructSweepResult, folder, figure_format: str):
    from ..plotting import plot_reconstruct_sweep
    from ..reports.reconstruct_sweep import sweep_writers

    sweep = result.sweep
    rows = sweep.rows
    panels = {
        "Hausdorff / (εL)": [r.hausdorff for r in rows],
        "max normal dev. (°)": [r.normal_deviation_max for r in rows],
        "min angle (°)": [r.min_angle_min for r in rows],
    }
    figure = plot_reconstruct_sweep(
        [r.eps for r in rows],
        panels,
        [r.ok for r in rows],
        _marks(sweep.marks),
        f"M̂ of {sweep.source}",
    )
    return _written(result, folder, sweep_writers(sweep, folder), figure, figure_format)


def _marks(marks) -> list[tuple]:
    """Every bound's ε* as the figures mark it: (label, target, ε*)."""
    return [(m.label, m.target, m.eps_star) for m in marks]


def _written(result, folder, writers: dict, figure, figure_format: str):
    """``result`` with its files (the rows, the figure if any, summary.json) written as one
    set."""
    from ..files import write_set
    from ..plotting import figure_writer
    from ..reports.reconstruct_sweep import SWEEP_FIGURE_STEM

    if figure is not None:
        stem = folder / f"{SWEEP_FIGURE_STEM}.{figure_format}"
        writers[stem] = figure_writer(figure, figure_format)
    result = dataclasses.replace(result, written=tuple(os.fspath(p) for p in writers))
    _summary_writer(writers, folder, result)
    write_set(writers)
    return result


def _draws(
    shape, values, quality, seed, repeats, options, asked, progress
) -> ReconstructDrawsResult:
    from ..reports.reconstruct_draws import reconstruct_draws

    draws = reconstruct_draws(shape, values, quality, seed, repeats, options, progress)
    return ReconstructDrawsResult(
        source=draws.source,
        repeats=repeats,
        n_eps=len(draws.rows),
        share_correct=draws.rows[0].share_correct if len(draws.rows) == 1 else None,
        largest_all_correct_eps=draws.largest_all_correct_eps,
        smallest_none_correct_eps=draws.smallest_none_correct_eps,
        draws=draws,
        asked=asked,
    )


def _write_draws(result: ReconstructDrawsResult, folder, figure_format: str):
    from ..plotting import plot_reconstruct_draws
    from ..reports.reconstruct_draws import draws_writers

    draws = result.draws
    rows = draws.rows
    figure = None
    if len(rows) > 1:
        spreads = {
            "Hausdorff / (εL)": [r.hausdorff for r in rows],
            "max normal dev. (°)": [r.normal_deviation_max for r in rows],
        }
        figure = plot_reconstruct_draws(
            [r.eps for r in rows],
            [r.share_correct for r in rows],
            {label: ([s.median for s in v], [s.max for s in v]) for label, v in spreads.items()},
            (draws.largest_all_correct_eps, draws.smallest_none_correct_eps),
            _marks(draws.marks),
            f"M̂ of {draws.source}, {draws.repeats} draws per ε",
        )
    return _written(result, folder, draws_writers(draws, folder), figure, figure_format)
