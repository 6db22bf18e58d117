"""Every API function refuses a wrong type for each keyword with a VoroboundError subclass that
names the keyword (the hostile pass of issue 34 found bare TypeErrors from deep inside:
``check(balls=123)``, ``lfs(mesh=None)``, ``sample(output=None)``; and ``check(out='')`` wrote
its outputs into the working folder, where the command line refuses ``--out ""``)."""

import inspect

import pytest

import vorobound
from vorobound.errors import VoroboundError

FUNCTIONS = {
    "solve": {},
    "bound": {"eps": 0.005},
    "sweep": {},
    "advise": {},
    "certify": {},
    "check_certificate": {"path": "missing.json"},
    "sample": {"eps": 0.3, "output": "o.csv", "sphere": 1.0},
    "check": {"eps": 0.3, "sphere": 1.0},
    "reconstruct": {"eps": 0.3, "sphere": 1.0},
    "lfs": {"mesh": "missing.obj"},
    "triangle": {"edges": [3.0, 4.0, 5.0]},
    "validate": {"eps": 0.005, "samples": 10},
    "figure": {"out": "figures"},
    "reproduce": {"out": "figures"},
    "cheng": {"alpha": 0.3},
}


def _cases():
    """(function, keyword, wrong value): values no keyword takes, and per kind of keyword
    the values of the other kinds."""
    for name in FUNCTIONS:
        for parameter in inspect.signature(getattr(vorobound, name)).parameters.values():
            kind = str(parameter.annotation)
            wrong = [object(), b"x"]
            if "PathLike" in kind:
                wrong += [123, 1.5, [1.0], ""]
            if "Progress" in kind:
                wrong += ["abc", 1]
            if kind in ("float", "float | None", "int", "int | None"):
                wrong += ["abc", [1.0], {"a": 1}]
            if kind.startswith("bool"):
                wrong += ["yes", 2]
            if kind.startswith("Sequence"):
                wrong += [5, "abc"]
            if parameter.default is inspect.Parameter.empty:
                wrong.append(None)
            for value in wrong:
                yield pytest.param(
                    name, parameter.name, value, id=f"{name}-{parameter.name}-{value!r:.12}"
                )


@pytest.mark.parametrize(("name", "keyword", "value"), list(_cases()))
def test_a_wrong_type_is_a_vorobound_error_naming_the_keyword(
    name, keyword, value, tmp_path, monkeypatch
):
    monkeypatch.chdir(tmp_path)
    arguments = FUNCTIONS[name] | {keyword: value}
    with pytest.raises(VoroboundError, match=keyword):
        getattr(vorobound, name)(**arguments)
    assert not any(tmp_path.iterdir()), "nothing is written before the arguments are checked"


@pytest.mark.parametrize(
    "call",
    [
        {"eps": 0.3, "balls": 123},
        {"eps": 0.3, "sphere": 1.0, "out": ""},
        {"eps": 0.3, "sphere": 1.0, "torus": 5},
    ],
)
def test_check_refuses_what_the_command_line_refuses(call, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(VoroboundError):
        vorobound.check(**call)
    assert not any(tmp_path.iterdir())


def test_lfs_and_sample_refuse_a_missing_path():
    with pytest.raises(VoroboundError, match="mesh must be a path"):
        vorobound.lfs(mesh=None)
    with pytest.raises(VoroboundError, match="output must be a path"):
        vorobound.sample(eps=0.3, sphere=1.0, output=None)
