"""``check``/``reconstruct`` of a VoroCrust run, and ``check`` without ``eps``: the parameters a
ball set realizes and the guarantee they give (vorobound.reports.vorocrust, docs/vorocrust.md)."""

from __future__ import annotations

import dataclasses
import os
from pathlib import Path

from ..errors import InputError

SMOOTH = "surface"
"""The stratum the theory covers (smooth patches); corner and edge balls are reported apart."""


def run_shape(run, surface: dict, progress):
    """The surface to measure a run against: the one given, else the run's input mesh."""
    from .surfaces import sample_shape

    if any(surface.get(k) is not None for k in ("sphere", "torus", "mesh")):
        return sample_shape(**surface, required=False, progress=progress)
    if surface.get("lfs") is not None or surface.get("sizing") is not None:
        return sample_shape(mesh=run.mesh, **_mesh_l(surface), progress=progress)
    return sample_shape(mesh=run.mesh, progress=progress)


def _mesh_l(surface: dict) -> dict:
    return {"lfs": surface.get("lfs"), "sizing": surface.get("sizing")}


def read(vorocrust):
    from ..sampling.io.vorocrust import read_run

    run = read_run(vorocrust)
    if run.strata[SMOOTH] is None or len(run.strata[SMOOTH]) < 4:
        raise InputError(
            f"VoroCrust run {vorocrust}: fewer than 4 surface balls (surface_spheres.csv); the "
            "smooth verdict needs them"
        )
    return run


def check_run(
    *,
    eps,
    vorocrust,
    balls,
    surface: dict,
    sigma,
    delta_ratio,
    rho_f,
    lipschitz,
    engine,
    out,
    figure_format,
    seed,
    progress,
    finish,
):
    """``check`` of a VoroCrust run (``vorocrust``) or of ``balls`` without ``eps``;
    ``finish(report, asked, extra, out, figure_format)`` makes the result (api.check's)."""
    from ..bounds.params import QualityParams
    from ..checks import checked_lipschitz
    from ..reports.check import check_balls
    from ..reports.vorocrust import realize, warn_off_surface
    from .result import checked_outputs

    checked_outputs(out, figure_format)
    strata, features = None, {}
    if vorocrust is not None:
        if balls is not None:
            raise InputError("give vorocrust or balls, not both")
        run = read(vorocrust)
        shape = run_shape(run, surface, progress)
        target_balls = run.strata[SMOOTH]
        source = f"{Path(vorocrust).name}/surface_spheres.csv"
        strata = run.counts() | {"seeds": _seed_count(run)}
        shape, features = _smooth_part(run, shape)
        deck = {
            "deck": os.fspath(run.deck.path),
            "values": run.deck.values,
            "ignored_keys": list(run.deck.ignored),
            "input_mesh": os.fspath(run.mesh),
            "sizing_file": run.deck.sizing_file,
        }
    else:
        from ..sampling.io.balls import read_balls
        from .surfaces import sample_shape

        shape = sample_shape(**surface, required=False, progress=progress)
        target_balls = read_balls(balls)
        source = os.path.basename(os.fspath(balls))
        strata = {"balls": len(target_balls)}
        deck = None
    if eps is not None:
        from ..constants import PAPER_DELTA_RATIO, PAPER_SIGMA

        sigma = PAPER_SIGMA if sigma is None else sigma
        delta_ratio = PAPER_DELTA_RATIO if delta_ratio is None else delta_ratio
        lam = checked_lipschitz(1.0 if lipschitz is None else lipschitz)
        params = QualityParams(sigma, delta_ratio, rho_f).at(eps).but(lipschitz=lam)
        report = check_balls(target_balls, params, engine, shape, source, progress)
        extra = {"strata": strata, "feature_strata": features}
        asked = {"seed": None, "engine": engine, "vorocrust": os.fspath(vorocrust)}
        return finish(
            report, asked, extra | ({"vorocrust": deck} if deck else {}), out, figure_format
        )
    if shape is None:
        raise InputError(
            "without eps, the parameters the balls realize need the surface: give sphere, "
            "torus or mesh (or vorocrust, whose deck names the mesh)"
        )
    given = [n for n, v in (("sigma", sigma), ("delta_ratio", delta_ratio)) if v is not None]
    if given or lipschitz is not None:
        raise InputError(
            "without eps, sigma, delta_ratio and lipschitz are inferred from the balls: give "
            "eps too to check at your own values"
        )
    realization = realize(target_balls, shape, engine, rho_f, progress)
    warn_off_surface(realization.measured, target_balls, source)
    target = "ratio"
    check_eps, check_quality = realization.eps, realization.quality
    if check_quality is None:
        raise _not_realized(realization, source)
    proven = realization.rho_f_ratio
    check_rho = proven if proven is not None and proven > 1 else rho_f
    params = check_quality.but(rho_f=check_rho).at(check_eps)
    report = check_balls(target_balls, params, engine, shape, source, progress)
    extra = {
        "realized": realization.realized_json(),
        "guarantee": realization.guarantee_json(target),
        "strata": strata,
        "feature_strata": features,
    }
    if deck:
        extra["vorocrust"] = deck
    asked = {"seed": None, "engine": engine, "balls": None if balls is None else os.fspath(balls)}
    if vorocrust is not None:
        asked["vorocrust"] = os.fspath(vorocrust)
    return finish(report, asked, extra, out, figure_format)


