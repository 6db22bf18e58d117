"""What a ball set realizes: the (ε, σ, δ/ε, λ) it satisfies and the guarantee they give.

VoroCrust's model puts on each sample p a ball of radius r_p = δ·L(p), δ = (δ/ε)·ε. A ball
file fixes r but not the split of r into δ and L; docs/vorocrust.md derives the inference this
module makes. With the balls (centres p, radii r) and the surface (local feature size f):

* from the balls only: S = min over pairs |p − q|/min(r_p, r_q) (spacing in radius units) and
  Λ = max |r_p − r_q|/|p − q| over neighbouring pairs and guide-triangle edges (vc_mesh's
  LIP_CONST, realized);
* with the surface: C = max over probes x of dist(x, sample)/f(x) (coverage in units of the
  surface's L) and M = max_p r_p/f(p) (ball radius in units of the surface's L at the centre).

Then ε ≥ C (coverage), δ ≥ M (L = r/δ ≤ f), σ = (δ/ε)·S (sparsity) and λ = Λ/δ (Lipschitz L).
The tight bound depends on (σ/(δ/ε), λσε, ε) only through μ* = X(2 + X)/S², X =
min(2ε/(1−ε), ΛS), which grows with ε; every condition of the constraint set (33)–(36) and H3
gets easier as ε grows at δ = M. So the realized ε is the smallest ε ≥ C at which every measured
guide triangle lies in the constraint set, found by bisection (the conditions are monotone in
ε). Printed values are rounded toward safety (:mod:`vorobound.rounding`): ε and δ/ε and λ up,
σ down, and the constraint set is checked again at the rounded values.

References
----------
Eq. (33)–(37), (54)–(55), H3 and the sampling conditions of Section 4.1; docs/tight.md.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from dataclasses import dataclass, field

import numpy as np

from ..bounds.params import QualityParams, SamplingParams
from ..checks import DELTA_RATIO_RANGE, EPS_RANGE, LIPSCHITZ_RANGE, SIGMA_RANGE
from ..errors import VoroboundWarning
from ..rounding import round_down, round_up
from ..sampling.balls import Balls
from ..sampling.guides.measure import measure_guides
from ..sampling.guides.triangles import find_guide_triangles
from ..sampling.sampler import conditions

SAFETY_RTOL = 1e-9
"""Relative margin added before directed rounding, so a realized value that is exactly a
5-digit number still clears the condition it bounds after the check's own float arithmetic."""
BISECTION_STEPS = 60
OFF_SURFACE_RTOL = 0.2
"""A ball centre lying farther from the given surface than this fraction of its radius is not
a sample of that surface. A VoroCrust centre lies on the input mesh; a faceted mesh of a curved
surface puts it off the analytic surface by a sagitta (0.08 of the radius at most on the
coarse torus fixture, 16 vertices around the tube)."""
LISTED = 5
"""Worst balls or triangles listed with a failed condition."""


@dataclass(frozen=True)
class Measured:
    """The raw ratios the inference rests on (docs/vorocrust.md)."""

    spacing: float
    """S = min |p − q|/min(r_p, r_q) (balls only)."""
    spacing_pair: tuple[int, int]
    radius_lipschitz: float
    """Λ = max |r_p − r_q|/|p − q| (balls only): the LIP_CONST the balls realize."""
    coverage: float | None
    """C = max dist(x, sample)/f(x) over the probes (needs the surface)."""
    coverage_where: list | None
    radius_over_lfs: float | None
    """M = max r_p/f(p) (needs the surface's L at the centres)."""
    radius_over_lfs_ball: int | None
    off_surface: float | None
    """max dist(p, surface)/r_p over the centres."""
    off_surface_ball: int | None


