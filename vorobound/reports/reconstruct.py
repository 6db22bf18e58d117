"""VoroCrust's surface M̂ rebuilt from the seeds and measured: the workflow and its outputs.

:func:`reconstruct_surface` samples a surface (as ``vorobound sample`` does), finds the guide
triangles and their seeds, labels the seeds by the surface, builds M̂ and measures it;
:func:`reconstruct_balls` starts from someone else's balls (labels by the surface if one is
given, else by the sheets of the union's boundary) and :func:`reconstruct_seeds` from a
labelled seed file. :func:`reconstruct_sweep` repeats the first over several ε and puts every
bound's ε* beside the results. :func:`output_writers` writes a report as one set of files.

References
----------
The seeds and guide triangles of Section 4.1; the ε* of every mode and target (eq. (33)–(55)).
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from ..bounds.params import Mode, QualityParams, SamplingParams
from ..errors import NoAdmissibleEps, NoGuideTriangles
from ..progress import Counter, Progress
from ..sampling.balls import Balls, make_balls
from ..sampling.guides.triangles import Engine, equal_radii_on_sphere, find_guide_triangles
from ..sampling.reconstruct.facets import InOutFacets, PolygonSurface, inout_facets
from ..sampling.reconstruct.measure import (
    FacetQuality,
    SurfaceMeasures,
    facet_quality,
    measure_against,
)
from ..sampling.reconstruct.reference import ExpectedTopology, reference_surface
from ..sampling.reconstruct.seeds import MIN_SEEDS, Seeds, seed_table, triangle_seeds
from ..sampling.reconstruct.topology import Topology, surface_topology

QUALITY_FIGURE_STEM = "quality"
"""File name (without extension) of the figure of the facet distributions."""
SWEEP_FIGURE_STEM = "sweep"
"""File name (without extension) of the sweep's figure."""
LISTED_FACETS = 20
"""Facets that make M̂ non-manifold listed in the summary (all are marked in the VTU)."""


@dataclass(frozen=True)
class SampleInfo:
    """How the balls and their guide triangles came about, when vorobound had them."""

    balls: int
    guide_triangles: int
    half_covered: int
    engine: str


