"""``vorobound advise``: sampling parameters and expected sample counts for a surface."""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from ..bounds.params import QualityParams, checked_modes, checked_targets
from ..checks import checked_number
from ..constants import PAPER_DELTA_RATIO, PAPER_RHO_F, PAPER_SIGMA
from ..errors import InputError
from ..progress import Progress

if TYPE_CHECKING:
    from ..mesh import TriangleMesh
    from ..reports.advisor import Advice
    from ..sampling.surfaces.base import SurfaceCounts
from .arguments import checked_arguments
from .result import Result, params_json

MAX_SAMPLES_LIMIT = 1e15
"""Largest sample budget accepted (far beyond any sample that fits in memory)."""
H3_ROUTE_STATEMENT = "H3 alone gives R <= rho_f*delta*L_i (eq. (55)); not eq. (54)"


@dataclass(frozen=True, repr=False)
class AdviseResult(Result):
    """ε* per mode and target, what it means on the surface, and the ε to use."""

    command = "advise"
    eps: float | None
    """The recommended ε (None: no target asked for has a proven or certified ε*)."""
    claim: str | None
    ball_radius: float | None
    samples_low: float | None
    samples_high: float | None
    surface_name: str | None
    lfs_source: str | None
    advice: Advice = field(repr=False)
    """:class:`vorobound.reports.advisor.Advice`."""
    surface: SurfaceCounts | None = field(repr=False)
    quality: QualityParams = field(repr=False)
    modes: tuple[str, ...] = field(repr=False)
    targets: tuple[str, ...] = field(repr=False)
    extra: dict = field(repr=False, default_factory=dict)
    """More of the JSON (``vorocrust``: the deck written and what it sets)."""
    max_samples: float | None = field(default=None, repr=False)

    @property
    def ok(self) -> bool:
        """False when ``vorobound sample`` cannot build the recommended ε (exit code 1)."""
        rec = self.advice.recommendation
        return rec is None or rec.samplable is not False

    @property
    def verdict(self) -> str:
        if self.ok:
            return ""
        from ..reports.advisor import samplable_verdict

        rec = self.advice.recommendation
        assert rec is not None  # not ok: a recommendation the sampler cannot make
        return samplable_verdict(rec)

    def payload(self) -> dict:
        from ..reports.advisor import GUARANTEE

        surface = self.surface
        counted = surface is not None
        entries = []
        for a in self.advice.rows:
            entries.append(
                {
                    "mode": a.mode,
                    "target": a.target,
                    "eps_star": a.eps_star,
                    "claim": a.claim,
                    "method": a.method,
                    "proven_lower_bound": a.proven_lower_bound,
                    "ball_radius": a.ball_radius,
                    "min_spacing": a.min_spacing,
                    "samples_low": a.samples_low if counted else None,
                    "samples_high": a.samples_high if counted else None,
                    "reduction_vs_1_500": a.reduction_vs_1_500,
                    "constraint_set": a.constraint_set,
                    "note": a.note,
                    "guarantee": guarantee_json(a.guarantee),
                    "sampler_cost": cost_json(a.cost),
                }
            )
        rec = self.advice.recommendation
        recommendation = None
        if rec is not None:
            features = rec.feature_samples
            recommendation = {
                "eps": rec.eps,
                "binding_target": rec.binding_target,
                "mode": rec.mode,
                "claim": rec.claim,
                "guarantees": list(rec.guarantees),
                "eps_per_target": rec.per_target,
                "ball_radius": rec.ball_radius,
                "min_spacing": rec.min_spacing,
                "samples_low": rec.samples_low if counted else None,
                "samples_high": rec.samples_high if counted else None,
                "reduction_vs_1_500": rec.reduction_vs_1_500,
                "feature_samples_low": None if features is None else features[0],
                "feature_samples_high": None if features is None else features[1],
                "lattice_candidates": rec.lattice_candidates,
                "samplable": rec.samplable,
                "rho_f_proven": rec.rho_f_proven,
                "guarantee": guarantee_json(rec.guarantee),
                "sampler_cost": cost_json(rec.cost),
                "max_samples": rec.max_samples,
                "smallest_samplable": fallback_json(rec.fallback, counted),
            }
        h3 = self.advice.h3_route
        surface_info = None
        if surface is not None:
            surface_info = {
                "name": surface.name,
                "area": surface.area,
                "lfs_min": surface.lfs_min,
                "inv_lfs_sq_integral": surface.inv_lfs_sq_integral,
                "counts_exact": surface.exact,
                "lfs_source": self.lfs_source,
                "feature_inv_lfs": surface.feature_inv_lfs,
            }
        params = params_json(self.quality, mode=list(self.modes))
        params["target"] = list(self.targets)
        params["max_samples"] = self.max_samples
        return self.extra | {
            "params": params,
            "surface": surface_info,
            "recommendation": recommendation,
            "modes": entries,
            "h3_route": {
                "eps_star": h3.eps_star,
                "claim": h3.claim,
                "premise": h3.premise,
                "statement": H3_ROUTE_STATEMENT,
            },
            "guarantee": GUARANTEE,
            "ok": self.ok,
        }