@dataclass(frozen=True)
class Realization:
    """The realized parameters and the guarantee they give."""

    measured: Measured
    eps: float | None
    sigma: float | None
    delta_ratio: float | None
    lipschitz: float | None
    failed_condition: str | None
    failed_detail: dict = field(default_factory=dict)
    rho_f_ratio: float | None = None
    """Smallest ρ_f with R ≤ ρ_f·R̂ proven at the realized parameters (tight closed form)."""
    rho_f_additive: float | None = None
    """Smallest ρ_f with R − R̂ ≤ (ρ_f − 1)δL_i proven there."""
    weight_ratio: float | None = None
    """μ* at the realized parameters."""
    claim: str | None = None
    eps_coverage: float | None = None
    """The smallest ε coverage allows (C rounded up); ``eps`` is larger when the constraint
    set needs it."""

    @property
    def quality(self) -> QualityParams | None:
        if self.eps is None or self.sigma is None or self.delta_ratio is None:
            return None  # all three are None together: nothing realized
        return QualityParams(self.sigma, self.delta_ratio, lipschitz=self.lipschitz)

    def realized_json(self) -> dict:
        m = self.measured
        return {
            "eps": self.eps,
            "sigma": self.sigma,
            "delta_ratio": self.delta_ratio,
            "lipschitz": self.lipschitz,
            "eps_coverage": self.eps_coverage,
            "delta": None
            if self.eps is None or self.delta_ratio is None
            else self.eps * self.delta_ratio,
            "measured": {
                "spacing_over_radius_min": m.spacing,
                "radius_lipschitz": m.radius_lipschitz,
                "coverage_over_lfs_max": m.coverage,
                "coverage_where": m.coverage_where,
                "radius_over_lfs_max": m.radius_over_lfs,
                "off_surface_over_radius_max": m.off_surface,
            },
        }

    def guarantee_json(self, target: str) -> dict:
        rho = self.rho_f_ratio if target == "ratio" else self.rho_f_additive
        return {
            "target": target,
            "rho_f": rho,
            "rho_f_ratio": self.rho_f_ratio,
            "rho_f_additive": self.rho_f_additive,
            "weight_ratio": self.weight_ratio,
            "claim": self.claim,
            "failed_condition": self.failed_condition,
            "failed_detail": self.failed_detail or None,
            "premise": "H3 and the constraint set (33)-(36) as measured on these balls' guide "
            "triangles; coverage measured on probes (numerical)",
        }


def measure(balls: Balls, shape, guides, seed: int | None = None) -> Measured:
    """The ratios of :class:`Measured`; the surface ones are None without ``shape``."""
    centers, radii = balls.centers, balls.radii
    near = conditions.neighbours(centers)
    spacing = conditions.sparsity(centers, radii, 1.0, 1.0, near)
    lam = conditions.measured_lipschitz(centers, radii, guides.triples, near)
    if shape is None:
        return Measured(
            spacing.extreme, spacing.extreme_pair, lam, None, None, None, None, None, None
        )
    closest = shape.closest(centers)
    with np.errstate(divide="ignore", invalid="ignore"):
        over = radii / closest.lfs
    worst = int(np.nanargmax(over))
    off = closest.distance / radii
    far = int(np.argmax(off))
    extra = guides.geometry.circumcenter if len(guides.triples) else None
    coverage, where, _ = conditions.surface_coverage(shape, centers, 1.0, None, extra)
    return Measured(
        spacing.extreme,
        spacing.extreme_pair,
        lam,
        coverage,
        np.asarray(where).tolist(),
        float(over[worst]),
        worst,
        float(off[far]),
        far,
    )


def warn_off_surface(measured: Measured | None, balls: Balls, what: str) -> None:
    """Warn when ball centres lie off the given surface by more than their sampling tolerance
    (:data:`OFF_SURFACE_RTOL` of their radius); nothing without a measurement."""
    if measured is None or measured.off_surface is None or measured.off_surface <= OFF_SURFACE_RTOL:
        return
    i = measured.off_surface_ball
    where = ", ".join(f"{v:.6g}" for v in balls.centers[i])
    warnings.warn(
        f"{what}: ball centres lie off the given surface, up to {measured.off_surface:.3g} of "
        f"their radius (ball {i} at {where}, {measured.off_surface * balls.radii[i]:.6g} off; "
        f"tolerance {OFF_SURFACE_RTOL:g}): wrong surface, size or axis? --mesh PART takes the "
        "part the balls were made for",
        VoroboundWarning,
        stacklevel=3,
    )


def off_surface(balls: Balls, shape) -> Measured | None:
    """Only the off-surface measurement (for commands that do not infer), or None."""
    if shape is None:
        return None
    closest = shape.closest(balls.centers)
    off = closest.distance / balls.radii
    far = int(np.argmax(off))
    nan = math.nan
    return Measured(nan, (-1, -1), nan, None, None, None, None, float(off[far]), far)