@dataclass(frozen=True)
class ReconstructReport:
    """M̂ of one seed set and everything measured on it."""

    source: str
    eps: float | None
    """ε of the sample (None for a seed file measured without a surface)."""
    params: SamplingParams | None
    seed: int | None
    sample: SampleInfo | None
    seeds: Seeds
    half_covered_seeds: bool
    """True when the uncovered seed of each half-covered triple is a seed too."""
    facets: InOutFacets
    topology: Topology
    expected: ExpectedTopology | None
    """The surface's topology (None when no surface is known, or a mesh is not closed)."""
    quality: FacetQuality
    measures: SurfaceMeasures | None
    """M̂ against the surface (None without a surface)."""
    sheet_disagreements: int | None
    """Seeds whose label from the union's sheets differs from their label by the surface
    (None: not compared, or the union's boundary is not two sheets)."""
    sheet_note: str | None = None
    """Why the sheets gave no labels, when they did not."""
    note: str | None = None
    """Why M̂ is empty, when it is."""
    timings: dict[str, float] = field(default_factory=dict)

    @property
    def topology_correct(self) -> bool:
        """M̂ is a closed 2-manifold with the surface's Euler characteristic and components
        (only the first when the surface is not known)."""
        top = self.topology
        if not top.closed_manifold:
            return False
        if self.expected is None:
            return True
        return (top.euler_characteristic, top.components) == (
            self.expected.euler_characteristic,
            self.expected.components,
        )

    def summary(self) -> dict:
        """The JSON summary (plain types; docs/reconstruct.md describes the fields)."""
        top, q, m = self.topology, self.quality, self.measures
        surface = self.facets.surface
        out = {
            "source": self.source,
            "params": None
            if self.params is None
            else {
                "eps": self.params.eps,
                "sigma": self.params.sigma,
                "delta_ratio": self.params.delta_ratio,
            },
            "eps": self.eps,
            "seed": self.seed,
            "n_samples": None if self.sample is None else self.sample.balls,
            "n_guide_triangles": None if self.sample is None else self.sample.guide_triangles,
            "n_half_covered": None if self.sample is None else self.sample.half_covered,
            "engine": None if self.sample is None else self.sample.engine,
            "n_seeds": len(self.seeds),
            "n_inside_seeds": int(self.seeds.inside.sum()),
            "labels": self.seeds.labels,
            "half_covered_seeds": self.half_covered_seeds,
            "sheet_label_disagreements": self.sheet_disagreements,
            "sheet_label_note": self.sheet_note,
            "n_facets": surface.n_facets,
            "n_vertices": top.vertices,
            "n_edges": top.edges,
            "closed_manifold": top.closed_manifold,
            "euler_characteristic": top.euler_characteristic,
            "components": top.components,
            "genus": top.genus,
            "expected_euler_characteristic": None
            if self.expected is None
            else self.expected.euler_characteristic,
            "expected_components": None if self.expected is None else self.expected.components,
            "topology_correct": self.topology_correct,
            "boundary_edges": top.boundary_edges,
            "nonmanifold_edges": top.nonmanifold_edges,
            "nonmanifold_vertices": top.nonmanifold_vertices,
            "misoriented_edges": top.misoriented_edges,
            "unbounded_facets": len(self.facets.unbounded),
            "collapsed_facets": self.facets.collapsed,
            "unresolved_facets": self.facets.unresolved,
            "non_simple_facets": self.facets.non_simple,
            "skipped_seeds": self.facets.skipped_seeds,
            "nonmanifold_facets": self._listed(top.bad_facets),
            "unbounded_seed_pairs": self.facets.unbounded[:LISTED_FACETS].tolist(),
            "edge_ratio_min": _min(q.edge_ratio),
            "edge_ratio_median": _median(q.edge_ratio),
            "min_angle_min_deg": _min(q.min_angle),
            "min_angle_median_deg": _median(q.min_angle),
        }
        if m is not None:
            out |= {
                "hausdorff_over_eps_lfs": _finite(m.hausdorff),
                "mhat_to_surface_over_eps_lfs": _finite(m.to_surface.value),
                "mhat_to_surface_where": _where(m.to_surface.where),
                "surface_to_mhat_over_eps_lfs": _finite(m.from_surface.value),
                "surface_to_mhat_where": _where(m.from_surface.where),
                "mhat_points_measured": m.points,
                "surface_probes": m.probes,
                "normal_deviation_max_deg": _max(m.normal_deviation),
                "normal_deviation_median_deg": _median(m.normal_deviation),
                "flipped_facets": int((m.normal_deviation > 90).sum()),
            }
        if self.note:
            out["note"] = self.note
        out["timings"] = {k: round(v, 3) for k, v in self.timings.items()}
        return out

    def _listed(self, facets: np.ndarray) -> list[dict]:
        surface = self.facets.surface
        shown = facets[:LISTED_FACETS]
        centroids = surface.centroids()[shown] if len(shown) else np.empty((0, 3))
        return [
            {"facet": int(f), "seeds": surface.seed_pairs[f].tolist(), "where": c.tolist()}
            for f, c in zip(shown, centroids, strict=True)
        ]


def _finite(value) -> float | None:
    value = float(value)
    return value if np.isfinite(value) else None


def _min(values) -> float | None:
    return None if len(values) == 0 else _finite(np.min(values))


def _max(values) -> float | None:
    return None if len(values) == 0 else _finite(np.max(values))


def _median(values) -> float | None:
    return None if len(values) == 0 else _finite(np.median(values))


def _where(point) -> list | None:
    return None if point is None else [float(x) for x in point]


class _Clock:
    """Wall time per stage, keyed by name."""

    def __init__(self):
        self.seconds: dict[str, float] = {}
        self._start = time.perf_counter()

    def lap(self, name: str) -> None:
        now = time.perf_counter()
        self.seconds[name] = self.seconds.get(name, 0.0) + now - self._start
        self._start = now


# --- Workflows -------------------------------------------------------------------------------


