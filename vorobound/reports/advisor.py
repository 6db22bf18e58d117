"""Sampling-parameter advice: largest ε per mode and target, ball radius, spacing, expected
sample counts, and the recommended ε (the most conservative proven or certified one).

Sample counts for a surface S with local feature size L (docs/advisor.md):

* covering (lower) estimate: an ε-sample puts every point within ε L of a sample, and each
  sample's ball covers at most π (ε L)² of the surface, so N ≥ ∫ dA / (π ε² L²);
* packing (upper) estimate: samples are pairwise at least σ ε L apart, so balls of radius
  σ ε L / 2 around them are disjoint, and N ≤ ∫ dA / (π (σ ε L / 2)²) = (4/σ²) × the covering.

On a sphere both are exact bounds: the part of a sphere within chord distance r of one of its
points has area exactly π r² (Archimedes). Elsewhere they are estimates to first order in ε L
over the curvature radius.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..bounds.claims import CERTIFIED, NUMERICAL, PROVEN
from ..bounds.guarantee import eps_star, for_mode
from ..bounds.params import Mode, QualityParams
from ..bounds.targets import H3Route, Target, h3_route
from ..constants import BASELINE_EPS
from ..errors import InputError, NoAdmissibleEps
from ..progress import Progress
from ..rounding import format_down, format_up, round_down
from ..sampling.sampler.lattice import MAX_CANDIDATES
from ..sampling.surfaces.base import SurfaceCounts

GUARANTEE = (
    "What eps <= eps_star gives, per target: every guide triangle of the mode's constraint set "
    "has R <= rho_f*R_hat (ratio target, eq. (54), the form of VoroCrust's Lemma 9) or "
    "R - R_hat <= (rho_f - 1)*delta*L_i (additive target, which gives R <= rho_f*delta*L_i, "
    "eq. (55), but not (54)). The recommended eps is the smallest proven or certified eps_star "
    "among the targets asked for: it gives (54), and (55) with it, when the ratio target is "
    "among them, and (55) alone when only the additive target is. Every bound assumes "
    "property H3 (R <= eps/(1-eps)*L_i for "
    "guide triangles), taken from the VoroCrust literature and not derived here; "
    "'vorobound check' measures it on a sample. Strength per row: proven (algebra in "
    "docs/errata.md or docs/tight.md), certified (an interval certificate, `vorobound "
    "certify`), numerical (optimizer evidence only) or invalid (the printed chain). Not "
    "covered: the rest of VoroCrust's proof (topology, approximation and its other lemmas) may "
    "need its own, possibly smaller, limit on eps; check those conditions separately."
)
CONSTRAINT_SETS = {
    "paper": "the printed chain (33)-(53)",
    "rigorous": "the corrected chain (33)-(53), valid for any guide triangle of an eps-sample",
    "tight": "the supremum over guide triangles allowed by (33)-(36), R <= eps/(1-eps) L_i "
    "and pairwise sparsity (closed form, docs/tight.md)",
}
NONE = "none"
"""Claim of a row without ε* (no admissible ε, or no crossing in the scanned range)."""
TRUSTED = (PROVEN, CERTIFIED)
"""Claims strong enough for a recommendation (and for a "fewer samples" comparison)."""


@dataclass(frozen=True)
class ModeAdvice:
    mode: str
    target: str
    """additive or ratio (:mod:`vorobound.bounds.targets`)."""
    eps_star: float | None
    """None when the row has no ε* (claim NONE, ``note`` says why)."""
    ball_radius: float | None
    """δ·L at the smallest local feature size of the surface."""
    min_spacing: float | None
    """σ·ε·L at the smallest local feature size."""
    samples_low: float | None
    samples_high: float | None
    reduction_vs_1_500: float | None
    """Sample count at ε = 1/500 divided by the count at ε* (same formula); None unless the
    claim is proven or certified."""
    constraint_set: str
    """Which guide triangles the bound covers."""
    claim: str
    """Strength of ε*: proven, certified, numerical or invalid (:mod:`vorobound.bounds.claims`)."""
    method: str
    """How ε* was found (chain, closed form, optimizer)."""
    proven_lower_bound: float | None = None
    """For a numerical ε*: the closed form's proven admissible ε, if any."""
    note: str | None = None
    """Why the row has no ε* (claim NONE): no admissible ε, or no crossing in the scanned
    range."""

    @property
    def trusted_eps(self) -> float | None:
        """The ε this row guarantees: ε* if proven or certified, else its proven lower bound."""
        if self.eps_star is None:
            return None
        if self.claim in TRUSTED:
            return self.eps_star
        return self.proven_lower_bound if self.claim == NUMERICAL else None


