"""Hostile input: every extreme value is one line on stderr and exit 2 (or a correct result).

Each case is a reproduction from the hardening issue; with ``--json`` stdout must stay empty.
"""

import json
import os
import subprocess
import sys

import numpy as np
import pytest
from helpers import assert_one_line_error

EXTREME_CASES = [
    ["validate", "--eps", "0.0047", "--sigma", "10"],
    ["validate", "--eps", "0.0047", "--seed", "-1"],
    ["validate", "--eps", "0.0047", "--delta-ratio", "1e308"],
    ["validate", "--eps", "0.0047", "--delta-ratio", "1e-300"],
    ["validate", "--eps", "0.0047", "--lipschitz", "1e-320"],
    ["validate", "--eps", "0.0047", "--samples", "1000000000"],
    ["cheng", "--alpha", "0.3", "--seed", "-1"],
    ["cheng", "--alpha", "0.3", "--seed", "99999999999999999999"],
    ["bounds", "--eps", "1e-320", "--mode", "tight"],
    ["bounds", "--eps", "0.0047", "--lfs", "1e-320", "--mode", "tight"],
    ["bounds", "--eps", "0.0047", "--rho-f", "1e308"],
    ["bounds", "--eps", "1e-320"],
    ["bounds", "--eps", "0.0047", "--sigma", "1e308"],
    ["bounds", "--eps", "0.5", "--sigma", "1.9", "--mode", "paper", "--target", "additive"],
    ["solve", "--mode", "tight", "--delta-ratio", "1e308"],
    ["solve", "--rho-f", "1e300"],
    ["solve", "--mode", "tight", "--sigma", "1e4"],
    ["sweep", "--mode", "tight", "--delta-ratio", "1e308"],
    ["sweep", "--sigma", "1e308"],
    ["sweep", "--eps", "1e-320"],
    ["sweep", "--sigma", "0.3:1.5:100000", "--rho-f", "1.01:3:100000"],
    ["sweep", "--sigma", "0.3:1.5:10000000000"],
    ["sweep", "--mode", "tight", "--method", "optimize", "--sigma", "0.3:1.5:1000"],
    ["sweep", "--mode", "paper,rigorous", "--lipschitz", "1"],
    ["advise", "--sphere", "1e200"],
    ["advise", "--area", "1", "--lfs", "1e-200"],
    ["advise", "--area", "1", "--lfs", "1e308"],
    ["advise", "--torus", "3,1e-320"],
    ["advise", "--torus", "1e200,1e199"],
    ["advise", "--mode", "paper,nope"],
    ["triangle", "--edges", "3,4,5", "-w", "1e308,-1e308,0"],
    ["triangle", "-p", "0,0", "-p", "1,0", "-p", "2,0"],
]


@pytest.mark.parametrize("args", EXTREME_CASES, ids=lambda a: " ".join(a)[:60])
def test_extreme_values_give_one_line_and_exit_2(run_cli, args):
    code, out, err = run_cli(*args, "--json")
    assert code == 2, (code, err)
    assert out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), err
    assert "bug" not in lines[0]


def test_triangle_overflow_message_blames_the_weights_not_the_edges(run_cli):
    code, _, err = run_cli("triangle", "--edges", "3,4,5", "-w", "1e308,-1e308,0")
    assert code == 2 and "overflow" in err and "degenerate" not in err


def test_paper_eps_star_for_huge_rho_f_is_a_root_at_the_chain_singularity(run_cli):
    """For large ρ_f the printed chain crosses its target just below ε = 0.19276, where
    sqrt(1 − k_cos²) in eq. (52) vanishes and the bound rises to infinity: a true root,
    located up to the float resolution of that singular function (not a jump)."""
    import json

    from vorobound.bounds.chain import chain_bounds
    from vorobound.bounds.params import QualityParams

    code, out, _ = run_cli(
        "solve", "--rho-f", "100000", "--mode", "paper", "--target", "additive", "--json"
    )
    assert code == 0
    star = json.loads(out)["eps_star"]
    quality = QualityParams(rho_f=1e5)
    below = chain_bounds(quality.at(0.1), "paper", eps=star * (1 - 1e-9))
    assert float(below.bound) < float(below.gap_allowance)
    at = chain_bounds(quality.at(0.1), "paper", eps=star)
    assert float(at.bound) == pytest.approx(float(at.gap_allowance), rel=1e-3)
    assert float(at.sin_min_obtuse) < 1e-4  # next to the singularity