def _params(eps: float, m: Measured, rho_f: float) -> tuple[QualityParams | None, str | None]:
    """(σ, δ/ε, λ) at ``eps`` from the measured ratios, rounded toward safety; None when one
    leaves its supported range."""
    assert m.radius_over_lfs is not None, "measured with the surface"
    kappa = round_up(m.radius_over_lfs / eps * (1 + SAFETY_RTOL))
    sigma = round_down(kappa * m.spacing * (1 - SAFETY_RTOL))
    lam = (
        0.0
        if m.radius_lipschitz == 0
        else round_up(m.radius_lipschitz / (kappa * eps) * (1 + SAFETY_RTOL))
    )
    if not (DELTA_RATIO_RANGE[0] <= kappa <= DELTA_RATIO_RANGE[1]):
        return None, "delta_ratio"
    if not (SIGMA_RANGE[0] <= sigma <= SIGMA_RANGE[1]):
        return None, "sparsity"
    if lam != 0 and not (LIPSCHITZ_RANGE[0] <= lam <= LIPSCHITZ_RANGE[1]):
        return None, "lipschitz"
    if sigma * (1 - eps) > math.sqrt(3):
        return None, "sparsity"
    return QualityParams(sigma, kappa, rho_f, lipschitz=lam), None


def _outside(guides, radii, eps: float, quality: QualityParams):
    """The guide triangles outside the constraint set at (ε, quality), measured."""
    params = SamplingParams(eps, quality)
    g = measure_guides(guides, radii / params.delta, params, [], [])
    bad = ~g.inside | (g.h3_ratio > 1 + 1e-9)
    return g, bad


def realize(balls: Balls, shape, engine, rho_f: float, progress=None) -> Realization:
    """Infer the parameters ``balls`` realize on ``shape`` and the guarantee they give
    (module docstring). Without ``shape`` only the ball-only ratios are measured and no ε."""
    search = find_guide_triangles(balls, engine, False, progress)
    guides = search.guide
    m = measure(balls, shape, guides)
    if shape is None:
        return Realization(m, None, None, None, None, "surface", {"note": "ε needs the surface"})
    if len(guides.triples) == 0:
        return Realization(m, None, None, None, None, "guide_triangles")
    assert m.coverage is not None, "measured with the surface"
    eps_low = round_up(m.coverage * (1 + SAFETY_RTOL))
    if eps_low > EPS_RANGE[1]:
        return Realization(
            m,
            None,
            None,
            None,
            None,
            "coverage",
            {"coverage_over_lfs_max": m.coverage, "where": m.coverage_where},
            eps_coverage=eps_low,
        )
    eps_low = max(eps_low, EPS_RANGE[0])

    def feasible(eps):
        quality, why = _params(eps, m, rho_f)
        if quality is None:
            return False, why, None
        g, bad = _outside(guides, balls.radii, eps, quality)
        return not bad.any(), None, (quality, g, bad)

    ok, why, state = feasible(eps_low)
    eps = eps_low
    if not ok:
        high = EPS_RANGE[1]
        ok_high, why_high, state_high = feasible(high)
        if not ok_high:
            return _failed(m, balls, high, why_high, state_high, eps_low)
        low = eps_low
        for _ in range(BISECTION_STEPS):
            mid = 0.5 * (low + high)
            if feasible(mid)[0]:
                high = mid
            else:
                low = mid
            if high - low <= 1e-6 * high:
                break
        eps = round_up(high)
        for _ in range(10):  # rounding may move the printed values off the boundary
            ok, why, state = feasible(eps)
            if ok:
                break
            eps = round_up(eps * (1 + 1e-5))
        if not ok:
            return _failed(m, balls, eps, why, state, eps_low)
    quality = state[0]
    return _guarantee(m, eps, quality, eps_low)


def _guarantee(m: Measured, eps: float, quality: QualityParams, eps_low: float) -> Realization:
    from ..bounds.tight.ratio_form import ratio_supremum_closed_form

    sup = ratio_supremum_closed_form(eps, quality.sigma, quality.delta_ratio, quality.lipschitz)
    additive = 1 + sup.vertex.value / (quality.delta_ratio * eps)
    ratio = None if not math.isfinite(sup.value) else round_up(sup.value)
    failed = None if ratio is not None else "ratio_bound"
    detail = {}
    if failed:
        detail = {
            "note": "mu* >= 1: the weights can move the orthocenter onto a vertex, so no finite "
            "bound on R/R^ is proven at these parameters (the additive target still is)"
        }
    return Realization(
        m,
        eps,
        quality.sigma,
        quality.delta_ratio,
        quality.lipschitz,
        failed,
        detail,
        ratio,
        round_up(additive),
        float(sup.vertex.weight_ratio),
        f"proven ({sup.status.value}), conditional on H3 and the constraint set as measured",
        eps_low,
    )


