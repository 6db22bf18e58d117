"""Mergeable summaries of a check: what each tile sends back instead of its rows.

A :class:`GuideTally` holds, for a set of guide triangles, the counts, the maxima (with the
triangle where each occurs) and a histogram of the gap on fixed bins; a :class:`PairTally` the
extreme, the count and the worst pairs of a pair condition (sparsity, Lipschitz). Tallies of
disjoint sets merge into the tally of their union, so a tiled check assembles the same numbers
as one tally of all rows at once (maxima keep NaN: a NaN anywhere makes the maximum NaN,
reported as null); a whole check's summary is built from such a tally too.

References
----------
Theorem 1, eq. (29), (33)–(36), (54)–(55) and property H3 of Section 4.1.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..bounds.params import SamplingParams
from ..sampling.guides.measure import GuideMeasurements
from ..sampling.sampler import conditions

MAXIMA = ("rho", "quality_ratio", "h3_ratio", "gap_ratio", "orthoradius_sq")
"""Per-triangle quantities whose maximum a tally keeps (orthoradius_sq over (δL_i)²)."""
H3_RTOL = 1e-9
"""A guide triangle breaks H3 when R(1−ε)/(εL_i) > 1 + H3_RTOL (rounding of R)."""
CLASSES = ("smooth", "at_features")
"""Where a guide triangle sits (:mod:`vorobound.sampling.guides.features`)."""
HISTOGRAM_BINS = 1200
"""Fixed bins of the gap ratio (R − R̂)/(εL_i) between 0 and :func:`gap_edges`' top."""


def gap_edges(params: SamplingParams, bound_ratios: list[float]) -> np.ndarray:
    """Bin edges of the gap histogram, fixed before any triangle is seen: from 0 to 1.05 times
    the larger of 1/(1 − ε) (the gap of a triangle meeting H3: R − R̂ ≤ R ≤ εL_i/(1 − ε)) and
    every finite bound. A tally counts values below and above them apart."""
    finite = [b for b in bound_ratios if np.isfinite(b)]
    top = 1.05 * max([1 / (1 - params.eps), *finite])
    return np.linspace(0.0, top, HISTOGRAM_BINS + 1)


@dataclass(frozen=True)
class Where:
    """The triangle (ball indices A, B, C) at which a maximum occurs, and its centroid."""

    triple: tuple[int, int, int]
    centroid: tuple[float, float, float]


