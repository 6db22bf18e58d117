"""Exits that used to break the contract (one line and exit 2 for bad input, no traceback, no
noise), found by a hostile pass: an NPY file named .npz, integers beyond float64, a reader that
closes the pipe, and a killed parent of worker processes."""

import copy
import json
import os
import subprocess
import sys
import time
import uuid
from pathlib import Path

import numpy as np
import pytest
from helpers import assert_one_line_error
from helpers import processes_with as _processes_with

from vorobound.cli import EXIT_BROKEN_PIPE

PYTHON = [sys.executable, "-m", "vorobound"]
HUGE = 10**400
"""An integer that JSON and the command line accept but float64 cannot hold."""
LONG_SWEEP = ["sweep", "--rho-f", "1.01:3:3000", "--mode", "paper", "--target", "additive"]
"""About 200 kB of CSV: more than a pipe holds, so the writer meets the closed pipe."""


def _one_line_error(code: int, out: str, err: str) -> None:
    assert_one_line_error(code, out, err)
    assert err.startswith("error: ") and "bug" not in err and len(err) < 300, err


def test_npy_file_named_npz_is_a_one_line_error(run_cli, tmp_path):
    path = tmp_path / "balls.npz"
    with open(path, "wb") as handle:  # np.save would append .npy to the name
        np.save(handle, np.random.default_rng(0).random((20, 4)))
    code, out, err = run_cli("check", "--eps", "0.1", "--balls", str(path), "--json")
    _one_line_error(code, out, err)
    assert "NPY" in err and "np.savez" in err


@pytest.fixture(scope="module")
def certificate(tmp_path_factory) -> dict:
    path = tmp_path_factory.mktemp("certificate") / "cert.json"
    from vorobound.cli import main

    assert main(["certify", "--eps", "0.005", "-o", str(path)]) == 0
    return json.loads(path.read_text())


def _with_parameter(key: str):
    return lambda payload, value: payload["parameters"].__setitem__(key, value)


def _with_node_bound(payload: dict, value) -> None:
    index = next(i for i, node in enumerate(payload["nodes"]) if isinstance(node, list))
    payload["nodes"][index] = [payload["nodes"][index][0], value]


@pytest.mark.parametrize("sign", [1, -1])
@pytest.mark.parametrize(
    "tamper",
    [
        *(
            _with_parameter(key)
            for key in ("sigma", "lipschitz", "rho_f", "delta_ratio", "eps_max")
        ),
        _with_node_bound,
        lambda p, v: p.__setitem__("precision_bits", v),
        lambda p, v: p.__setitem__("format_version", v),
        lambda p, v: p["nodes"].__setitem__(0, v),
    ],
    ids=[
        "sigma",
        "lipschitz",
        "rho_f",
        "delta_ratio",
        "eps_max",
        "bound",
        "bits",
        "version",
        "split",
    ],
)
def test_certificate_integers_beyond_float_are_one_line_errors(
    run_cli, tmp_path, certificate, tamper, sign
):
    payload = copy.deepcopy(certificate)
    tamper(payload, sign * HUGE)
    path = tmp_path / "huge.json"
    path.write_text(json.dumps(payload))
    code, out, err = run_cli("certify", "--check", str(path), "--json")
    _one_line_error(code, out, err)


@pytest.mark.parametrize("option", ["--sigma", "--lipschitz", "--rho-f", "--delta-ratio", "--eps"])
def test_option_integers_beyond_float_are_one_line_errors(run_cli, option):
    code, out, err = run_cli("certify", option, str(HUGE), "--json")
    _one_line_error(code, out, err)


def test_certificate_as_written_still_checks(run_cli, tmp_path, certificate):
    path = tmp_path / "cert.json"
    path.write_text(json.dumps(certificate))
    code, _, err = run_cli("certify", "--check", str(path), "--json")
    assert code == 0, err  # so the refusals above come from the huge values alone


# --- a reader that goes away ----------------------------------------------------------------


def test_head_closing_the_pipe_exits_141_quietly(tmp_path):
    """A real shell pipeline: head takes one byte and leaves; the sweep meets the broken pipe."""
    command = " ".join([*PYTHON, *LONG_SWEEP, "--format", "csv"]) + " | head -c1"
    done = subprocess.run(
        ["bash", "-c", f'{command}; echo "status=${{PIPESTATUS[0]}}" >&2'],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.stdout == "m"  # the CSV's first byte ("mode,...")
    assert done.stderr.strip() == f"status={EXIT_BROKEN_PIPE}"  # no message, no traceback


@pytest.mark.parametrize(
    "args",
    [["certify"], ["certify", "--json"], ["solve"], ["sweep", "--rho-f", "1.2:1.5:4"]],
    ids=["certify", "certify-json", "solve", "sweep"],
)
def test_output_into_a_closed_pipe_is_not_read_as_a_verdict(args):
    """The reader closed before anything was written: every write fails with EPIPE. The exit
    code must not be 0 (all written) nor 1 (for certify: "not certified")."""
    proc = subprocess.Popen([*PYTHON, *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    proc.stdout.close()
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == EXIT_BROKEN_PIPE, err
    assert err == b""


# --- a killed parent of worker processes ------------------------------------------------------


TIGHT_SWEEP = [
    "sweep",
    "--mode",
    "tight",
    "--method",
    "optimize",
    "--sigma",
    "0.5,0.6,0.7,0.8",
    "--jobs",
    "4",
    "--yes",
]


@pytest.mark.skipif(not Path("/proc/self/environ").exists(), reason="needs Linux /proc")
def test_killing_the_parent_of_a_parallel_sweep_prints_nothing(tmp_path):
    marker = uuid.uuid4().hex
    proc = subprocess.Popen(
        [*PYTHON, *TIGHT_SWEEP, "-o", str(tmp_path / "t.csv")],
        env=os.environ | {"VOROBOUND_TEST_MARKER": marker},
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    end = time.monotonic() + 60
    while len(_processes_with(marker.encode())) < 3 and time.monotonic() < end:
        time.sleep(0.1)  # the parent, its resource tracker and the workers carry the marker
    assert len(_processes_with(marker.encode())) >= 3, "workers did not start"
    time.sleep(0.5)  # the workers are busy
    proc.kill()
    _, err = proc.communicate(timeout=60)  # waits for the resource tracker, which shares stderr
    lines = [line for line in err.splitlines() if not line.startswith("note: using")]
    assert lines == [], err
    end = time.monotonic() + 20
    while _processes_with(marker.encode()) and time.monotonic() < end:
        time.sleep(0.1)
    assert not _processes_with(marker.encode()), "a worker or the tracker outlived the parent"