def reconstruct_surface(
    shape,
    eps: float,
    quality: QualityParams,
    seed: int = 0,
    half_covered: bool = False,
    engine: Engine | str = Engine.auto,
    compare_sheets: bool = False,
    progress: Progress | None = None,
) -> ReconstructReport:
    """Sample ``shape`` at ``eps`` (σ-sparse ε-sample, balls r = δL), take the seeds of the
    guide triangles, label them by the surface, build M̂ and measure it.

    Parameters
    ----------
    shape
        A surface of :mod:`vorobound.sampling.surfaces` (sphere, torus, mesh).
    eps : float
        Sampling density ε.
    quality : QualityParams
        σ and δ/ε (ρ_f and L_i are not used).
    seed : int
        Random seed of the sampler and of the surface probes.
    half_covered : bool
        Also use the uncovered seed of each half-covered triple.
    engine : Engine
        Source of candidate triples (as for ``vorobound check``).
    compare_sheets : bool
        Also label the seeds by the union's sheets and count the disagreements.
    progress : Progress, optional

    References
    ----------
    The sampling conditions, guide triangles and seeds of Section 4.1.
    """
    from ..sampling.sampler.maximal import sample_surface

    params = SamplingParams(eps, quality)
    clock = _Clock()
    sample = sample_surface(shape, eps, quality.sigma, seed, progress)
    balls = make_balls(sample.points, params.delta * sample.lfs, shape.name)
    clock.lap("sample")
    return _from_balls(
        balls,
        params,
        shape,
        seed,
        half_covered,
        engine,
        compare_sheets,
        clock,
        shape.name,
        progress,
    )


def reconstruct_balls(
    balls: Balls,
    params: SamplingParams | None = None,
    shape=None,
    half_covered: bool = False,
    engine: Engine | str = Engine.auto,
    source: str = "balls",
    compare_sheets: bool = False,
    progress: Progress | None = None,
) -> ReconstructReport:
    """M̂ of balls made elsewhere: seeds of their guide triangles, labelled by ``shape`` when
    given (then also measured against it at ``params.eps``), else by the union's sheets."""
    clock = _Clock()
    return _from_balls(
        balls, params, shape, 0, half_covered, engine, compare_sheets, clock, source, progress
    )


def _from_balls(
    balls, params, shape, seed, half_covered, engine, compare_sheets, clock, source, progress
) -> ReconstructReport:
    from ..sampling.reconstruct.labels import NotTwoSheets, sheet_labels

    reference = None if shape is None else reference_surface(shape)
    cospherical = bool(getattr(shape, "equal_radii_on_sphere", False)) and equal_radii_on_sphere(
        balls, shape.radius
    )
    search = find_guide_triangles(balls, engine, cospherical, progress)
    guides = len(search.guide.triples)
    if guides == 0:
        raise NoGuideTriangles(
            f"{source}: no guide triangle, so no seeds and no M̂ ({search.with_seeds:,} triples "
            f"of balls meet in a seed pair, {search.half_covered:,} of them half-covered)"
        )
    clock.lap("guide triangles")
    found = triangle_seeds(balls, search.seeded, half_covered)
    disagreements = sheet_note = None
    if reference is None:
        Counter(progress, "labels from the union's sheets", None)
        inside = sheet_labels(balls, search.seeded)[found.rows, found.side]
        labels = "sheets"
    else:
        inside, labels = reference.inside(found.points), "surface"
        if compare_sheets:
            Counter(progress, "labels from the union's sheets", None)
            try:
                by_sheets = sheet_labels(balls, search.seeded)[found.rows, found.side]
            except NotTwoSheets as exc:
                sheet_note = str(exc)
            else:
                disagreements = int((by_sheets != inside).sum())
    clock.lap("labels")
    seeds = found.labelled(inside, labels, source)
    info = SampleInfo(len(balls), guides, search.half_covered, search.engine)
    report = _finish(
        seeds, reference, params, seed, info, half_covered, disagreements, clock, source, progress
    )
    return replace(report, sheet_note=sheet_note)


def reconstruct_seeds(
    seeds: Seeds,
    shape=None,
    params: SamplingParams | None = None,
    seed: int = 0,
    progress: Progress | None = None,
) -> ReconstructReport:
    """M̂ of labelled seeds (a VoroCrust seed file), measured against ``shape`` at ``params.eps``
    when both are given."""
    reference = None if shape is None else reference_surface(shape)
    clock = _Clock()
    return _finish(seeds, reference, params, seed, None, False, None, clock, seeds.source, progress)