@dataclass(frozen=True)
class Recommendation:
    """The ε to use: the most conservative of the targets' best proven or certified ε*."""

    eps: float
    """That ε* rounded down to :data:`vorobound.rounding.DIGITS` significant digits (the
    number printed), never above it; the lengths and counts below are at this ε."""
    binding_target: str
    """The target that sets it (its best trusted ε* is the smallest)."""
    mode: str
    """The mode whose ε* it is."""
    claim: str
    per_target: dict[str, float]
    """Best trusted ε per target asked for."""
    ball_radius: float
    min_spacing: float
    samples_low: float
    samples_high: float
    reduction_vs_1_500: float
    feature_samples: tuple[float, float] | None = None
    """(low, high) samples on the sharp features, part of the counts (None: smooth)."""
    lattice_candidates: float | None = None
    """About how many candidates ``vorobound sample`` needs at ε (meshes only)."""

    @property
    def guarantees(self) -> tuple[str, ...]:
        """The equations the recommended ε gives for every guide triangle of the constraint
        set (given H3): (54) and (55) when the ratio target was asked for, since
        R̂ ≤ δ·L_i (docs/advisor.md); (55) alone when only the additive target was."""
        return ("(54)", "(55)") if Target.ratio.value in self.per_target else ("(55)",)

    @property
    def guarantee_statement(self) -> str:
        """:attr:`guarantees` in words, for people."""
        if self.guarantees == ("(55)",):
            return (
                "R <= rho_f*delta*L_i (eq. (55)) only: the additive target does not give "
                "R <= rho_f*R_hat (eq. (54)); ask for --target ratio for (54)"
            )
        return "R <= rho_f*R_hat (eq. (54)) and hence R <= rho_f*delta*L_i (eq. (55))"

    @property
    def samplable(self) -> bool | None:
        """Whether ``vorobound sample`` builds that lattice (None: not a mesh)."""
        if self.lattice_candidates is None:
            return None
        return self.lattice_candidates <= MAX_CANDIDATES


@dataclass(frozen=True)
class Advice:
    """Everything ``advise`` found: one row per (mode, target), the H3 row and the choice."""

    rows: list[ModeAdvice]
    recommendation: Recommendation | None
    """None when no row is proven or certified (then nothing is recommended)."""
    h3_route: H3Route


def covering_count(surface: SurfaceCounts, eps: float) -> float:
    """∫ dA / (π ε² L²): fewest samples an ε-sample can have (see the module docstring)."""
    return _finite_count(surface.inv_lfs_sq_integral / (math.pi * eps**2), surface)


def packing_count(surface: SurfaceCounts, eps: float, sigma: float) -> float:
    """∫ dA / (π (σ ε L / 2)²): most samples a σ-sparse sample can have."""
    return _finite_count(surface.inv_lfs_sq_integral / (math.pi * (sigma * eps / 2) ** 2), surface)


def feature_counts(surface: SurfaceCounts, eps: float, sigma: float) -> tuple[float, float] | None:
    """Samples on the sharp features: consecutive ones are σεL to 2σεL apart along a curve
    (σ-sparse; a maximal subset of dense candidates on it), so ∫ds/L/(2σε) to ∫ds/L/(σε)."""
    if not surface.feature_inv_lfs > 0:
        return None
    high = surface.feature_inv_lfs / (sigma * eps)
    return (high / 2, high)


def lattice_candidates(surface: SurfaceCounts, eps: float, sigma: float, lam: float | None):
    """Expected size of the lattice ``vorobound sample`` builds on a mesh (None otherwise)."""
    if not surface.mesh_lattice:
        return None
    from ..sampling.sampler.mesh_lattice import expected_candidates

    return expected_candidates(surface.inv_lfs_sq_integral, eps, sigma, 1.0 if lam is None else lam)


def _finite_count(count: float, surface: SurfaceCounts) -> float:
    if not math.isfinite(count):
        raise InputError(f"the sample count for {surface.name} overflows: no advice possible")
    return count


