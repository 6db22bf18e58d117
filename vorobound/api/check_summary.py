"""What a check found, as typed fields: the view of its JSON that ``vorobound check`` prints.

:meth:`CheckSummary.of` reads the ``--json`` object of a check
(:meth:`vorobound.api.check.CheckResult.to_dict`) field by field
(:func:`~vorobound.api.result.typed_view`), so the tables show the numbers of the JSON and the
JSON keys stay the interface they are (docs/samples.md describes them).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from .result import typed_view


@dataclass(frozen=True)
class CheckParams:
    """The parameters the check measured against."""

    eps: float
    sigma: float
    delta_ratio: float
    rho_f: float


@dataclass(frozen=True)
class BoundAtEps:
    """One mode's bound at the check's ε, and how many guide triangles exceed it."""

    mode: str
    claim: str
    lipschitz: float | None
    """The λ the bound assumes (None: a bound without λ)."""
    value: float | None
    """The bound: on (R − R̂)/(εL_i), or on R/R̂ (eq. (54)); None where there is none."""
    above: int | None
    """Guide triangles above the bound (None: not defined)."""


@dataclass(frozen=True)
class PairViolation:
    """A pair of balls that breaks sparsity or the λ-Lipschitz condition."""

    i: int
    j: int
    ratio: float
    where: Sequence[float]
    """Midpoint of the two centers."""


@dataclass(frozen=True)
class ClassFailures:
    """The failures counted on the guide triangles of one class (on smooth patches, or within
    reach of a sharp feature)."""

    n_guide_triangles: int
    outside_constraint_set: int
    """Outside the constraint set (33)–(36) or H3."""
    quality: int
    """R > ρ_f δL_i (eq. (55))."""
    ratio: int
    """R > ρ_f R̂ (eq. (54))."""
    proven_bound: int
    """Exceedances of a proven bound."""
    worst_h3_centroid: Sequence[float] | None = None
    """Where the largest R(1−ε)/(εL_i) sits (None: not located)."""


@dataclass(frozen=True)
class RealizedParams:
    """The ε, δ/ε, σ and λ a set of balls realizes (a check without ε, or of a VoroCrust run),
    and the measured ratios each comes from."""

    eps: float | None
    delta_ratio: float | None
    sigma: float | None
    lipschitz: float | None
    coverage_over_lfs_max: float | None
    radius_over_lfs_max: float | None
    spacing_over_radius_min: float | None
    radius_lipschitz: float | None


@dataclass(frozen=True)
class RealizedGuarantee:
    """What the realized parameters guarantee for the target."""

    target: str
    rho_f: float | None
    """R ≤ ρ_f·R̂ for every guide triangle (None: nothing proven)."""
    claim: str | None
    failed_condition: str | None
    """The condition that fails when nothing is proven."""


@dataclass(frozen=True)
class CheckSummary:
    """The check of one sample as the CLI prints it (the JSON keys of the same names)."""

    source: str
    params: CheckParams
    engine: str
    n_samples: int
    n_guide_triangles: int
    n_half_covered: int
    half_covered_share: float | None
    """Half-covered triples over seeded ones (None: none seeded)."""
    coverage_max: float | None
    sparsity_min: float | None
    sparsity_violations: int
    lipschitz: float | None
    """The λ the balls' L is checked against."""
    lipschitz_realized: float | None
    lipschitz_violations: int
    rho_max: float | None
    """max R/(δL_i)."""
    quality_violations: int
    gap_ratio_max: float | None
    """max (R − R̂)/(εL_i) (Theorem 1)."""
    ratio_max: float | None
    """max R/R̂ (eq. (54))."""
    ratio_violations: int
    h3_ratio_max: float | None
    """max R(1−ε)/(εL_i) (≤ 1 if H3 holds)."""
    h3_violations: int
    outside_constraint_set: int
    constraint_violations: Mapping[str, int]
    """Guide triangles outside each constraint of (33)–(36)."""
    gap_bounds: tuple[BoundAtEps, ...]
    """Each mode's bound on (R − R̂)/(εL_i) at this ε."""
    ratio_bounds: tuple[BoundAtEps, ...]
    """Each mode's bound on R/R̂ (eq. (54))."""
    sparsity_worst: tuple[PairViolation, ...]
    lipschitz_worst: tuple[PairViolation, ...]
    smooth: ClassFailures
    """Guide triangles on smooth patches (they decide the exit code)."""
    at_features: ClassFailures
    """Guide triangles within reach of a sharp feature (reported only)."""
    feature_rule: str
    """How a guide triangle counts as at a feature."""
    coverage_note: str | None = None
    """Why coverage was not measured, where it was not."""
    realized: RealizedParams | None = None
    guarantee: RealizedGuarantee | None = None
    strata: Mapping[str, int | None] | None = None
    """Balls per stratum of a VoroCrust run (surface, edges, corners)."""

    @classmethod
    def of(cls, data: Mapping) -> CheckSummary:
        """The view of a check's JSON object."""
        features = data["violations_at_features"]
        worst = features["worst"].get("h3_ratio")
        realized = data.get("realized")
        return typed_view(
            cls,
            data,
            params=typed_view(CheckParams, data["params"]),
            gap_bounds=_bounds(data["bound"], "gap_ratio", data["violations"]),
            ratio_bounds=_bounds(data["ratio_bound"], "value", data["ratio_bound_violations"]),
            sparsity_worst=_pairs(data["sparsity_worst"]),
            lipschitz_worst=_pairs(data["lipschitz_worst"]),
            smooth=typed_view(
                ClassFailures,
                data["violations_smooth"],
                n_guide_triangles=data["n_guide_triangles"] - features["n_guide_triangles"],
            ),
            at_features=typed_view(
                ClassFailures,
                features,
                worst_h3_centroid=None if worst is None else worst["centroid"],
            ),
            feature_rule=data["by_class"]["feature_rule"],
            realized=None
            if realized is None
            else typed_view(RealizedParams, realized | realized["measured"]),
            guarantee=None
            if "guarantee" not in data
            else typed_view(RealizedGuarantee, data["guarantee"]),
        )


def _bounds(entries: Mapping, key: str, above: Mapping) -> tuple[BoundAtEps, ...]:
    """Each mode's bound (``key`` of its entry) and the triangles above it."""
    return tuple(
        typed_view(BoundAtEps, entry, mode=mode, value=entry[key], above=above.get(mode, 0))
        for mode, entry in entries.items()
    )


def _pairs(rows: Sequence[Mapping]) -> tuple[PairViolation, ...]:
    return tuple(typed_view(PairViolation, row) for row in rows)
