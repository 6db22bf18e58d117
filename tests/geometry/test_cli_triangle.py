"""``vorobound triangle``: output keys, values, and one-line errors."""

import json

import pytest
from helpers import assert_one_line_error

from vorobound import weighted_triangles

TRIANGLE = ["-p", "0,0", "-p", "1,0", "-p", "0.2,0.9", "-w", "0.05,0.01,0.03"]
REQUIRED_KEYS = {
    "circumradius",
    "orthoradius_sq",
    "shifted_orthoradius",
    "delta",
    "delta_direct",
    "paper_literal",
    "min_weight_vertex",
    "assumption1_holds",
    "circumcenter",
    "orthocenter",
}


def test_json_from_points(run_cli):
    code, out, err = run_cli("triangle", *TRIANGLE, "--json")
    assert code == 0 and err == ""
    data = json.loads(out)
    assert REQUIRED_KEYS <= data.keys()
    lib = weighted_triangles([[0, 0], [1, 0], [0.2, 0.9]], [0.05, 0.01, 0.03])
    assert data["delta"] == pytest.approx(float(lib.radius_gap), rel=1e-15)
    assert data["min_weight_vertex"] == 1
    assert data["circumcenter"] == pytest.approx([0.5, 0.3611111111111111])


def test_json_from_edges_agrees_with_points(run_cli):
    lib = weighted_triangles([[0, 0, 0], [3, 0, 0], [0, 4, 0]], [0.0, 0.2, 0.5])
    code, out, _ = run_cli("triangle", "--edges", "5,4,3", "-w", "0,0.2,0.5", "--json")
    assert code == 0
    data = json.loads(out)
    assert data["delta"] == pytest.approx(float(lib.radius_gap), rel=1e-13)
    assert data["delta_direct"] is None and "circumcenter" not in data


def test_table_for_people(run_cli):
    code, out, _ = run_cli("triangle", *TRIANGLE)
    assert code == 0
    assert "Theorem 1" in out and "eq. (32) as printed" in out


@pytest.mark.parametrize(
    "args, fragment",
    [
        (["-p", "0,0", "-p", "1,0"], "exactly three"),
        (["-p", "0,0", "-p", "1,0", "-p", "1,1,1"], "same dimension"),
        (["-p", "0,0", "-p", "1,0", "-p", "x,1"], "not a number"),
        (["-p", "0,0", "-p", "1,0", "-p", "nan,1"], "finite"),
        (["-p", "0,0", "-p", "1,0", "-p", "inf,1"], "finite"),
        (["-p", "0,0", "-p", "1,0", "-p", "2,0"], "collinear"),
        (["-p", "0,0", "-p", "0,0", "-p", "0,1"], "collinear"),
        (["--edges", "1,1,3"], "triangle inequality"),
        (["--edges", "0,1,1"], "positive"),
        (["--edges", "1,1,1", "-w", "1,2"], "3 comma-separated"),
        (["--edges", "1,1,1", "-p", "0,0"], "either"),
        ([], "either"),
        (["--edges", "1,1,1", "--bogus"], "No such option"),
        # Exact arithmetic ends above the float64 range: rejected, not an OverflowError.
        (["-p", "1e-85,1", "-p", "0,2", "-p", "0,0", "-w", "1e300,0,0"], "overflows"),
    ],
)
def test_bad_input_is_one_line_exit_2(run_cli, args, fragment):
    assert_one_line_error(*run_cli("triangle", *args), fragment)