def _not_realized(realization, source):
    from ..errors import NoAdmissibleEps

    detail = realization.failed_detail or {}
    worst = detail.get("worst") or []
    where = ""
    if worst:
        w = worst[0]
        where = f"; worst balls {w['balls']} near ({', '.join(f'{x:.6g}' for x in w['where'])})"
    elif detail.get("where"):
        where = f" at ({', '.join(f'{x:.6g}' for x in detail['where'])})"
    return NoAdmissibleEps(
        f"{source}: no parameters realized: {realization.failed_condition} fails for every "
        f"eps < 1{where}"
    )


def _seed_count(run) -> int | None:
    if run.seeds is None:
        return None
    with open(run.seeds, encoding="utf-8") as handle:
        return max(sum(1 for line in handle if line.strip()) - 1, 0)


def _smooth_part(run, shape):
    """The shape restricted, for coverage, to probes nearer a surface ball than any corner or
    edge ball, and a summary of those feature strata."""
    import numpy as np

    from ..reports.vorocrust import feature_summary

    feature = [run.strata[n] for n in ("corner", "edge") if run.strata[n] is not None]
    summaries = {
        name: feature_summary(run.strata[name], shape)
        for name in ("corner", "edge")
        if run.strata[name] is not None
    }
    if not feature:
        return shape, summaries
    from ..reports.vorocrust import SmoothPart

    centers = np.concatenate([b.centers for b in feature])
    return SmoothPart(shape, run.strata[SMOOTH].centers, centers), summaries


DISTANCE_UNIT = (
    "the local ball radius: distances over the radius of the run's nearest corner, edge or "
    "surface ball (the keys keep reconstruct's *_over_eps_lfs names)"
)
UNIT_EPS = 0.5
"""M̂'s distances are measured over ε·L with ε = UNIT_EPS and L = r/UNIT_EPS, i.e. over r."""


def reconstruct_run(*, vorocrust, surface: dict, seed: int, progress):
    """The report of M̂ of a VoroCrust run: its seeds.csv against its input mesh (or the
    surface given), distances in units of the local ball radius."""
    from ..bounds.params import QualityParams
    from ..reports import reconstruct as workflow
    from ..reports.vorocrust import BallRadiusUnits
    from ..sampling.reconstruct.seeds import read_seed_file

    run = read(vorocrust)
    if run.seeds is None:
        raise InputError(f"VoroCrust run {vorocrust}: no seeds.csv (M̂ is built from the seeds)")
    shape = run_shape(run, surface, progress)
    import numpy as np

    on_surface = [run.strata[n] for n in ("corner", "edge", SMOOTH) if run.strata[n] is not None]
    centers = np.concatenate([b.centers for b in on_surface])
    radii = np.concatenate([b.radii for b in on_surface])
    units = BallRadiusUnits(shape, centers, radii, UNIT_EPS)
    params = QualityParams().at(UNIT_EPS)
    report = workflow.reconstruct_seeds(read_seed_file(run.seeds), units, params, seed, progress)
    return dataclasses.replace(report, eps=None, params=None)