def _failed(m: Measured, balls: Balls, eps, why, state, eps_low) -> Realization:
    """No ε < 1 puts every measured guide triangle in the constraint set (or a parameter
    leaves its range): the condition and the worst triangles, with coordinates."""
    if state is None:
        return Realization(m, None, None, None, None, why, {"eps": eps}, eps_coverage=eps_low)
    _, g, bad = state
    names = [name for name, rows in g.violated.items() if rows.any()]
    h3 = g.h3_ratio > 1 + 1e-9
    condition = names[0] if names else "H3"
    rows = np.flatnonzero(bad)
    order = rows[np.argsort(-g.h3_ratio[rows])][:LISTED]
    listed = [
        {
            "balls": g.triples[i].tolist(),
            "where": balls.centers[g.triples[i]].mean(axis=0).tolist(),
            "h3_ratio": float(g.h3_ratio[i]),
        }
        for i in order
    ]
    detail = {
        "eps": eps,
        "triangles": int(bad.sum()),
        "h3_violations": int(h3.sum()),
        "constraint_violations": {n: int(r.sum()) for n, r in g.violated.items() if r.any()},
        "worst": listed,
    }
    return Realization(m, None, None, None, None, condition, detail, eps_coverage=eps_low)


class SmoothPart:
    """A surface restricted, for the coverage probes, to the points nearer a smooth-stratum
    ball than any corner or edge ball (those are covered by the feature strata, which are
    reported apart). Everything else is the surface's."""

    def __init__(self, shape, smooth_centers: np.ndarray, feature_centers: np.ndarray):
        from scipy.spatial import cKDTree

        self._shape = shape
        self._smooth = cKDTree(smooth_centers)
        self._feature = cKDTree(feature_centers)

    def __getattr__(self, name):
        return getattr(self._shape, name)

    def _keep(self, points: np.ndarray) -> np.ndarray:
        return self._smooth.query(points)[0] <= self._feature.query(points)[0]

    def random_points(self, count: int, rng):
        points, lfs = self._shape.random_points(count, rng)
        keep = self._keep(points)
        return points[keep], lfs[keep]

    def project(self, points: np.ndarray):
        found = self._shape.project(points)
        if found is None:
            return None
        keep = self._keep(found[0])
        return found[0][keep], found[1][keep]


def feature_summary(balls: Balls, shape) -> dict:
    """Sizes and spacing of a corner or edge stratum (never folded into the smooth verdict)."""
    from scipy.spatial import cKDTree

    centers, radii = balls.centers, balls.radii
    out = {
        "count": len(radii),
        "radius_min": float(radii.min()),
        "radius_max": float(radii.max()),
        "spacing_over_radius_min": None,
        "radius_over_lfs_max": None,
        "off_surface_over_radius_max": None,
    }
    if len(radii) > 1:
        dist, near = cKDTree(centers).query(centers, k=2)
        ratio = dist[:, 1] / np.minimum(radii, radii[near[:, 1]])
        out["spacing_over_radius_min"] = float(ratio.min())
    if shape is not None:
        closest = shape.closest(centers)
        out["radius_over_lfs_max"] = float(np.max(radii / closest.lfs))
        out["off_surface_over_radius_max"] = float(np.max(closest.distance / radii))
    return out


class BallRadiusUnits:
    """A surface whose L is replaced by r/``eps``, r the radius of the ball nearest to the
    point: measured over ε·L, distances come out over the local ball radius."""

    def __init__(self, shape, centers: np.ndarray, radii: np.ndarray, eps: float):
        from scipy.spatial import cKDTree

        self._shape, self._tree, self._radii, self._eps = shape, cKDTree(centers), radii, eps

    def __getattr__(self, name):
        return getattr(self._shape, name)

    def _scale(self, points: np.ndarray) -> np.ndarray:
        return self._radii[self._tree.query(points)[1]] / self._eps

    def closest(self, points: np.ndarray):
        found = self._shape.closest(points)
        return dataclasses.replace(found, lfs=self._scale(found.points))

    def random_points(self, count: int, rng):
        points, _ = self._shape.random_points(count, rng)
        return points, self._scale(points)

    def project(self, points: np.ndarray):
        found = self._shape.project(points)
        return None if found is None else (found[0], self._scale(found[0]))
