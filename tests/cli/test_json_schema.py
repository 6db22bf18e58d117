"""Every command's --json output follows docs/schema/vorobound-output.schema.json, carries the
version that made it and its parameters, and equals the Python function's to_dict()."""

import json
from pathlib import Path

import pytest

jsonschema = pytest.importorskip("jsonschema")

import vorobound  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
SCHEMA = json.loads((ROOT / "docs" / "schema" / "vorobound-output.schema.json").read_text())
VALIDATOR = jsonschema.Draft202012Validator(SCHEMA)

RUNS = {
    "solve": ["solve", "--lipschitz", "1"],
    "solve-additive": ["solve", "--target", "additive", "--mode", "rigorous"],
    "bounds-tight": ["bounds", "--eps", "0.005"],
    "bounds-chain": ["bounds", "--eps", "0.005", "--mode", "paper", "--target", "additive"],
    "sweep": ["sweep", "--rho-f", "1.2,1.5"],
    "advise": ["advise", "--sphere", "1"],
    "advise-no-surface": ["advise", "--mode", "tight"],
    "certify": ["certify", "--sigma", "1.2", "--delta-ratio", "0.5", "--rho-f", "1.5"],
    "certify-failure": [
        "certify",
        "--sigma",
        "1.2",
        "--delta-ratio",
        "0.5",
        "--rho-f",
        "1.5",
        "--fraction",
        "1.01",
    ],
    "triangle": ["triangle", "-p", "0,0", "-p", "1,0", "-p", "0,1", "-w", "0,0.1,0.2"],
    "triangle-edges": ["triangle", "--edges", "5,4,3", "-w", "0,0.2,0.5"],
    "validate": ["validate", "--eps", "0.0047", "--samples", "500"],
    "cheng": ["cheng", "--alpha", "0.2"],
    "reconstruct": ["reconstruct", "--sphere", "1", "--eps", "0.2"],
    # ε = 0.3, 0.4: both M̂ correct, the same fields as at 0.2, 0.3 with a third of the balls.
    "reconstruct-sweep": ["reconstruct", "--torus", "3,1", "--eps", "0.3,0.4"],
    "reconstruct-repeats": ["reconstruct", "--sphere", "1", "--eps", "0.3", "--repeats", "2"],
    "reconstruct-repeats-sweep": [
        "reconstruct",
        "--sphere",
        "1",
        "--eps",
        "0.3,0.5",
        "--repeats",
        "2",
    ],
}


def _validate(payload: dict) -> None:
    errors = sorted(VALIDATOR.iter_errors(payload), key=lambda e: e.path)
    assert not errors, [f"{list(e.path)}: {e.message}" for e in errors[:5]]
    assert payload["vorobound_version"] == vorobound.__version__
    assert isinstance(payload["params"], dict)


def test_the_schema_is_a_valid_schema():
    jsonschema.Draft202012Validator.check_schema(SCHEMA)


@pytest.mark.parametrize("name", sorted(RUNS))
def test_command_output_follows_the_schema(run_cli, name):
    code, out, err = run_cli(*RUNS[name], "--json")
    assert code in (0, 1), err
    _validate(json.loads(out))


def test_file_outputs_follow_the_schema(run_cli, tmp_path):
    code, out, err = run_cli(
        "sample", "--sphere", "1", "--eps", "0.2", "-o", str(tmp_path / "s.npz"), "--json"
    )
    assert code == 0, err
    _validate(json.loads(out))
    code, out, err = run_cli(
        "check",
        "--balls",
        str(tmp_path / "s.npz"),
        "--sphere",
        "1",
        "--eps",
        "0.2",
        "--out",
        str(tmp_path / "out"),
        "--json",
    )
    assert code in (0, 1), err
    printed = json.loads(out)
    _validate(printed)
    written = json.loads((tmp_path / "out" / "summary.json").read_text())
    _validate(written)
    assert written == printed  # summary.json is the command's JSON
    code, out, err = run_cli(
        "check",
        "--balls",
        str(tmp_path / "s.npz"),
        "--eps",
        "0.2",
        "--workers",
        "1",
        "--out",
        str(tmp_path / "tiled"),
        "--table",
        "csv",
        "--json",
    )
    assert code in (0, 1), err
    tiled = json.loads(out)
    _validate(tiled)
    assert tiled["n_guide_triangles"] == printed["n_guide_triangles"]
    assert json.loads((tmp_path / "tiled" / "summary.json").read_text()) == tiled


def test_a_broken_object_is_rejected():
    """The schema can fail: a check object without its counts does not pass."""
    payload = {"vorobound_version": "0.3.0", "command": "check", "params": {}}
    assert list(VALIDATOR.iter_errors(payload))


@pytest.mark.parametrize(
    "function, kwargs, argv",
    [
        (vorobound.solve, {"mode": "tight"}, ["solve"]),
        (vorobound.bound, {"eps": 0.005}, ["bounds", "--eps", "0.005"]),
        (
            vorobound.triangle,
            {"edges": (5, 4, 3), "weights": (0, 0.2, 0.5)},
            ["triangle", "--edges", "5,4,3", "-w", "0,0.2,0.5"],
        ),
        (vorobound.advise, {"sphere": 1.0}, ["advise", "--sphere", "1"]),
    ],
)
def test_to_dict_is_the_command_json(run_cli, function, kwargs, argv):
    code, out, _ = run_cli(*argv, "--json")
    assert code == 0
    assert function(**kwargs).to_dict() == json.loads(out)
