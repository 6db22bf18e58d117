"""Each command declared once (issue 30): the CLI's choices are the library's enums, shared
options are declared in one group, a command hands its options to its API function by name,
and "no ε*" and the empty constraint set have one representation each."""

import json

import numpy as np
import pytest
import typer

from vorobound.api.result import FigureFormat, TableFormat
from vorobound.api.surfaces import SURFACE_FIELDS
from vorobound.bounds.params import Mode, Target, TightMethod
from vorobound.cli import app
from vorobound.cli.command import invoke
from vorobound.cli.options import (
    EngineChoice,
    MethodChoice,
    ModeChoice,
    QualityOptions,
    SurfaceOptions,
    TableChoice,
    TargetChoice,
)
from vorobound.errors import EmptyConstraintSet, NoAdmissibleEps, NoCrossing
from vorobound.sampling.guides.engines import Engine


def _params(command: str) -> dict:
    click_command = typer.main.get_command(app).commands[command]
    return {p.name: p for p in click_command.params}


def test_the_choices_are_the_librarys_enums(run_cli):
    assert (ModeChoice, TargetChoice, MethodChoice) == (Mode, Target, TightMethod)
    assert (EngineChoice, TableChoice) == (Engine, TableFormat)
    for option, enum in (
        ("--engine", Engine),
        ("--table", TableFormat),
        ("--figure-format", FigureFormat),
    ):
        code, out, err = run_cli("check", "--eps", "0.3", "--sphere", "1", option, "bogus")
        assert code == 2 and not out and len(err.strip().splitlines()) == 1
        assert all(repr(e.value) in err or e.value in err for e in enum), err


@pytest.mark.parametrize("command", ["sample", "check", "reconstruct", "advise"])
def test_the_surface_options_are_one_group_in_every_command(command):
    names = list(_params(command))
    at = names.index("sphere")
    assert tuple(names[at : at + len(SURFACE_FIELDS)]) == SURFACE_FIELDS
    assert tuple(f for f in SurfaceOptions.__dataclass_fields__) == SURFACE_FIELDS


@pytest.mark.parametrize("command", ["bounds", "solve", "figure", "reproduce", "validate"])
def test_the_quality_options_are_one_group(command):
    names = list(_params(command))
    group = tuple(QualityOptions.__dataclass_fields__)
    at = names.index(group[0])
    assert tuple(names[at : at + len(group)]) == group


class _Done:
    ok = True
    verdict = ""

    def to_dict(self):
        return {"done": True}


def test_invoke_hands_the_options_over_by_name(capsys):
    seen = {}

    def run(*, torus, sphere, mesh, lfs, sizing, mode, tight, sigma, delta_ratio, rho_f):
        seen.update(locals())
        return _Done()

    options = {
        "surface": SurfaceOptions(torus="3,1,y"),
        "mode": Mode.rigorous,
        "no_tight": True,
        "quality": QualityOptions(sigma=0.5),
        "as_json": True,
    }
    assert invoke(run, print, options) == 0
    assert json.loads(capsys.readouterr().out) == {"done": True}
    assert seen["torus"] == [3.0, 1.0, "y"] and seen["sphere"] is None
    assert seen["mode"] == "rigorous" and type(seen["mode"]) is str
    assert seen["tight"] is False and seen["sigma"] == 0.5


def test_no_eps_star_is_one_family_of_errors_and_the_batch_codes_name_it():
    from vorobound.bounds.eps_star import NO_EPS_STAR, STATUS_REASONS, solve_eps_star_batch
    from vorobound.bounds.guarantee import eps_star
    from vorobound.bounds.params import QualityParams

    assert NO_EPS_STAR == (NoAdmissibleEps, NoCrossing, EmptyConstraintSet)
    assert STATUS_REASONS == {k + 1: e.reason for k, e in enumerate(NO_EPS_STAR)}
    # σ = 1.75 > √3: the set is empty below ε = 0.0103, and ρ_f = 1 + 1e-7 is exceeded there.
    _, status = solve_eps_star_batch(
        np.array([1.75]), np.array([2.0]), np.array([1 + 1e-7]), "rigorous"
    )
    with pytest.raises(NoAdmissibleEps) as raised:
        eps_star(QualityParams(1.75, 2.0, 1 + 1e-7, target="additive"), "rigorous", "auto", None)
    assert type(raised.value) is NO_EPS_STAR[int(status[0]) - 1]


def test_the_empty_constraint_set_is_one_error_everywhere():
    from vorobound.bounds.tight.closed_form import tight_supremum_closed_form
    from vorobound.bounds.tight.ratio_form import ratio_supremum_closed_form

    for supremum in (tight_supremum_closed_form, ratio_supremum_closed_form):
        with pytest.raises(EmptyConstraintSet, match="no feasible guide triangle"):
            supremum(0.01, 1.9, 2.0)
