"""VoroCrust's surface M̂ rebuilt from the seeds and measured: the workflow and its outputs.

:func:`reconstruct_surface` samples a surface (as ``vorobound sample`` does), finds the guide
triangles and their seeds, labels the seeds by the surface, builds M̂ and measures it;
:func:`reconstruct_balls` starts from someone else's balls (labels by the surface if one is
given, else by the sheets of the union's boundary) and :func:`reconstruct_seeds` from a
labelled seed file. The ε sweep is in :mod:`vorobound.reports.reconstruct_sweep`, the output
files in :mod:`vorobound.reports.reconstruct_files`.

References
----------
The seeds and guide triangles of Section 4.1; the ε* of every mode and target (eq. (33)–(55)).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace

import numpy as np

from ..bounds.params import QualityParams, SamplingParams
from ..errors import NoGuideTriangles
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
from ..sampling.reconstruct.seeds import MIN_SEEDS, Seeds, triangle_seeds
from ..sampling.reconstruct.topology import Topology, surface_topology
from ..sampling.surfaces.base import ExpectedTopology

LISTED_FACETS = 20
"""Facets that make M̂ non-manifold listed in the summary (all are marked in the VTU)."""


@dataclass(frozen=True)
class SampleInfo:
    """How the balls and their guide triangles came about, when vorobound had them."""

    balls: int
    guide_triangles: int
    half_covered: int
    engine: str
    lfs_range: tuple[float, float] | None = None
    """Smallest and largest L = r/δ of the balls (None without sampling parameters)."""


@dataclass(frozen=True)
class MhatOptions:
    """How M̂ is built from the balls, whatever their source (``vorobound reconstruct``'s
    --half-covered, --engine, --compare-sheets and --slabs)."""

    half_covered: bool = False
    """Also use the uncovered seed of each half-covered triple."""
    engine: Engine | str = Engine.auto
    """Source of candidate triples (as for ``vorobound check``)."""
    compare_sheets: bool = False
    """Also label the seeds by the union's sheets and count the disagreements."""
    slabs: int | None = None
    """Triangulate the seeds in this many overlapping slabs (1: all at once; None: by their
    count, :func:`vorobound.sampling.reconstruct.slabs.slab_count`)."""


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
    def topology_correct(self) -> bool | None:
        """M̂ is a closed 2-manifold with the surface's Euler characteristic and components,
        built from every seed (a seed left out of the triangulation, other than an exact copy,
        misses its facets: False); None when there is no reference surface to compare with
        (no surface given, or a mesh that is not closed)."""
        if self.facets.skipped_seeds:
            return False
        if self.expected is None:
            return None
        top = self.topology
        return top.closed_manifold and (top.euler_characteristic, top.components) == (
            self.expected.euler_characteristic,
            self.expected.components,
        )

    @property
    def ok(self) -> bool:
        """M̂ has the surface's topology; without a reference surface, M̂ is a closed
        2-manifold (all that can be checked)."""
        correct = self.topology_correct
        return self.topology.closed_manifold if correct is None else correct

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
            "duplicate_seeds": self.facets.duplicate_seeds,
            "slabs": self.facets.slabs,
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
    options: MhatOptions = MhatOptions(),
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
    options : MhatOptions
        Which seeds, which engine, whether to compare the sheets' labels.
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
    return _from_balls(balls, params, shape, seed, options, clock, shape.name, progress)


def reconstruct_balls(
    balls: Balls,
    params: SamplingParams | None = None,
    shape=None,
    half_covered: bool = False,
    engine: Engine | str = Engine.auto,
    source: str = "balls",
    compare_sheets: bool = False,
    progress: Progress | None = None,
    slabs: int | None = None,
) -> ReconstructReport:
    """M̂ of balls made elsewhere: seeds of their guide triangles, labelled by ``shape`` when
    given (then also measured against it at ``params.eps``), else by the union's sheets
    (``slabs``: as :class:`MhatOptions`)."""
    options = MhatOptions(half_covered, engine, compare_sheets, slabs)
    return _from_balls(
        balls, params, shape, 0, options, clock=_Clock(), source=source, progress=progress
    )