@checked_arguments
def advise(
    *,
    rho_f: float = PAPER_RHO_F,
    sigma: float = PAPER_SIGMA,
    delta_ratio: float = PAPER_DELTA_RATIO,
    lipschitz: float | None = None,
    mode: str | Sequence[str] = "rigorous,tight",
    target: str | Sequence[str] = "additive,ratio",
    area: float | None = None,
    lfs: float | None = None,
    sphere: float | None = None,
    torus: Sequence[float] | None = None,
    mesh: str | os.PathLike | TriangleMesh | None = None,
    sizing: str | os.PathLike | None = None,
    vorocrust: str | os.PathLike | None = None,
    max_samples: float | None = None,
    progress: Progress | None = None,
) -> AdviseResult:
    """Largest ε per mode and target, ball radius δ·L, spacing σ·ε·L and sample counts for a
    surface, and the ε to use.

    The recommendation is the most conservative proven or certified ε* among the targets asked
    for, and says which target binds. Sample counts are a covering lower and a packing upper
    estimate (exact bounds on a sphere; docs/advisor.md). Without a surface, lengths are per
    unit L and there are no counts. A mesh without ``lfs`` or ``sizing`` has its L estimated
    (as by :func:`vorobound.lfs`), and the result says so. ``vorocrust`` (a folder, with
    ``mesh``) receives a VoroCrust run directory that samples the part at the recommended ε:
    the part as OBJ, vc.in and sizing.csv (docs/vorocrust.md), written as one set.

    Each ε comes with what it guarantees (the smallest proven ρ_f per target) and, on a mesh,
    the estimated cost of ``vorobound sample``. ``max_samples`` (needs a surface) makes the
    recommendation the best proven guarantee whose packing count is at most that many samples.
    When ``vorobound sample`` cannot build the recommended ε, the result names the smallest ε
    it can and what that guarantees, and ``ok`` is False.
    """
    from ..reports.advisor import advise as run
    from ..sampling.surfaces.base import planar_area
    from .surfaces import Surface, count_surface

    if max_samples is not None:
        max_samples = checked_number(max_samples, "max_samples", 1.0, MAX_SAMPLES_LIMIT)
    if vorocrust is not None:
        _checked_deck_folder(vorocrust, mesh)
    modes = tuple(m.value for m in checked_modes(mode))
    targets = tuple(t.value for t in checked_targets(target))
    quality = QualityParams(sigma, delta_ratio, rho_f, lipschitz=lipschitz)
    surface, lfs_source = count_surface(
        Surface(sphere, torus, mesh, lfs, sizing), area=area, progress=progress
    )
    if max_samples is not None and surface is None:
        raise InputError("--max-samples needs a surface (--sphere, --torus, --mesh or --area)")
    basis = surface or planar_area(1.0, 1.0)
    advice = run(
        quality,
        basis,
        list(modes),
        progress=progress,
        targets=list(targets),
        max_samples=max_samples,
    )
    rec = advice.recommendation
    counted = rec if surface is not None else None
    result = AdviseResult(
        eps=None if rec is None else rec.eps,
        claim=None if rec is None else rec.claim,
        ball_radius=None if rec is None else rec.ball_radius,
        samples_low=None if counted is None else counted.samples_low,
        samples_high=None if counted is None else counted.samples_high,
        surface_name=None if surface is None else surface.name,
        lfs_source=lfs_source,
        advice=advice,
        surface=surface,
        quality=quality,
        modes=modes,
        targets=targets,
        max_samples=max_samples,
    )
    if vorocrust is None:
        return result
    from ..files import write_set
    from .vorocrust import deck_files

    writers, chosen = deck_files(
        result,
        mesh=mesh,
        lfs=lfs,
        sizing=sizing,
        lipschitz=lipschitz,
        vorocrust=vorocrust,
        progress=progress,
    )
    write_set(writers)
    chosen["written"] = [os.fspath(p) for p in writers]
    return dataclasses.replace(result, extra={"vorocrust": chosen})


def _checked_deck_folder(vorocrust, mesh) -> None:
    """Refuse, before any work, a deck folder that cannot receive the run directory's files."""
    from ..files import checked_destination, checked_folder
    from .vorocrust import DECK_NAME, SIZING_NAME

    if mesh is None:
        raise InputError("vorocrust writes a deck for a part: give mesh too")
    folder = checked_folder(vorocrust)
    if folder.is_dir():
        for name in (DECK_NAME, SIZING_NAME):
            checked_destination(folder / name)


def guarantee_json(guarantee) -> dict | None:
    """What an ε guarantees (:class:`vorobound.bounds.guarantee_at.GuaranteeAt`) as JSON."""
    if guarantee is None:
        return None
    names = ("eps", "rho_f_ratio", "rho_f_additive", "additive_fraction", "rho_f_55", "rho_f_h3")
    return {n: getattr(guarantee, n) for n in names} | {
        "claim": "proven",
        "status": guarantee.status,
    }


def cost_json(cost) -> dict | None:
    """The sampler's estimated cost (:class:`vorobound.sampling.sampler.cost.SamplerCost`)."""
    if cost is None:
        return None
    names = ("memory_bytes", "cpu_seconds", "samplable")
    return (
        {"lattice_candidates": cost.candidates}
        | {n: getattr(cost, n) for n in names}
        | {"claim": "numerical"}
    )


def fallback_json(fallback, counted: bool) -> dict | None:
    """The smallest samplable ε and its guarantee (None when the recommendation is samplable)."""
    if fallback is None:
        return None
    return {
        "eps": fallback.eps,
        "rho_f_proven": None if fallback.guarantee is None else fallback.guarantee.rho_f_ratio,
        "guarantee": guarantee_json(fallback.guarantee),
        "samples_low": fallback.samples_low if counted else None,
        "samples_high": fallback.samples_high if counted else None,
        "sampler_cost": cost_json(fallback.cost),
    }