def _finish(
    seeds, reference, params, seed, info, half_covered, disagreements, clock, source, progress
) -> ReconstructReport:
    note = None
    if len(seeds) < MIN_SEEDS or seeds.inside.all() or not seeds.inside.any():
        note = (
            f"no M̂: {len(seeds)} seeds, {int(seeds.inside.sum())} of them inside (M̂ needs "
            f"at least {MIN_SEEDS} seeds on both sides)"
        )
        facets = _empty_facets()
    else:
        facets = inout_facets(seeds.points, seeds.inside, progress)
    clock.lap("mhat (Delaunay, facets)")
    topology = surface_topology(facets.surface, len(facets.unbounded))
    quality = facet_quality(facets.surface)
    clock.lap("topology, quality")
    measures = None
    if reference is not None and params is not None and facets.surface.n_facets:
        Counter(progress, "distances to the surface", None)
        rng = np.random.default_rng([seed or 0, 2])
        measures = measure_against(facets.surface, reference, params.eps, rng)
        clock.lap("distances")
    return ReconstructReport(
        source=source,
        eps=None if params is None else params.eps,
        params=params,
        seed=seed if info is not None else None,
        sample=info,
        seeds=seeds,
        half_covered_seeds=half_covered,
        facets=facets,
        topology=topology,
        expected=None if reference is None else reference.expected,
        quality=quality,
        measures=measures,
        sheet_disagreements=disagreements,
        note=note,
        timings=clock.seconds,
    )


def _empty_facets() -> InOutFacets:
    surface = PolygonSurface(
        np.empty((0, 3)),
        np.empty(0, dtype=np.int64),
        np.zeros(1, dtype=np.int64),
        np.empty((0, 2), dtype=np.int64),
        np.empty((0, 3)),
    )
    return InOutFacets(surface, np.empty((0, 2), dtype=np.int64), 0, 0, 0, 0, 0, 0)


# --- The ε sweep -----------------------------------------------------------------------------


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
    topology_correct: bool
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

    @classmethod
    def of(cls, report: ReconstructReport) -> SweepRow:
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
            "all_correct": all(row.topology_correct for row in self.rows),
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
                star = eps_star(quality, Mode(mode), target, lam)
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
    half_covered: bool = False,
    engine: Engine | str = Engine.auto,
    compare_sheets: bool = False,
    progress: Progress | None = None,
) -> ReconstructSweep:
    """:func:`reconstruct_surface` at each ε (a row per ε; an ε without guide triangles is a
    row without M̂), and every bound's ε* (:func:`bound_marks`)."""
    counter = Counter(progress, "ε values", len(eps_values))
    rows = []
    for eps in eps_values:
        try:
            report = reconstruct_surface(
                shape, eps, quality, seed, half_covered, engine, compare_sheets, progress
            )
        except NoGuideTriangles as exc:
            rows.append(SweepRow.failed(SamplingParams(eps, quality).eps, str(exc)))
        else:
            rows.append(SweepRow.of(report))
        counter.step()
    return ReconstructSweep(
        source=shape.name,
        quality=quality,
        seed=seed,
        expected=reference_surface(shape).expected,
        rows=rows,
        marks=bound_marks(quality),
    )


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
    lines = [",".join(SWEEP_COLUMNS)]
    for row in sweep.rows:
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
        lines.append(",".join(cells))
    return "\n".join(lines) + "\n"


def sweep_writers(sweep: ReconstructSweep, out_dir: str | Path) -> dict[Path, Callable]:
    """Writers of sweep.csv and summary.json (the figure joins them in the command line)."""
    out = Path(out_dir)
    text = sweep_csv(sweep)
    summary = json.dumps(sweep.summary(), indent=2, allow_nan=False) + "\n"
    return {
        out / "sweep.csv": lambda path: path.write_text(text, encoding="utf-8"),
        out / "summary.json": lambda path: path.write_text(summary, encoding="utf-8"),
    }


# --- Output files of one reconstruction -----------------------------------------------------


