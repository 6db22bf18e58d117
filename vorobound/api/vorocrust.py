"""``check``/``reconstruct`` of a VoroCrust run, and ``check`` without ``eps``: the parameters a
ball set realizes and the guarantee they give (vorobound.reports.vorocrust, docs/vorocrust.md)."""

from __future__ import annotations

import dataclasses
import math
import os
from pathlib import Path

from ..errors import InputError

SMOOTH = "surface"
"""The stratum the theory covers (smooth patches); corner and edge balls are reported apart."""


def run_shape(run, surface: dict, progress):
    """The surface to measure a run against: the one given, else the run's input mesh."""
    from .surfaces import Surface

    if any(surface.get(k) is not None for k in ("sphere", "torus", "mesh")):
        return Surface(**surface).shape(required=False, progress=progress)
    if surface.get("lfs") is not None or surface.get("sizing") is not None:
        return Surface(mesh=run.mesh, **_mesh_l(surface)).shape(progress=progress)
    return Surface(mesh=run.mesh).shape(progress=progress)


def _mesh_l(surface: dict) -> dict:
    return {"lfs": surface.get("lfs"), "sizing": surface.get("sizing")}


def read(vorocrust):
    from ..sampling.io.vorocrust import read_run

    run = read_run(vorocrust)
    surface = run.strata[SMOOTH]
    if surface is None or len(surface) < 4:
        raise InputError(
            f"VoroCrust run {vorocrust}: fewer than 4 surface balls (surface_spheres.csv); the "
            "smooth verdict needs them"
        )
    _warn_above_r_max(run)
    return run


def _warn_above_r_max(run) -> None:
    """Warn when a ball is larger than the deck's R_MAX (vc_mesh caps every radius by it):
    the deck read is then not the one that made the balls."""
    from ..errors import warn_once

    r_max = run.deck.values["R_MAX"]
    largest = max(float(b.radii.max()) for b in run.strata.values() if b is not None)
    if largest > r_max * (1 + 1e-9):
        warn_once(
            f"VoroCrust run {run.folder}: balls up to radius {largest:.6g} exceed the deck's "
            f"R_MAX = {r_max:g} (vc_mesh caps every radius by it): is {run.deck.path.name} "
            "the deck of this run?"
        )


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
        from .surfaces import Surface

        shape = Surface(**surface).shape(required=False, progress=progress)
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
    if check_quality is None or check_eps is None:
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
    with open(run.seeds, "rb") as handle:  # a count only: bytes that are not UTF-8 do not matter
        return sum(_numeric_row(line) for line in handle)


def _numeric_row(line: bytes) -> bool:
    """A row of numbers (not blank, not a header): its first cell is a number."""
    first = line.replace(b";", b",").replace(b"\t", b",").split(b",")[0].split()
    try:
        return bool(first) and math.isfinite(float(first[0]))
    except ValueError:
        return False


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
    seeds = read_seed_file(run.seeds)  # refused before the surface's work
    shape = run_shape(run, surface, progress)
    import numpy as np

    on_surface = [run.strata[n] for n in ("corner", "edge", SMOOTH) if run.strata[n] is not None]
    centers = np.concatenate([b.centers for b in on_surface])
    radii = np.concatenate([b.radii for b in on_surface])
    units = BallRadiusUnits(shape, centers, radii, UNIT_EPS)
    params = QualityParams().at(UNIT_EPS)
    report = workflow.reconstruct_seeds(seeds, units, params, seed, progress)
    return dataclasses.replace(report, eps=None, params=None)


VC_COVERAGE_RATIO = 0.4
"""vc_mesh's coverage radius ratio α for surface balls (hard-coded in its sampler, commit
b5e0859): a surface point counts as covered within β·r of a ball centre, β = sqrt(1 − α²),
and a new centre stays at least β·r from the others."""
SIZING_NAME = "sizing.csv"
DECK_NAME = "vc.in"


