"""``vorobound advise``: sampling parameters and expected sample counts for a surface."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

from ..constants import PAPER_DELTA_RATIO, PAPER_RHO_F, PAPER_SIGMA
from ..rounding import format_down
from .command import grouped, invoke
from .options import (
    CountedSurfaceOptions,
    DeltaRatio,
    Json,
    Lipschitz,
    ModesOpt,
    RhoF,
    Sigma,
    TargetsOpt,
    parse_modes,
    parse_targets,
)

if TYPE_CHECKING:
    from ..api.advise import AdviseResult
from .render import print_footer, print_table

DECK = (
    "With --mesh: write DIR/vc.in, DIR/sizing.csv and the part as OBJ, so that "
    "`vc_mesh -vc vc.in` run in DIR samples at the recommended ε (radii ε·L/β, β = "
    "VoroCrust's coverage factor; LIP_CONST, R_MAX, VC_ANGLE from L; docs/vorocrust.md "
    "says what vc_mesh promises and what to check after)."
)
"""--vorocrust of advise: the deck for vc_mesh."""


@grouped
def advise(
    rho_f: RhoF = PAPER_RHO_F,
    sigma: Sigma = PAPER_SIGMA,
    delta_ratio: DeltaRatio = PAPER_DELTA_RATIO,
    lipschitz: Lipschitz = None,
    mode: ModesOpt = "rigorous,tight",
    target: TargetsOpt = "additive,ratio",
    area: Annotated[
        float | None, typer.Option("--area", metavar="AREA", help="Surface area (with --lfs).")
    ] = None,
    surface: CountedSurfaceOptions = CountedSurfaceOptions(),
    vorocrust: Annotated[Path | None, typer.Option("--vorocrust", metavar="DIR", help=DECK)] = None,
    max_samples: Annotated[
        float | None,
        typer.Option(
            "--max-samples",
            metavar="N",
            help="Sample budget: recommend the best proven guarantee (smallest proven ρ_f) "
            "whose packing count is at most N samples (needs a surface).",
        ),
    ] = None,
    as_json: Json = False,
) -> int:
    """Largest ε per mode and target, ball radius δ·L, spacing σ·ε·L and sample counts for a
    surface, and the ε to use.

    The recommendation is the most conservative proven or certified ε* among the targets asked
    for (default: both), and says which target binds. Sample counts are a covering lower and a
    packing upper estimate (exact bounds on a sphere; docs/advisor.md). Each row says how strong
    its ε* is: proven, certified, numerical or invalid. Each ε comes with what it guarantees
    (the smallest proven ρ_f per target) and, on a mesh, what `vorobound sample` would cost.
    Exit code 1 when `vorobound sample` cannot build the recommended ε; the last line then
    names the smallest ε it can and what that guarantees. Python: vorobound.advise(...).
    """
    return invoke("advise", _show, locals(), mode=parse_modes(mode), target=parse_targets(target))


def _show(result) -> None:
    _show_advice(result)
    deck = result.to_dict().get("vorocrust")
    if deck:
        print(
            f"VoroCrust deck for eps = {deck['eps']:g}: R_MAX = {deck['R_MAX']:.6g}, LIP_CONST = "
            f"{deck['LIP_CONST']:.6g}, VC_ANGLE = {deck['VC_ANGLE']:g}, "
            f"{deck['sizing_rows']:,} sizing rows"
        )
        for path in deck["written"]:
            print(f"wrote {path}")


def _show_advice(result: AdviseResult) -> None:
    from ..reports.advisor import GUARANTEE, guarantee_words, versus_baseline

    entries, surface, h3 = result.advice.rows, result.surface, result.advice.h3_route
    rec = result.advice.recommendation
    title = "Sampling advice" + (f" for {surface.name}" if surface else " (lengths per unit L)")
    table = [
        (
            e.mode,
            e.target,
            format_down(e.eps_star),
            e.claim,
            format_down(e.ball_radius),
            format_down(e.min_spacing),
            "—"
            if surface is None or e.samples_low is None
            else f"{e.samples_low:,.0f} – {e.samples_high:,.0f}",
            versus_baseline(e.reduction_vs_1_500),
        )
        for e in entries
    ]
    table.append(("H3 alone", "(55) only", format_down(h3.eps_star), "given H3", "", "", "", "—"))
    print_table(
        title,
        (
            "mode",
            "target",
            "ε*",
            "claim",
            "ball radius δL",
            "spacing σεL",
            "samples (low–high)",
            "vs 1/500",
        ),
        table,
    )
    _budget_table(result)
    for e in entries:
        if e.note:
            print_footer(f"no ε* for {e.mode}, target {e.target}: {e.note}")
    if rec is None:
        print("recommended ε: none (no target asked for has a proven or certified ε*)")
    else:
        counts = (
            "" if surface is None else f", {rec.samples_low:,.0f} – {rec.samples_high:,.0f} samples"
        )
        if rec.max_samples is None:
            why = f"{rec.claim}; {rec.mode}, binding target {rec.binding_target}"
        else:
            why = f"the best proven guarantee within {rec.max_samples:,.0f} samples"
        print_footer(
            f"recommended ε = {format_down(rec.eps)} ({why}): ball radius "
            f"{format_down(rec.ball_radius)}{counts}, "
            f"{versus_baseline(rec.reduction_vs_1_500)} samples than ε = 1/500"
        )
        print_footer(f"  for every guide triangle, given H3, it gives {rec.guarantee_statement}")
        print_footer(f"  it guarantees {guarantee_words(rec.guarantee)}")
    if rec is not None and surface is not None:
        for line in _sampler_lines(rec):
            print_footer(line)
    if surface is not None:
        print_footer(f"local feature size L: {result.lfs_source}")
    print_footer(GUARANTEE)


def _budget_table(result) -> None:
    """Per row: what its ε* costs (samples, the sampler's estimate) and guarantees."""
    from ..rounding import format_down, format_up

    rows = [a for a in result.advice.rows if a.eps_star is not None]
    if not rows:
        return
    table = []
    for a in rows:
        g, cost = a.guarantee, a.cost
        table.append(
            (
                a.mode,
                a.target,
                format_down(a.eps_star),
                "—" if result.surface is None else f"{a.samples_high:,.0f}",
                "—" if cost is None else _memory(cost.memory_bytes),
                "—" if cost is None else _duration(cost.cpu_seconds),
                "—" if cost is None else ("yes" if cost.samplable else "no"),
                "n/a" if g is None else format_up(g.rho_f_ratio),
                "n/a" if g is None else format_up(g.rho_f_additive),
                "n/a" if g is None else format_up(g.rho_f_55),
            )
        )
    print_table(
        "What each ε* costs and guarantees (ρ_f: smallest proven, given H3)",
        (
            "mode",
            "target",
            "ε*",
            "samples (high)",
            "sampler memory",
            "sampler CPU",
            "samplable",
            "ρ_f (54) ratio",
            "ρ_f additive",
            "ρ_f (55)",
        ),
        table,
    )


def _memory(size: float) -> str:
    return f"{size / 1e9:.3g} GB" if size >= 1e9 else f"{size / 1e6:.3g} MB"


def _duration(seconds: float) -> str:
    if seconds >= 3600:
        return f"{seconds / 3600:.3g} h"
    return f"{seconds / 60:.3g} min" if seconds >= 60 else f"{seconds:.3g} s"


def _sampler_lines(rec) -> list[str]:
    """What the counts include, and whether `vorobound sample` can make this sample."""
    from ..reports.advisor import guarantee_words
    from ..rounding import format_down

    lines = []
    if rec.feature_samples is not None:
        low, high = rec.feature_samples
        lines.append(
            f"  of these, {low:,.0f} – {high:,.0f} on the sharp features (sampled first, as "
            "VoroCrust protects them)"
        )
    if rec.lattice_candidates is not None:
        from ..sampling.sampler.slabs import MAX_EXPECTED_CANDIDATES as MAX_CANDIDATES

        cost = rec.cost
        if rec.samplable:
            lines.append(
                f"  `vorobound sample --mesh` at this ε: about {rec.lattice_candidates:.3g} "
                f"plain-lattice candidates (at most {MAX_CANDIDATES:.0e}; the slab sampler makes "
                f"about a quarter), about {_memory(cost.memory_bytes)} and "
                f"{_duration(cost.cpu_seconds)} CPU (estimates)"
            )
        else:
            lines.append(
                f"  `vorobound sample --mesh` cannot make this sample: it needs about "
                f"{rec.lattice_candidates:.3g} lattice candidates, more than the "
                f"{MAX_CANDIDATES:.0e} it builds (any smaller ε needs more); the counts stand "
                "for any VoroCrust sampler"
            )
            back = rec.fallback
            if back is not None:
                lines.append(
                    f"  the smallest ε it builds: {format_down(back.eps)} "
                    f"({back.samples_low:,.0f} – {back.samples_high:,.0f} samples, about "
                    f"{_memory(back.cost.memory_bytes)} and {_duration(back.cost.cpu_seconds)} "
                    f"CPU), which guarantees {guarantee_words(back.guarantee)}"
                )
    return lines