def advise(
    quality: QualityParams,
    surface: SurfaceCounts,
    modes: list[str],
    progress: Progress | None = None,
    targets: list[str] = ("additive", "ratio"),
) -> Advice:
    """Advice for each (mode, target): ε*, ball radius, spacing and sample counts on
    ``surface``, the H3 row, and the recommended ε. ``quality.lipschitz`` is the tight mode's
    λ (the chains have none); ``quality.target`` is replaced by each of ``targets``."""
    lipschitz = quality.lipschitz
    for name, value in (("area", surface.area), ("integral of 1/L²", surface.inv_lfs_sq_integral)):
        if not (math.isfinite(value) and value > 0):
            raise InputError(f"{surface.name}: its {name} is not a positive finite number")
    rows = []
    for target in dict.fromkeys(Target(t) for t in targets):
        for name in dict.fromkeys(modes):  # each mode once, in the order given
            mode = Mode(name)
            asked = for_mode(quality.but(target=target), mode)
            lam = asked.lipschitz
            try:
                star = eps_star(asked, mode, progress=progress)
            except NoAdmissibleEps as err:  # this row has no ε*; the others still do
                rows.append(_no_row(mode, target, lam, err))
                continue
            rows.append(_row(quality, surface, mode, target, lam, star))
    return Advice(rows, _recommend(quality, surface, rows, lipschitz), h3_route(quality))


def _labels(mode, lam) -> tuple[str, str]:
    label, constraint = mode.value, CONSTRAINT_SETS[mode.value]
    if lam is not None:
        label = f"tight λ={lam:g}"
        constraint += f", plus {lam:g}-Lipschitz L"
    return label, constraint


def _no_row(mode, target, lam, err: NoAdmissibleEps) -> ModeAdvice:
    """A (mode, target) without ε*: why, in ``note``; never recommended."""
    label, constraint = _labels(mode, lam)
    return ModeAdvice(
        mode=label,
        target=target.value,
        eps_star=None,
        ball_radius=None,
        min_spacing=None,
        samples_low=None,
        samples_high=None,
        reduction_vs_1_500=None,
        constraint_set=constraint,
        claim=NONE,
        method="no eps*",
        note=str(err),
    )


def _row(quality, surface, mode, target, lam, star) -> ModeAdvice:
    label, constraint = _labels(mode, lam)
    eps = star.eps_star
    return ModeAdvice(
        mode=label,
        target=target.value,
        eps_star=eps,
        ball_radius=quality.delta_ratio * eps * surface.lfs_min,
        min_spacing=quality.sigma * eps * surface.lfs_min,
        samples_low=covering_count(surface, eps),
        samples_high=packing_count(surface, eps, quality.sigma),
        reduction_vs_1_500=(eps / BASELINE_EPS) ** 2 if star.claim in TRUSTED else None,
        constraint_set=constraint,
        claim=star.claim,
        method=star.method,
        proven_lower_bound=star.proven_lower_bound,
    )


def _recommend(quality, surface, rows: list[ModeAdvice], lipschitz) -> Recommendation | None:
    """Per target the largest trusted ε over the modes; then the smallest over the targets."""
    best: dict[str, ModeAdvice] = {}
    for row in rows:
        if row.trusted_eps is None:
            continue
        if row.target not in best or row.trusted_eps > best[row.target].trusted_eps:
            best[row.target] = row
    targets = {row.target for row in rows}
    if not best or set(best) != targets:
        return None  # some target asked for has no proven or certified ε*
    binding = min(best.values(), key=lambda row: row.trusted_eps)
    # The ε a user copies is the printed one: round it down (never past the trusted ε*) and
    # give every count and length at that ε.
    eps = round_down(binding.trusted_eps)
    claim = binding.claim if binding.claim in TRUSTED else PROVEN
    return Recommendation(
        eps=eps,
        binding_target=binding.target,
        mode=binding.mode,
        claim=claim,
        per_target={t: row.trusted_eps for t, row in best.items()},
        ball_radius=quality.delta_ratio * eps * surface.lfs_min,
        min_spacing=quality.sigma * eps * surface.lfs_min,
        samples_low=covering_count(surface, eps),
        samples_high=packing_count(surface, eps, quality.sigma),
        reduction_vs_1_500=(eps / BASELINE_EPS) ** 2,
        feature_samples=feature_counts(surface, eps, quality.sigma),
        lattice_candidates=lattice_candidates(surface, eps, quality.sigma, lipschitz),
    )


def versus_baseline(reduction: float | None) -> str:
    """Sample count at ε = 1/500 over the count at ε*, in words ("—" when not trusted); a
    saving is never overstated and a cost never understated (:mod:`vorobound.rounding`)."""
    if reduction is None:
        return "—"
    if reduction >= 1:
        return f"{format_down(reduction, 4)}× fewer"
    return f"{format_up(1 / reduction, 4)}× more"