@pytest.mark.parametrize(
    "name, content",
    [
        ("face.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99\n"),
        ("face_2_64.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 18446744073709551617\n"),
        ("face_2_63.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9223372036854775808\n"),
        ("face_int64.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9223372036854775807\n"),
        ("line.obj", "v 0\nv 1\nv 2\nf 1 2 3\n"),
        ("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"),
        ("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n"),
        ("bad.ply", "ply\nformat ascii 1.0\ngarbage\n"),
        ("bad.vtk", "garbage\n"),
        ("bad.off", "garbage\n"),
        ("bad.vtu", "garbage\n"),
    ],
)
def test_bad_meshes_are_one_line_and_keep_stdout_clean(run_cli, tmp_path, name, content):
    mesh = tmp_path / name
    mesh.write_text(content)
    code, out, err = run_cli("advise", "--mesh", str(mesh), "--lfs", "1", "--json")
    assert_one_line_error(code, out, err)


@pytest.mark.parametrize("content", [b"\xff\xfe\x00garbage\n", b"L\n1e308\n1e308\n1e308\n"])
def test_bad_sizing_files_are_refused(run_cli, tmp_path, content):
    mesh = tmp_path / "tri.obj"
    mesh.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    sizing = tmp_path / "sizing.csv"
    sizing.write_bytes(content)
    code, out, err = run_cli("advise", "--mesh", str(mesh), "--sizing", str(sizing), "--json")
    assert_one_line_error(code, out, err)


def test_huge_jobs_is_capped_not_a_crash(run_cli):
    code, out, _ = run_cli("sweep", "--jobs", "99999999999999999999", "--format", "csv")
    assert code == 0 and out.startswith("mode,")


def test_duplicate_modes_and_values_are_computed_once(run_cli):
    code, out, _ = run_cli(
        "sweep", "--mode", "paper,paper", "--target", "ratio,ratio", "--rho-f", "1.3,1.3", "--json"
    )
    assert code == 0
    import json

    assert len(json.loads(out)["rows"]) == 1


def test_lipschitz_mixes_none_with_values(run_cli):
    import json

    code, out, _ = run_cli(
        "sweep",
        "--mode",
        "tight",
        "--target",
        "additive",
        "--lipschitz",
        "none,0,1",
        "--json",
        "--rho-f",
        "1.38",
    )
    assert code == 0
    rows = json.loads(out)["rows"]
    assert [r["lipschitz"] for r in rows] == [None, 0.0, 1.0]
    assert rows[1]["eps_star"] is None and "no crossing" in rows[1]["note"]


def _run(args, **env):
    return subprocess.run(
        [sys.executable, "-m", "vorobound", *args],
        capture_output=True,
        text=True,
        env=os.environ | env,
        check=False,
        timeout=120,
    )


def test_ascii_terminal_does_not_crash():
    done = _run(["bounds", "--eps", "0.0047"], PYTHONIOENCODING="ascii")
    assert done.returncode == 0, done.stderr
    assert "bound on R" in done.stdout


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="needs /dev/full")
def test_stdout_to_a_full_device_is_one_line_exit_2():
    with open("/dev/full", "w") as full:
        done = subprocess.run(
            [sys.executable, "-m", "vorobound", "bounds", "--eps", "0.0047", "--json"],
            stdout=full,
            stderr=subprocess.PIPE,
            text=True,
            check=False,
            timeout=120,
        )
    assert done.returncode == 2
    assert done.stderr.strip().splitlines() == [
        "error: cannot write the output: No space left on device"
    ]


def test_closed_stdout_is_one_line_exit_2():
    """Started with standard output closed (``>&-``), Python has ``sys.stdout = None``."""
    done = subprocess.run(
        [sys.executable, "-m", "vorobound", "bounds", "--eps", "0.0047", "--json"],
        capture_output=True,
        text=True,
        preexec_fn=lambda: os.close(1),
        check=False,
        timeout=120,
    )
    assert done.returncode == 2
    assert done.stderr.strip().splitlines() == [
        "error: cannot write the output: standard output is closed"
    ]


def test_unexpected_errors_are_reported_as_bugs(run_cli, monkeypatch):
    import vorobound.bounds.chain as chain

    def broken(*args, **kwargs):
        raise ZeroDivisionError("planted")

    monkeypatch.setattr(chain, "chain_bounds", broken)
    code, out, err = run_cli("bounds", "--eps", "0.0047", "--mode", "paper")
    assert code == 70 and out == ""
    assert err.count("\n") == 1 and "bug" in err and "planted" in err
    monkeypatch.setenv("VOROBOUND_DEBUG", "1")
    code, _, err = run_cli("bounds", "--eps", "0.0047", "--mode", "paper")
    assert code == 70 and "Traceback" in err