def _from_balls(
    balls, params, shape, seed, options: MhatOptions, clock, source, progress
) -> ReconstructReport:
    from ..sampling.reconstruct.labels import NotTwoSheets, sheet_labels

    cospherical = bool(getattr(shape, "equal_radii_on_sphere", False)) and equal_radii_on_sphere(
        balls, shape.radius
    )
    search = find_guide_triangles(balls, options.engine, cospherical, progress)
    guides = len(search.guide.triples)
    if guides == 0:
        raise NoGuideTriangles(
            f"{source}: no guide triangle, so no seeds and no M̂ ({search.with_seeds:,} triples "
            f"of balls meet in a seed pair, {search.half_covered:,} of them half-covered)"
        )
    clock.lap("guide triangles")
    found = triangle_seeds(balls, search.seeded, options.half_covered)
    disagreements = sheet_note = None
    if shape is None:
        Counter(progress, "labels from the union's sheets", None)
        inside = sheet_labels(balls, search.seeded)[found.rows, found.side]
        labels = "sheets"
    else:
        inside, labels = shape.inside(found.points), "surface"
        if options.compare_sheets:
            Counter(progress, "labels from the union's sheets", None)
            try:
                by_sheets = sheet_labels(balls, search.seeded)[found.rows, found.side]
            except NotTwoSheets as exc:
                sheet_note = str(exc)
            else:
                disagreements = int((by_sheets != inside).sum())
    clock.lap("labels")
    seeds = found.labelled(inside, labels, source)
    lfs_range = None
    if params is not None and len(balls.radii):
        lfs_range = (
            float(balls.radii.min()) / params.delta,
            float(balls.radii.max()) / params.delta,
        )
    info = SampleInfo(len(balls), guides, search.half_covered, search.engine, lfs_range)
    del search, found, inside  # the guide triangles are not needed for M̂ (memory)
    report = _finish(
        seeds,
        shape,
        params,
        seed,
        info,
        options.half_covered,
        disagreements,
        clock,
        source,
        progress,
        options.slabs,
    )
    return replace(report, sheet_note=sheet_note)


def reconstruct_seeds(
    seeds: Seeds,
    shape=None,
    params: SamplingParams | None = None,
    seed: int = 0,
    progress: Progress | None = None,
    slabs: int | None = None,
) -> ReconstructReport:
    """M̂ of labelled seeds (a VoroCrust seed file), measured against ``shape`` at ``params.eps``
    when both are given (``slabs``: as :class:`MhatOptions`)."""
    clock = _Clock()
    return _finish(
        seeds, shape, params, seed, None, False, None, clock, seeds.source, progress, slabs
    )


def _finish(
    seeds, shape, params, seed, info, half_covered, disagreements, clock, source, progress, slabs
) -> ReconstructReport:
    note = None
    if len(seeds) < MIN_SEEDS or seeds.inside.all() or not seeds.inside.any():
        note = (
            f"no M̂: {len(seeds)} seeds, {int(seeds.inside.sum())} of them inside (M̂ needs "
            f"at least {MIN_SEEDS} seeds on both sides)"
        )
        facets = _empty_facets()
    else:
        facets = inout_facets(seeds.points, seeds.inside, progress, slabs=slabs)
    clock.lap("mhat (Delaunay, facets)")
    topology = surface_topology(facets.surface, len(facets.unbounded))
    quality = facet_quality(facets.surface)
    clock.lap("topology, quality")
    measures = None
    if shape is not None and params is not None and facets.surface.n_facets:
        Counter(progress, "distances to the surface", None)
        rng = np.random.default_rng([seed or 0, 2])
        measures = measure_against(facets.surface, shape, params.eps, rng)
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
        expected=None if shape is None else shape.expected_topology,
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
