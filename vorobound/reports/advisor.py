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
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..bounds.claims import CERTIFIED, NUMERICAL, PROVEN
from ..bounds.guarantee import eps_star, for_mode
from ..bounds.guarantee_at import GuaranteeAt, guarantee_at
from ..bounds.params import Mode, QualityParams
from ..bounds.targets import H3Route, Target, h3_route
from ..checks import EPS_RANGE
from ..constants import BASELINE_EPS
from ..errors import EmptyConstraintSet, InputError, NoAdmissibleEps
from ..progress import Progress
from ..rounding import format_down, format_up, round_down, round_up
from ..sampling.surfaces.base import SurfaceCounts

if TYPE_CHECKING:
    from ..sampling.sampler.cost import SamplerCost

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
    guarantee: GuaranteeAt | None = None
    """What ε* guarantees per target (the smallest proven ρ_f each meets there)."""
    cost: SamplerCost | None = None
    """:class:`vorobound.sampling.sampler.cost.SamplerCost` at ε* (meshes only)."""

    @property
    def trusted_eps(self) -> float | None:
        """The ε this row guarantees: ε* if proven or certified, else its proven lower bound."""
        if self.eps_star is None:
            return None
        if self.claim in TRUSTED:
            return self.eps_star
        return self.proven_lower_bound if self.claim == NUMERICAL else None


@dataclass(frozen=True)
class Fallback:
    """The smallest ε ``vorobound sample`` can build when the recommended one is too fine, and
    what it still guarantees."""

    eps: float
    guarantee: GuaranteeAt | None
    samples_low: float
    samples_high: float
    cost: SamplerCost | None
    """:class:`vorobound.sampling.sampler.cost.SamplerCost` at ``eps``."""


@dataclass(frozen=True)
class Recommendation:
    """The ε to use: the most conservative of the targets' best proven or certified ε*, or
    with a sample budget the ε of the best proven guarantee within it."""

    eps: float
    """That ε* rounded down to :data:`vorobound.rounding.DIGITS` significant digits (the
    number printed), never above it; the lengths and counts below are at this ε."""
    binding_target: str
    """The target that sets it (its best trusted ε* is the smallest); "budget" when a sample
    budget sets it."""
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
    guarantee: GuaranteeAt | None = None
    """What ``eps`` guarantees per target (smallest proven ρ_f)."""
    cost: SamplerCost | None = None
    """:class:`vorobound.sampling.sampler.cost.SamplerCost` at ``eps`` (meshes only)."""
    fallback: Fallback | None = None
    """When ``eps`` cannot be sampled: the smallest ε that can, and its guarantee."""
    max_samples: float | None = None
    """The sample budget asked for (``--max-samples``), if any."""

    @property
    def lattice_candidates(self) -> float | None:
        """About how many candidates ``vorobound sample`` needs at ε (meshes only)."""
        return None if self.cost is None else self.cost.candidates

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
        return None if self.cost is None else self.cost.samplable

    @property
    def rho_f_proven(self) -> float | None:
        """The smallest ρ_f proven at ``eps`` for the ratio target R ≤ ρ_f·R̂ (eq. (54))."""
        return None if self.guarantee is None else self.guarantee.rho_f_ratio


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


def sampler_cost(
    surface: SurfaceCounts, eps: float, sigma: float, lam: float | None
) -> SamplerCost | None:
    """Estimated cost of ``vorobound sample`` on a mesh at ``eps`` (None for other surfaces)."""
    if not surface.mesh_lattice:
        return None
    from ..sampling.sampler.cost import sampler_cost as cost

    return cost(surface.inv_lfs_sq_integral, eps, sigma, 1.0 if lam is None else lam)


def what_eps_guarantees(quality: QualityParams, eps: float) -> GuaranteeAt | None:
    """The smallest proven ρ_f per target at ``eps`` (None where no guide triangle exists)."""
    try:
        return guarantee_at(eps, quality)
    except (InputError, EmptyConstraintSet):
        return None


