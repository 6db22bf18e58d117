"""Monte Carlo validation: sampled feasible guide triangles against every bound."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..bounds.audit import audit_chain, exact_quantities
from ..bounds.configurations import sample_feasible
from ..bounds.guarantee import bound_at, for_mode
from ..bounds.params import SamplingParams, Target
from ..checks import checked_count, checked_seed
from ..errors import InputError

MAX_SAMPLES = 2_000_000
"""Most configurations one validation draws (about 1 kB each while they are evaluated)."""


@dataclass(frozen=True)
class LabelAudit:
    """All checks of one printed equation, merged."""

    violations: int
    worst_ratio: float
    """Largest value/bound in the violating direction; above 1 means the step fails."""
    checked: int


@dataclass(frozen=True)
class ValidationReport:
    params: SamplingParams
    samples: int
    seed: int
    lipschitz: float | None
    inequalities: dict[str, LabelAudit]
    """Equation label, e.g. "(49)" → how the printed step fared."""
    modes: dict[str, float]
    """Mode → largest observed (R − R̂)/bound; above 1 means that bound was exceeded."""
    max_radius_gap: float
    """Largest observed R − R̂."""


def validate(
    params: SamplingParams,
    samples: int = 20_000,
    seed: int = 0,
    tight: bool = True,
) -> ValidationReport:
    """Sample feasible configurations (uniform and boundary-biased) and audit every bound.

    Parameters
    ----------
    params : SamplingParams
        ε, σ, δ/ε, L_i, ρ_f, and λ: with it only configurations whose L is λ-Lipschitz
        between the three vertices are sampled. The bounds audited are those on R − R̂ (the
        additive target), whatever ``params.target``.
    samples : int
        Number of feasible configurations.
    seed : int
        Seed of the random generator (the run is deterministic).
    tight : bool
        Also compare against the tight supremum (one optimization).

    References
    ----------
    Eq. (33)–(53).
    """
    samples = checked_count(samples, "samples", 1, MAX_SAMPLES)
    seed = checked_seed(seed)
    params = params.but(target=Target.additive)
    tri = sample_feasible(params, samples, np.random.default_rng(seed))
    if len(tri) < samples:
        raise InputError(
            f"found only {len(tri)} feasible configurations of {samples}; the constraints "
            "leave (almost) no room at these parameters"
        )
    merged: dict[str, LabelAudit] = {}
    for audit in audit_chain(tri, params, "paper"):
        seen = merged.get(audit.label)
        if seen is None:
            merged[audit.label] = LabelAudit(audit.violations, audit.worst_ratio, audit.checked)
        else:
            worst = np.nanmax([seen.worst_ratio, audit.worst_ratio])
            merged[audit.label] = LabelAudit(
                seen.violations + audit.violations, float(worst), seen.checked + audit.checked
            )
    max_gap = float(exact_quantities(tri, params).radius_gap.max())
    names = ("paper", "rigorous", "tight") if tight else ("paper", "rigorous")
    quality = params.quality
    modes = {
        mode: max_gap / bound_at(for_mode(quality, mode).at(params.eps), mode).value
        for mode in names
    }
    return ValidationReport(params, samples, seed, params.lipschitz, merged, modes, max_gap)