def _write_npz(path, **arrays):
    import numpy as np

    np.savez(path, **{k: np.asarray(v) for k, v in arrays.items()})


@pytest.mark.parametrize("case", ["empty", "truncated", "ragged", "bool", "tiny", "huge", "dir"])
def test_bad_ball_files_are_one_line(run_cli, tmp_path, case):
    import numpy as np

    rng = np.random.default_rng(0)
    good = {"x": rng.random(20), "y": rng.random(20), "z": rng.random(20), "r": np.full(20, 0.3)}
    path = tmp_path / "balls.npz"
    if case == "empty":
        path.write_bytes(b"")
    elif case == "truncated":
        _write_npz(path, **good)
        path.write_bytes(path.read_bytes()[:200])
    elif case == "ragged":
        _write_npz(path, **(good | {"z": good["z"][:15]}))
    elif case == "bool":
        _write_npz(path, **(good | {"x": good["x"] > 0.5}))
    elif case == "tiny":
        _write_npz(path, **{k: v * 1e-150 for k, v in good.items()})
    elif case == "huge":
        _write_npz(path, **{k: v * 1e150 for k, v in good.items()})
    else:
        path.mkdir()
    code, out, err = run_cli("check", "--eps", "0.1", "--balls", str(path), "--json")
    assert code == 2 and out == "", err
    assert len(err.strip().splitlines()) == 1 and "bug" not in err


def test_certificate_bombs_are_refused_quickly(run_cli, tmp_path):
    import json

    base = {"format": "vorobound-certificate", "format_version": 1}
    deep = tmp_path / "deep.json"
    deep.write_text("[" * 100_000 + "]" * 100_000)
    splits = tmp_path / "splits.json"
    code, _, _ = run_cli("certify", "--eps", "0.005", "-o", str(splits))
    assert code == 0
    payload = json.loads(splits.read_text())
    payload["nodes"] = [0] * 1_000_000
    splits.write_text(json.dumps(payload))
    version = tmp_path / "version.json"
    version.write_text(json.dumps(payload | base | {"format_version": True}))
    for path in (deep, splits, version, "/dev/zero"):
        code, out, err = run_cli("certify", "--check", str(path), "--json")
        assert code == 2 and out == "", err
        assert len(err.strip().splitlines()) == 1 and "bug" not in err


def test_repeated_faces_are_counted_once(run_cli, tmp_path):
    """A face listed twice (either orientation) must not double the area or the samples."""
    from vorobound.sampling.surfaces.demo_meshes import icosphere

    sphere = icosphere(2.0, 2)

    def obj(triangles):
        lines = [f"v {x:.17g} {y:.17g} {z:.17g}" for x, y, z in sphere.points]
        lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in triangles]
        return "\n".join(lines) + "\n"

    once, twice = tmp_path / "once.obj", tmp_path / "twice.obj"
    once.write_text(obj(sphere.triangles))
    twice.write_text(obj(list(sphere.triangles) + [t[::-1] for t in sphere.triangles]))
    results = []
    for path in (once, twice):
        code, out, err = run_cli("advise", "--mesh", str(path), "--lfs", "2", "--json")
        assert code == 0, err
        results.append((json.loads(out)["surface"]["area"], err))
    assert results[1][0] == pytest.approx(results[0][0], rel=1e-12)
    assert "repeat another one" in results[1][1] and "repeat" not in results[0][1]


def test_a_sizing_steeper_than_one_lipschitz_is_warned_about(run_cli, tmp_path):
    from vorobound.sampling.surfaces.demo_meshes import icosphere

    sphere = icosphere(2.0, 2)
    mesh = tmp_path / "s.obj"
    lines = [f"v {x:.17g} {y:.17g} {z:.17g}" for x, y, z in sphere.points]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in sphere.triangles]
    mesh.write_text("\n".join(lines) + "\n")
    messages = {}
    for name, values in (("smooth", np.full(len(sphere.points), 2.0)), ("jumpy", None)):
        if values is None:
            values = np.where(np.arange(len(sphere.points)) % 2, 0.01, 2.0)
        sizing = tmp_path / f"{name}.csv"
        sizing.write_text("lfs\n" + "\n".join(f"{v!r}" for v in values.tolist()) + "\n")
        code, out, err = run_cli("advise", "--mesh", str(mesh), "--sizing", str(sizing), "--json")
        samplable = json.loads(out)["recommendation"]["samplable"]
        assert code == (0 if samplable else 1), err  # 1: sample cannot build the advised ε
        messages[name] = err
    assert "1-Lipschitz" in messages["jumpy"] and "1-Lipschitz" not in messages["smooth"]