def printable_eps_up(value: float) -> float:
    """The float at or above ``value`` that :func:`vorobound.rounding.format_down` prints as
    ``value`` rounded up: an ε chosen for a budget (it may only grow) printed without loss."""
    eps = round_up(value)
    text = format_up(value)
    while format_down(eps) != text:  # the decimal's float may lie just below the decimal
        eps = math.nextafter(eps, math.inf)
    return eps


def _finite_count(count: float, surface: SurfaceCounts) -> float:
    if not math.isfinite(count):
        raise InputError(f"the sample count for {surface.name} overflows: no advice possible")
    return count


def advise(
    quality: QualityParams,
    surface: SurfaceCounts,
    modes: list[str],
    progress: Progress | None = None,
    targets: Sequence[str] = ("additive", "ratio"),
    max_samples: float | None = None,
) -> Advice:
    """Advice for each (mode, target): ε*, ball radius, spacing, sample counts and sampler cost
    on ``surface``, what each ε* guarantees, the H3 row, and the recommended ε.
    ``quality.lipschitz`` is the tight mode's λ (the chains have none); ``quality.target`` is
    replaced by each of ``targets``. With ``max_samples`` the recommendation is instead the
    best proven guarantee whose packing count stays within that many samples
    (:func:`budget_recommendation`)."""
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
    if max_samples is None:
        recommendation = _recommend(quality, surface, rows, lipschitz)
    else:
        recommendation = budget_recommendation(quality, surface, max_samples)
    return Advice(rows, recommendation, h3_route(quality))


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
        guarantee=what_eps_guarantees(quality, eps),
        cost=sampler_cost(surface, eps, quality.sigma, lam),
    )


def _recommend(quality, surface, rows: list[ModeAdvice], lipschitz) -> Recommendation | None:
    """Per target the largest trusted ε over the modes; then the smallest over the targets."""
    best: dict[str, tuple[ModeAdvice, float]] = {}  # target: (row, its trusted ε)
    for row in rows:
        trusted = row.trusted_eps
        if trusted is None:
            continue
        if row.target not in best or trusted > best[row.target][1]:
            best[row.target] = (row, trusted)
    targets = {row.target for row in rows}
    if not best or set(best) != targets:
        return None  # some target asked for has no proven or certified ε*
    binding, binding_eps = min(best.values(), key=lambda pair: pair[1])
    # The ε a user copies is the printed one: round it down (never past the trusted ε*) and
    # give every count and length at that ε.
    eps = round_down(binding_eps)
    claim = binding.claim if binding.claim in TRUSTED else PROVEN
    return _recommendation(
        quality,
        surface,
        eps,
        binding_target=binding.target,
        mode=binding.mode,
        claim=claim,
        per_target={t: trusted for t, (_, trusted) in best.items()},
    )


def budget_eps(surface: SurfaceCounts, sigma: float, max_samples: float) -> float:
    """The smallest ε whose packing count (the most samples a σ-sparse sample can have) is at
    most ``max_samples``: ε = (2/σ)·sqrt(∫dA/L² / (π N)); every ε below it may need more."""
    return 2 / sigma * math.sqrt(surface.inv_lfs_sq_integral / (math.pi * max_samples))


def budget_recommendation(
    quality: QualityParams, surface: SurfaceCounts, max_samples: float
) -> Recommendation:
    """The best proven guarantee within ``max_samples`` samples: the smallest ε whose packing
    count fits (rounded up to the printed digits), since every target's proven ρ_f grows with
    ε; its ρ_f per target is in ``guarantee``.

    Raises
    ------
    InputError
        When even the largest supported ε needs more samples.
    """
    low, high = EPS_RANGE
    eps = printable_eps_up(max(budget_eps(surface, quality.sigma, max_samples), low))
    while packing_count(surface, eps, quality.sigma) > max_samples:  # rounding of the formula
        eps = math.nextafter(eps, math.inf)
    if not eps <= high:
        raise InputError(
            f"{max_samples:.6g} samples are too few for {surface.name}: even eps={high:g} can "
            f"need {packing_count(surface, high, quality.sigma):,.0f}"
        )
    return _recommendation(
        quality,
        surface,
        eps,
        binding_target="budget",
        mode="tight",
        claim=PROVEN,
        per_target={},
        max_samples=max_samples,
    )


