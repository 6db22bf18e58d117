"""Each guide triangle measured against the paper's bounds and its constraint set.

For a guide triangle with vertices relabelled as in Section 3 (A = p_i the vertex of smallest
L, then B = p_j and C = p_k in cyclic order) this records L_i, L_j, L_k, the circumradius R, the
signed squared orthoradius R̂² of the balls as given, the realized quality ratio R/(δL_i), the
gap (R − R̂)/(εL_i) of Theorem 1 (R̂ of the triangle with the minimum weight subtracted, the
quantity the additive target bounds), the ratio R/R̂ of eq. (54) (the ratio target), H3's
ratio R(1−ε)/(εL_i) (at most 1 where H3 holds), the edges over εL_i, which conditions of the
constraint set it breaks, and which mode's bound it exceeds.

References
----------
Theorem 1, eq. (29), (33)–(36), (54)–(55) and property H3 of Section 4.1.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ...bounds import constraints
from ...bounds.params import SamplingParams, Target
from .seeds import SeededTriangles

BOUND_RTOL = 1e-9
"""A triangle exceeds a bound when R − R̂ > bound·L_i·(1 + BOUND_RTOL) (rounding of both)."""


@dataclass(frozen=True)
class ModeBound:
    """One mode's bound at the sample's ε for one target: on R − R̂ per unit L_i (additive)
    or on R/R̂ (ratio)."""

    mode: str
    """paper, rigorous, tight, or tight_lipschitz (tight with the sample's λ)."""
    value: float
    lipschitz: float | None
    """λ of the constraint set the bound is over (None: no Lipschitz condition)."""
    claim: str
    """proven, numerical or invalid (docs/errata.md, docs/tight.md)."""


def mode_bounds(params: SamplingParams, target: Target | str) -> list[ModeBound]:
    """Every mode's bound at ``params.eps`` for ``target``, for L_i = 1, through the one
    facade :func:`vorobound.bounds.guarantee.bound_at`.

    Additive target: the paper's and the rigorous chain and ``tight``, the supremum over the
    paper's constraint set; ratio target (R/R̂, eq. (54)): the rigorous chain and ``tight``
    (the printed chain's bound on R/R̂ is infinite at practical ε). With ``params.lipschitz``
    the list also has ``tight_lipschitz``, the supremum once |L_x − L_y| ≤ λ|p_x − p_y| is
    added. Tight values are the closed form where it is proven exact, else the numerical
    optimizer; the claim says which.

    References
    ----------
    Eq. (29)–(30), (33)–(55).
    """
    from ...bounds.guarantee import bound_at

    target = Target(target)
    unit = params.but(lfs=1.0, target=target, lipschitz=None)
    chains = ("paper", "rigorous") if target is Target.additive else ("rigorous",)
    cases = [(mode, unit) for mode in (*chains, "tight")]
    if params.lipschitz is not None:
        cases.append(("tight_lipschitz", unit.but(lipschitz=params.lipschitz)))
    out = []
    for name, case in cases:
        bound = bound_at(case, "tight" if name == "tight_lipschitz" else name)
        out.append(ModeBound(name, float(bound.value), case.lipschitz, bound.claim))
    return out


@dataclass(frozen=True)
class GuideMeasurements:
    """Per guide triangle (rows), vertices relabelled A (smallest L), B, C."""

    triples: np.ndarray
    """(m, 3) ball indices of A, B, C."""
    lfs: np.ndarray
    """(m, 3) L_i, L_j, L_k."""
    circumradius: np.ndarray
    """R, eq. (15)."""
    orthoradius_sq: np.ndarray
    """R̂² of the balls as given (signed, eq. (2)); negative for a guide triangle."""
    radius_gap: np.ndarray
    """R − R̂ of the triangle with the minimum weight subtracted, Theorem 1 (eq. (29))."""
    rho: np.ndarray
    """R/(δL_i): the realized quality ratio, to compare with ρ_f of eq. (55)."""
    gap_ratio: np.ndarray
    """(R − R̂)/(εL_i)."""
    quality_ratio: np.ndarray
    """R/R̂ with R̂ = R − (R − R̂) the shifted orthoradius: the ratio target of eq. (54)
    (inf where R̂ = 0)."""
    h3_ratio: np.ndarray
    """R·(1−ε)/(ε·L_i): property H3 says at most 1."""
    edges: np.ndarray
    """(m, 3) a, b, c over εL_i (a = |BC|, b = |CA|, c = |AB|, eq. (7)–(9))."""
    sin_theta: np.ndarray
    """sin θ, θ the angle at A."""
    violated: dict[str, np.ndarray]
    """Constraint name ↦ rows breaking it (the constraint set with the sample's λ)."""
    exceeds: dict[str, np.ndarray]
    """Mode ↦ rows whose R − R̂ exceeds that mode's bound."""
    exceeds_ratio: dict[str, np.ndarray] | None = None
    """Mode ↦ rows whose R/R̂ exceeds that mode's bound on it (ratio target)."""
    feature_reach: np.ndarray | None = None
    """min over the vertices of d_F/r, the distance to the nearest sharp feature in ball
    radii (:mod:`vorobound.sampling.guides.features`); None: no features known."""

    def __len__(self) -> int:
        return len(self.triples)

    @property
    def at_feature(self) -> np.ndarray:
        """Rows within reach of a sharp feature (:func:`.features.at_features`); none when no
        features are known."""
        from .features import at_features

        if self.feature_reach is None:
            return np.zeros(len(self), dtype=bool)
        return at_features(self.feature_reach)

    def take(self, rows: np.ndarray) -> GuideMeasurements:
        """The measurements of ``rows`` only (a boolean mask or indices)."""
        out: dict[str, Any] = {}
        for name, value in vars(self).items():
            if isinstance(value, dict):
                out[name] = {k: v[rows] for k, v in value.items()}
            elif value is None:
                out[name] = None
            else:
                out[name] = value[rows]
        return GuideMeasurements(**out)

    def with_features(self, centers, radii, features) -> GuideMeasurements:
        """These measurements with each row's distance to the sharp ``features`` (None: none
        known), in ball radii; ``centers`` and ``radii`` are indexed by ``triples``."""
        from dataclasses import replace

        from .features import feature_reach

        return replace(self, feature_reach=feature_reach(self.triples, centers, radii, features))

    @property
    def inside(self) -> np.ndarray:
        """Rows inside the whole constraint set."""
        out = np.ones(len(self), dtype=bool)
        for rows in self.violated.values():
            out &= ~rows
        return out


def measure_guides(
    guides: SeededTriangles,
    lfs: np.ndarray,
    params: SamplingParams,
    bounds: list[ModeBound],
    ratio_bounds: list[ModeBound] | None = None,
) -> GuideMeasurements:
    """Measure every guide triangle (see the module docstring).

    Parameters
    ----------
    guides : SeededTriangles
        The guide triangles (rows with both seeds uncovered).
    lfs : numpy.ndarray
        L of every ball (indexed by ``guides.triples``).
    params : SamplingParams
        ε, σ, δ/ε of the sample and λ of its L (adds the Lipschitz conditions to the
        constraint set).
    bounds : list of ModeBound
        From :func:`mode_bounds` for the additive target (bounds on R − R̂).
    ratio_bounds : list of ModeBound, optional
        From :func:`mode_bounds` for the ratio target (bounds on R/R̂).

    References
    ----------
    Theorem 1, eq. (33)–(36), H3.
    """
    geometry = guides.geometry
    first = np.asarray(geometry.min_weight_vertex, dtype=np.int64)
    rows = np.arange(len(first))
    order = np.stack([first, (first + 1) % 3, (first + 2) % 3], axis=1)
    triples = guides.triples[rows[:, None], order]
    vertex_lfs = lfs[triples]
    lfs_i = vertex_lfs[:, 0]
    unit = params.eps * lfs_i
    a, b, c = geometry.edges.T
    config = constraints.scale_configuration(
        b, c, a, geometry.sin_theta, lfs_i, vertex_lfs[:, 1], vertex_lfs[:, 2], params.eps
    )
    limits = constraints.ConstraintParams(params.eps, params.sigma, params.lipschitz)
    gap = geometry.radius_gap
    circumradius = geometry.circumradius
    shifted = circumradius - gap  # R̂ of the min-weight-shifted triangle (≥ 0 up to rounding)
    with np.errstate(divide="ignore", invalid="ignore"):
        quality_ratio = np.where(shifted > 0, circumradius / shifted, np.inf)
    exceeds_ratio = {
        bound.mode: quality_ratio > bound.value * (1 + BOUND_RTOL) for bound in ratio_bounds or ()
    }
    return GuideMeasurements(
        triples=triples,
        lfs=vertex_lfs,
        circumradius=geometry.circumradius,
        orthoradius_sq=geometry.orthoradius_sq,
        radius_gap=gap,
        rho=geometry.circumradius / (params.delta * lfs_i),
        gap_ratio=gap / unit,
        quality_ratio=quality_ratio,
        h3_ratio=circumradius * (1 - params.eps) / unit,
        edges=np.column_stack([a, b, c]) / unit[:, None],
        sin_theta=geometry.sin_theta,
        violated=constraints.violations(config, limits),
        exceeds={bound.mode: gap > bound.value * lfs_i * (1 + BOUND_RTOL) for bound in bounds},
        exceeds_ratio=exceeds_ratio,
    )