SIZING_ROWS = 20_000
"""Random surface points in the sizing file (besides the mesh's vertices)."""
SIZING_PROBES = 4
"""Probes per row that find how far each row's nearest-row region reaches."""


def sizing_rows(shape, lam: float, seed: int = 0):
    """Rows (points) and a safe L at each: vc_mesh caps a radius by the size of the *nearest*
    row, so each row carries min over its nearest-row region of L, bounded below by L(row) −
    λ·h, h the farthest probe that has the row as its nearest (λ the Lipschitz constant of L)."""
    import numpy as np
    from scipy.spatial import cKDTree

    rng = np.random.default_rng([seed, 31])
    extra, _ = shape.random_points(SIZING_ROWS, rng)
    points = np.unique(np.concatenate([shape.vertices, extra]), axis=0)
    values = shape.closest(points).lfs
    probes, _ = shape.random_points(SIZING_PROBES * len(points), rng)
    reach = np.zeros(len(points))
    dist, nearest = cKDTree(points).query(probes)
    np.maximum.at(reach, nearest, dist)
    return points, np.maximum(values - lam * reach, 0.5 * values)


def deck_files(advice, *, mesh, lfs, sizing, lipschitz, vorocrust, progress) -> tuple[dict, dict]:
    """The files of a VoroCrust run directory that samples the part at the advised ε: the
    part as OBJ, ``sizing.csv`` (r = ε·L/β at the mesh's vertices and face centroids) and
    ``vc.in``; returns the writers by path and what was chosen (docs/vorocrust.md)."""
    import math

    from ..files import ensure_folder
    from ..sampling.io.vorocrust import deck_text, obj_writer, sizing_writer
    from ..sampling.lfs.estimate import SHARP_ANGLE
    from .surfaces import Surface

    if mesh is None:
        raise InputError("vorocrust writes a deck for a part: give mesh too")
    if advice.eps is None:
        raise InputError("no proven or certified eps to hand to vc_mesh (see the table)")
    folder = ensure_folder(vorocrust)
    shape = Surface(mesh=mesh, lfs=lfs, sizing=sizing).shape(required=False, progress=progress)
    beta = math.sqrt(1 - VC_COVERAGE_RATIO**2)
    eps = advice.eps
    lam = 1.0 if lipschitz is None else float(lipschitz)
    lam = min(lam, float(getattr(shape, "lipschitz", lam) or lam))
    points, lfs_values = sizing_rows(shape, lam)
    sizes = eps * lfs_values / beta
    lip_const = lam * eps / beta
    r_max = float(sizes.max())
    stem = Path(os.fspath(mesh)).stem.replace(" ", "_") or "part"
    obj = f"{stem}.obj"
    text = deck_text(
        input_mesh=obj,
        sizing_file=SIZING_NAME,
        r_max=r_max,
        lip_const=lip_const,
        vc_angle=SHARP_ANGLE,
        comments=(
            f"written by vorobound advise: eps = {eps!r} ({advice.claim}), "
            f"radius = eps*L/{beta:.6f} (vc_mesh covers within {beta:.6f} r)",
            f"LIP_CONST = lambda*eps/beta with lambda = {lam:g} (the Lipschitz constant of L)",
            "run: vc_mesh -vc vc.in (in this folder); then vorobound check --vorocrust .",
        ),
    )
    writers = {
        folder / obj: obj_writer(shape.vertices, shape.triangles),
        folder / SIZING_NAME: sizing_writer(points, sizes),
        folder / DECK_NAME: lambda path: path.write_text(text, encoding="utf-8"),
    }
    chosen = {
        "folder": os.fspath(folder),
        "eps": eps,
        "delta_ratio_vc": 1 / beta,
        "sigma_vc": 1.0,
        "R_MAX": r_max,
        "LIP_CONST": lip_const,
        "VC_ANGLE": SHARP_ANGLE,
        "sizing_rows": len(sizes),
        "radius_min": float(sizes.min()),
    }
    return writers, chosen