@dataclass(frozen=True)
class GuideTally:
    """Counts, maxima and the gap histogram of a set of guide triangles."""

    count: int
    maxima: dict[str, float]
    """Name in ``MAXIMA`` ↦ maximum (NaN if any row is NaN; absent without rows)."""
    where: dict[str, Where]
    """Name ↦ the triangle of the (finite) maximum."""
    gap_min: float | None
    counts: dict[str, int]
    """quality_violations (ρ > ρ_f), ratio_violations (R/R̂ > ρ_f), h3_violations,
    outside_constraint_set."""
    violations: dict[str, int]
    """Mode ↦ triangles whose R − R̂ exceeds the mode's bound."""
    ratio_bound_violations: dict[str, int]
    constraint_violations: dict[str, int]
    histogram: np.ndarray
    """Counts below the first edge, in each bin, and at or above the last edge."""
    classes: dict[str, GuideTally] = field(default_factory=dict)
    """Class in ``CLASSES`` ↦ the tally of its triangles (smooth patch, at a sharp feature);
    empty in those tallies themselves."""

    @classmethod
    def of(
        cls,
        guides: GuideMeasurements,
        ids: np.ndarray,
        centers: np.ndarray,
        params: SamplingParams,
        edges: np.ndarray,
        split: bool = True,
    ) -> GuideTally:
        """The tally of measured guide triangles; ``ids`` maps their ball indices to the ones
        reported, ``centers`` are the balls' centers (by the same local indices). ``split``
        adds the tallies of the smooth-patch and the feature triangles (``classes``)."""
        g = guides
        classes = {}
        if split:
            feature = g.at_feature
            for name, rows in zip(CLASSES, (~feature, feature), strict=True):
                classes[name] = cls.of(g.take(rows), ids, centers, params, edges, split=False)
        values = {
            "rho": g.rho,
            "quality_ratio": g.quality_ratio,
            "h3_ratio": g.h3_ratio,
            "gap_ratio": g.gap_ratio,
            "orthoradius_sq": g.orthoradius_sq / (params.delta * g.lfs[:, 0]) ** 2,
        }
        maxima, where = {}, {}
        if len(g):
            for name, rows in values.items():
                maxima[name] = float(rows.max())
                finite = np.flatnonzero(np.isfinite(rows))
                if len(finite):
                    at = int(finite[np.argmax(rows[finite])])
                    triple = g.triples[at]
                    a, b, c = (int(i) for i in ids[triple])
                    x, y, z = (float(v) for v in centers[triple].mean(axis=0))
                    where[name] = Where((a, b, c), (x, y, z))
        gap = g.gap_ratio
        inner = np.histogram(gap[(gap >= edges[0]) & (gap < edges[-1])], bins=edges)[0]
        histogram = np.concatenate(
            [[int((gap < edges[0]).sum())], inner, [int((gap >= edges[-1]).sum())]]
        ).astype(np.int64)
        return cls(
            count=len(g),
            maxima=maxima,
            where=where,
            gap_min=float(gap.min()) if len(g) else None,
            counts={
                "quality_violations": int((g.rho > params.rho_f).sum()),
                "ratio_violations": int((g.quality_ratio > params.rho_f).sum()),
                "h3_violations": int((g.h3_ratio > 1 + H3_RTOL).sum()),
                "outside_constraint_set": int((~g.inside).sum()),
            },
            violations={mode: int(rows.sum()) for mode, rows in g.exceeds.items()},
            ratio_bound_violations={
                mode: int(rows.sum()) for mode, rows in (g.exceeds_ratio or {}).items()
            },
            constraint_violations={name: int(rows.sum()) for name, rows in g.violated.items()},
            histogram=histogram,
            classes=classes,
        )

    @classmethod
    def merge(cls, tallies: list[GuideTally]) -> GuideTally:
        """The tally of the union of disjoint sets."""
        maxima, where = {}, {}
        for name in MAXIMA:
            found = [t for t in tallies if name in t.maxima]
            if not found:
                continue
            maxima[name] = float(np.max([t.maxima[name] for t in found]))  # NaN propagates
            placed = [t for t in found if name in t.where]
            if placed:
                best = max(placed, key=lambda t: _finite_max(t, name))
                where[name] = best.where[name]
        gaps = [t.gap_min for t in tallies if t.gap_min is not None]
        return cls(
            count=sum(t.count for t in tallies),
            maxima=maxima,
            where=where,
            gap_min=float(np.min(gaps)) if gaps else None,
            counts=_sum(t.counts for t in tallies),
            violations=_sum(t.violations for t in tallies),
            ratio_bound_violations=_sum(t.ratio_bound_violations for t in tallies),
            constraint_violations=_sum(t.constraint_violations for t in tallies),
            histogram=np.sum([t.histogram for t in tallies], axis=0),
            classes={
                name: cls.merge([t.classes[name] for t in tallies])
                for name in CLASSES
                if all(name in t.classes for t in tallies)
            },
        )


def _finite_max(tally: GuideTally, name: str) -> float:
    value = tally.maxima[name]
    return value if np.isfinite(value) else -np.inf


def _sum(dicts) -> dict[str, int]:
    out: dict[str, int] = {}
    for d in dicts:
        for key, value in d.items():
            out[key] = out.get(key, 0) + value
    return out


@dataclass(frozen=True)
class PairTally:
    """A pair condition's extreme, how many pairs break it, and the worst of them."""

    extreme: float
    violations: int
    worst: list[tuple[int, int, float, tuple[float, float, float]]] = field(default_factory=list)
    """(i, j, ratio, midpoint), worst first, at most ``conditions.WORST_LISTED``."""

    @classmethod
    def of(cls, report: conditions.PairReport, ids: np.ndarray, centers: np.ndarray) -> PairTally:
        worst = []
        for (i, j), value in zip(report.worst, report.worst_values, strict=True):
            x, y, z = (float(v) for v in 0.5 * (centers[i] + centers[j]))
            worst.append((int(ids[i]), int(ids[j]), float(value), (x, y, z)))
        return cls(float(report.extreme), int(report.violations), worst)

    @classmethod
    def merge(cls, tallies: list[PairTally], smallest: bool) -> PairTally:
        """Merge; ``smallest``: the extreme is a minimum and lower ratios are worse."""
        extremes = [t.extreme for t in tallies]
        sign = 1 if smallest else -1
        worst = sorted(
            (row for t in tallies for row in t.worst),
            key=lambda row: (sign * row[2], min(row[:2]), max(row[:2])),
        )
        return cls(
            float(np.min(extremes) if smallest else np.max(extremes)),
            sum(t.violations for t in tallies),
            worst[: conditions.WORST_LISTED],
        )