def _recommendation(quality, surface, eps, max_samples=None, **choice) -> Recommendation:
    """The recommendation at ``eps``: counts, guarantee, sampler cost and, when the sampler
    cannot build ``eps``, the smallest ε it can (:class:`Fallback`)."""
    cost = sampler_cost(surface, eps, quality.sigma, quality.lipschitz)
    return Recommendation(
        eps=eps,
        ball_radius=quality.delta_ratio * eps * surface.lfs_min,
        min_spacing=quality.sigma * eps * surface.lfs_min,
        samples_low=covering_count(surface, eps),
        samples_high=packing_count(surface, eps, quality.sigma),
        reduction_vs_1_500=(eps / BASELINE_EPS) ** 2,
        feature_samples=feature_counts(surface, eps, quality.sigma),
        guarantee=what_eps_guarantees(quality, eps),
        cost=cost,
        fallback=None if cost is None or cost.samplable else smallest_samplable(quality, surface),
        max_samples=max_samples,
        **choice,
    )


def smallest_samplable(
    quality: QualityParams, surface: SurfaceCounts, lam: float | None = None
) -> Fallback:
    """The smallest ε ``vorobound sample`` builds on ``surface`` (a mesh), and what it
    guarantees; ``lam`` is the Lipschitz constant the lattice uses (default: λ, or 1)."""
    from ..sampling.sampler.cost import smallest_samplable_eps

    if lam is None:
        lam = 1.0 if quality.lipschitz is None else quality.lipschitz
    eps = printable_eps_up(smallest_samplable_eps(surface.inv_lfs_sq_integral, quality.sigma, lam))
    return Fallback(
        eps=eps,
        guarantee=what_eps_guarantees(quality, eps),
        samples_low=covering_count(surface, eps),
        samples_high=packing_count(surface, eps, quality.sigma),
        cost=sampler_cost(surface, eps, quality.sigma, lam),
    )


def guarantee_words(guarantee: GuaranteeAt | None) -> str:
    """What an ε guarantees, for people (ρ_f rounded up: a bound)."""
    if guarantee is None:
        return "no guarantee (no guide triangle exists at this eps)"
    ratio = guarantee.rho_f_ratio
    first = (
        f"R <= {format_up(ratio)}·R̂ (eq. (54))"
        if math.isfinite(ratio)
        else "no ρ_f for eq. (54) (R̂ can be 0)"
    )
    return (
        f"{first}, R − R̂ <= {format_up(guarantee.additive_fraction)}·δL_i, "
        f"R <= {format_up(guarantee.rho_f_55)}·δL_i (eq. (55)); proven, given H3"
    )


def samplable_verdict(rec: Recommendation) -> str:
    """The last line when ``vorobound sample`` cannot build the recommended ε."""
    text = (
        f"`vorobound sample --mesh` cannot build the recommended eps = {format_down(rec.eps)} "
        f"(about {rec.lattice_candidates:.3g} lattice candidates)"
    )
    if rec.fallback is None:
        return text
    return (
        f"{text}; the smallest eps it builds is {format_down(rec.fallback.eps)}, which "
        f"guarantees {guarantee_words(rec.fallback.guarantee)}"
    )


def versus_baseline(reduction: float | None) -> str:
    """Sample count at ε = 1/500 over the count at ε*, in words ("—" when not trusted); a
    saving is never overstated and a cost never understated (:mod:`vorobound.rounding`)."""
    if reduction is None:
        return "—"
    if reduction >= 1:
        return f"{format_down(reduction, 4)}× fewer"
    return f"{format_up(1 / reduction, 4)}× more"