def facet_fields(report: ReconstructReport) -> dict[str, np.ndarray]:
    """Per-facet arrays of M̂ for the VTU (NaN where not measured)."""
    surface, m = report.facets.surface, report.measures
    count = surface.n_facets
    blank = np.full(count, np.nan)
    bad = np.zeros(count)
    bad[report.topology.bad_facets] = 1.0
    return {
        "facet": np.arange(count, dtype=float),
        "hausdorff_over_eps_lfs": blank if m is None else m.facet_distance,
        "normal_deviation_deg": blank if m is None else m.normal_deviation,
        "edge_ratio": report.quality.edge_ratio,
        "min_angle_deg": report.quality.min_angle,
        "area": report.quality.area,
        "nonmanifold": bad,
        "inside_seed": surface.seed_pairs[:, 0].astype(float),
        "outside_seed": surface.seed_pairs[:, 1].astype(float),
    }


def polygon_cells(surface: PolygonSurface, fields: dict[str, np.ndarray]):
    """meshio cell blocks (triangle, quad, polygon of each size) and the matching cell data."""
    sizes = surface.sizes
    cells, data = [], {name: [] for name in fields}
    for size in np.unique(sizes):
        chosen = np.flatnonzero(sizes == size)
        start = surface.offsets[chosen]
        block = surface.corners[start[:, None] + np.arange(size)].astype(np.int32)
        kind = {3: "triangle", 4: "quad"}.get(int(size), "polygon")
        cells.append((kind, block))
        for name, values in fields.items():
            data[name].append(values[chosen])
    return cells, data


def _write_mhat_vtu(path: Path, report: ReconstructReport) -> None:
    from ..sampling.io.balls import fill_vtu

    surface = report.facets.surface
    cells, data = polygon_cells(surface, facet_fields(report))
    fill_vtu(path, surface.vertices, cells, {}, data)


def _write_mhat_ply(path: Path, report: ReconstructReport) -> None:
    import meshio

    surface = report.facets.surface
    cells, _ = polygon_cells(surface, {})
    meshio.write(path, meshio.Mesh(surface.vertices, cells), file_format="ply")


def _write_seeds_vtu(path: Path, report: ReconstructReport) -> None:
    from ..sampling.io.balls import fill_vtu

    seeds = report.seeds
    cells = [("vertex", np.arange(len(seeds)).reshape(-1, 1))]
    point_data = {
        "region_id": seeds.inside.astype(float),
        "sizing": seeds.sizing,
        "triangle": seeds.triangle.astype(float),
    }
    fill_vtu(path, seeds.points, cells, point_data)


def _write_seeds_csv(path: Path, report: ReconstructReport) -> None:
    from ..sampling.io.balls import fill_csv

    names, table = seed_table(report.seeds)
    fill_csv(path, names, table)


def output_writers(report: ReconstructReport, out_dir: str | Path) -> dict[Path, Callable]:
    """Writers of mhat.vtu (ParaView; facet fields), mhat.ply, seeds.vtu (with region_id),
    seeds.csv (VoroCrust's seed format) and summary.json in ``out_dir``, for
    :func:`vorobound.files.write_set`. The quality figure (``QUALITY_FIGURE_STEM``) joins the
    set in the command line."""
    out = Path(out_dir)
    summary = json.dumps(report.summary(), indent=2, allow_nan=False) + "\n"
    writers = {
        out / "mhat.vtu": lambda path: _write_mhat_vtu(path, report),
        out / "mhat.ply": lambda path: _write_mhat_ply(path, report),
        out / "seeds.vtu": lambda path: _write_seeds_vtu(path, report),
        out / "seeds.csv": lambda path: _write_seeds_csv(path, report),
        out / "summary.json": lambda path: path.write_text(summary, encoding="utf-8"),
    }
    return writers


def quality_distributions(report: ReconstructReport) -> dict[str, np.ndarray]:
    """The per-facet arrays the quality figure shows (label ↦ values)."""
    shown = {
        "shortest / longest edge": report.quality.edge_ratio,
        "smallest angle (°)": report.quality.min_angle,
    }
    if report.measures is not None:
        shown["distance to the surface / (εL)"] = report.measures.facet_distance
        shown["normal deviation (°)"] = report.measures.normal_deviation
    return shown
