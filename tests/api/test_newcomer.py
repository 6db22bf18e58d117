"""What a new user meets first (issue 33): the API takes what the options take, messages name
every alternative, ball files by content, rows with coordinates, warnings once, one notation
on the terminal, and a reading of every measurement that needs one."""

import json
import os
import subprocess
import sys
import warnings

import meshio
import numpy as np
import pytest
from helpers import assert_one_line_error

import vorobound
from vorobound.errors import InputError, VoroboundWarning, forget_warnings

# --- the API takes what the options take ---------------------------------------------------


def test_sweep_takes_the_options_range_text_lists_and_arrays():
    from_text = vorobound.sweep(rho_f="1.2:1.5:4", mode="tight", target="ratio")
    from_list = vorobound.sweep(rho_f=[1.2, 1.3, 1.4, 1.5], mode="tight", target="ratio")
    from_array = vorobound.sweep(rho_f=np.linspace(1.2, 1.5, 4), mode="tight", target="ratio")
    stars = [[row.eps_star for row in r.rows] for r in (from_text, from_list, from_array)]
    assert len(stars[0]) == 4 and stars[0] == stars[1] == stars[2]
    assert stars[0] == sorted(stars[0])  # a larger ρ_f admits a larger ε
    commas = vorobound.sweep(sigma="0.5, 0.75", lipschitz="none,1", mode="tight", target="ratio")
    assert commas.n_rows == 4
    assert {row.lipschitz for row in commas.rows} == {None, 1.0}


@pytest.mark.parametrize("text", ["1.2:x", "1.2:1.5", "a,b", "1:2:0"])
def test_sweep_refuses_bad_range_text_naming_the_keyword(text):
    with pytest.raises(InputError, match="^rho_f: "):
        vorobound.sweep(rho_f=text)


def test_reconstruct_takes_eps_as_the_option_does():
    from vorobound.api.reconstruct import _eps_values

    assert _eps_values("0.1:0.3:3") == pytest.approx([0.1, 0.2, 0.3])
    assert _eps_values("0.1,0.2") == [0.1, 0.2]
    with pytest.raises(InputError, match="^eps: "):
        _eps_values("0.1:")


# --- error messages name every alternative ----------------------------------------------------


@pytest.mark.parametrize(
    "command, alternatives",
    [("check", ["--balls"]), ("reconstruct", ["--balls", "--seeds"])],
)
def test_a_missing_input_names_the_surfaces_and_every_alternative(run_cli, command, alternatives):
    code, out, err = run_cli(command, "--eps", "0.3")
    assert_one_line_error(code, out, err)
    for option in ["--sphere", "--torus", "--mesh", *alternatives]:
        assert option in err


def test_the_api_names_balls_too():
    with pytest.raises(InputError, match=r"mesh FILE\) or balls FILE$"):
        vorobound.check(eps=0.3)
    with pytest.raises(InputError, match="or balls FILE or seeds FILE$"):
        vorobound.reconstruct(eps=0.3)


# --- lfs takes --mesh; the positional form says it is deprecated -------------------------------


@pytest.fixture(scope="module")
def cube_file(tmp_path_factory):
    from vorobound.sampling.surfaces.cad_meshes import cube

    mesh = cube()
    path = tmp_path_factory.mktemp("part") / "cube.stl"
    meshio.write(path, meshio.Mesh(mesh.points, [("triangle", mesh.triangles)]))
    return str(path)


def test_lfs_positional_mesh_works_with_a_deprecation_note(run_cli, cube_file):
    from vorobound.cli.lfs_cmd import POSITIONAL_MESH_NOTE

    code, out, err = run_cli("lfs", cube_file, "--json")
    assert code == 0 and json.loads(out)["lfs_max"] == pytest.approx(1.0, rel=1e-6)
    assert POSITIONAL_MESH_NOTE in err and "--mesh" in POSITIONAL_MESH_NOTE
    code, out, err = run_cli("lfs", "--mesh", cube_file, "--json")
    assert code == 0 and "deprecated" not in err


# --- ball files by content -------------------------------------------------------------------


@pytest.fixture(scope="module")
def sphere_balls(tmp_path_factory):
    folder = tmp_path_factory.mktemp("balls")
    vorobound.sample(sphere=1, eps=0.3, output=str(folder / "s.csv"))
    table = np.loadtxt(folder / "s.csv", delimiter=",", skiprows=1)[:, :4]
    return folder, table


@pytest.mark.parametrize(
    "name, header", [("s.txt", ""), ("s.dat", "x y z r"), ("balls", "# from a solver\nx\ty\tz\tr")]
)
def test_a_text_table_of_balls_is_read_whatever_its_suffix(sphere_balls, name, header):
    from vorobound.sampling.io.balls import ball_format, read_balls

    folder, table = sphere_balls
    path = folder / name
    np.savetxt(path, table, header=header, comments="", delimiter="\t" if "\t" in header else " ")
    assert ball_format(path) == "csv"
    balls = read_balls(path)
    np.testing.assert_array_equal(balls.centers, table[:, :3])
    np.testing.assert_array_equal(balls.radii, table[:, 3])


def test_other_content_still_goes_to_its_reader(sphere_balls, tmp_path):
    from vorobound.errors import ReadError
    from vorobound.sampling.io.balls import ball_format, read_balls

    folder, table = sphere_balls
    np.savez(tmp_path / "b.bin", x=table[:, 0], y=table[:, 1], z=table[:, 2], r=table[:, 3])
    os.replace(tmp_path / "b.bin.npz", tmp_path / "b.bin")
    assert ball_format(tmp_path / "b.bin") == "npz"
    assert len(read_balls(tmp_path / "b.bin")) == len(table)
    (tmp_path / "words.txt").write_text("hello world\n")
    assert ball_format(tmp_path / "words.txt") == "meshio"
    with pytest.raises(ReadError):
        read_balls(tmp_path / "words.txt")
    (tmp_path / "three.txt").write_text("1 2 3\n4 5 6\n")  # three columns: not balls
    assert ball_format(tmp_path / "three.txt") == "meshio"


def test_check_reads_a_txt_ball_file_from_the_command_line(run_cli, sphere_balls):
    folder, table = sphere_balls
    path = folder / "cli.txt"
    np.savetxt(path, table)
    code, out, err = run_cli("check", "--balls", str(path), "--eps", "0.3", "--json")
    assert code == 0, err
    assert json.loads(out)["n_samples"] == len(table)


# --- rows with coordinates; the sample's L in the JSON -----------------------------------------


def test_check_frame_rows_carry_the_ball_centres(sphere_balls):
    pytest.importorskip("pandas")
    folder, table = sphere_balls
    check = vorobound.check(balls=str(folder / "s.csv"), eps=0.3)
    frame = check.to_frame()
    assert len(frame) == check.n_guide_triangles > 0
    for vertex in "abc":
        centres = table[frame[f"{vertex}_index"].to_numpy(), :3]
        got = frame[[f"{vertex}_{axis}" for axis in "xyz"]].to_numpy()
        np.testing.assert_array_equal(got, centres)


def test_json_reports_the_samples_l_not_the_unit_of_the_bounds(tmp_path):
    sphere = vorobound.sample(sphere=2, eps=0.3, output=str(tmp_path / "s.npz")).to_dict()
    assert sphere["params"]["lfs"] == 2.0 and sphere["lfs_min"] == sphere["lfs_max"] == 2.0
    torus = vorobound.sample(torus=(1.5, 1), eps=0.3, output=str(tmp_path / "t.npz")).to_dict()
    assert torus["params"]["lfs"] is None  # L varies on this torus
    assert 0.4 < torus["lfs_min"] < torus["lfs_max"] <= 1.0 + 1e-12


def test_check_of_a_half_unit_cube_says_l_is_a_half(tmp_path):
    """The issue's cube: a part whose L is 0.5 had "lfs": 1.0 in summary.json."""
    from vorobound.sampling.surfaces.cad_meshes import cube

    mesh = cube()
    path = tmp_path / "unit.stl"
    meshio.write(path, meshio.Mesh(mesh.points / 2, [("triangle", mesh.triangles)]))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", VoroboundWarning)  # the sharp edges, said elsewhere
        summary = vorobound.check(mesh=str(path), eps=0.2).to_dict()
    assert summary["params"]["lfs"] == pytest.approx(0.5, rel=1e-6)
    assert summary["lfs_max"] == pytest.approx(0.5, rel=1e-6)


def test_a_tiled_check_reports_the_balls_l(sphere_balls):
    """The tiles keep no L per ball: the JSON gave the bounds' unit L_i = 1 on a unit-radius
    sphere sampled with L = 1 only by chance; the range comes from the radii over δ."""
    folder, table = sphere_balls
    radii = table[:, 3]
    half = folder / "half.csv"
    np.savetxt(half, np.c_[table[:, :3] / 2, radii / 2], delimiter=",", header="x,y,z,r")
    whole = vorobound.check(balls=str(half), eps=0.3).to_dict()
    tiled = vorobound.check(balls=str(half), eps=0.3, workers=1).to_dict()
    assert "tiles" in tiled and "tiles" not in whole
    delta = 2.0 * 0.3
    assert tiled["lfs_min"] == pytest.approx(radii.min() / 2 / delta, rel=1e-12)
    assert tiled["lfs_max"] == pytest.approx(radii.max() / 2 / delta, rel=1e-12)
    assert tiled["params"]["lfs"] == whole["params"]["lfs"] == pytest.approx(0.5, rel=1e-9)


def test_reconstruct_reports_the_samples_l_not_the_unit_of_the_bounds():
    one = vorobound.reconstruct(sphere=2, eps=0.3).to_dict()
    assert one["params"]["lfs"] == 2.0 and one["lfs_min"] == one["lfs_max"] == 2.0
    sweep = vorobound.reconstruct(sphere=2, eps="0.3,0.35").to_dict()
    assert sweep["params"]["lfs"] == 2.0 and sweep["lfs_max"] == 2.0
    draws = vorobound.reconstruct(sphere=2, eps=0.3, repeats=2).to_dict()
    assert draws["params"]["lfs"] == 2.0 and draws["lfs_min"] == 2.0
    torus = vorobound.reconstruct(torus=(1.5, 1), eps=0.3).to_dict()
    assert torus["params"]["lfs"] is None and 0.4 < torus["lfs_min"] < torus["lfs_max"] <= 1.0


def test_reconstruct_of_seeds_alone_has_no_l():
    from pathlib import Path

    run = Path(__file__).parents[1] / "data" / "vorocrust" / "cube"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", VoroboundWarning)  # the cube's sharp edges
        summary = vorobound.reconstruct(vorocrust=str(run)).to_dict()
    assert summary["params"]["lfs"] is None and "lfs_min" not in summary


# --- a warning once per mesh per process --------------------------------------------------------


def test_a_meshs_warning_is_given_once_per_process():
    from vorobound.sampling.lfs.estimate import estimate_lfs
    from vorobound.sampling.surfaces.cad_meshes import cube

    mesh = cube()

    def sharp_warnings():
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            estimate_lfs(mesh, samples=0)
        return [w for w in caught if "sharp edges" in str(w.message)]

    assert len(sharp_warnings()) == 1
    assert sharp_warnings() == []  # the same mesh again: said already
    other = cube(per_unit=3)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        estimate_lfs(other, samples=0)
    assert any("sharp edges" in str(w.message) for w in caught)  # another mesh: said
    forget_warnings()
    assert len(sharp_warnings()) == 1


# --- one notation on the terminal ---------------------------------------------------------------


def test_footers_take_the_tables_notation_and_leave_options_alone():
    from vorobound.cli.notation import to_ascii, to_unicode

    text = "R <= rho_f*R_hat and R - R_hat <= (rho_f - 1)*delta*L_i for eps <= eps_star"
    assert to_unicode(text) == "R ≤ ρ_f·R̂ and R − R̂ ≤ (ρ_f − 1)·δ·L_i for ε ≤ ε*"
    assert to_unicode("R <= eps/(1-eps)*L_i") == "R ≤ ε/(1−ε)·L_i"
    assert to_unicode("R <= rho_f * R^ (eq. (54))") == "R ≤ ρ_f·R̂ (eq. (54))"
    kept = "`vorobound certify --eps` and h3_ratio_max, 'vorobound check --sigma'"
    assert to_unicode(kept) == kept
    spelt = "R <= rho_f*R_hat and R - R_hat <= (rho_f - 1)*delta*L_i for eps <= eps_star"
    assert to_ascii(to_unicode(text)) == spelt
    assert to_ascii("ε ∈ [10⁻¹², 0.999], 45°, M̂") == "eps in [10^-12, 0.999], 45 deg, M_hat"


def test_footers_are_wrapped_to_the_width():
    import io

    from vorobound.cli.notation import FALLBACK_WIDTH, footer
    from vorobound.reports.advisor import GUARANTEE

    stream = io.TextIOWrapper(io.BytesIO(), encoding="utf-8")
    lines = footer(GUARANTEE, stream).splitlines()
    assert len(GUARANTEE) > 500 and len(lines) > 5
    assert max(len(line) for line in lines) < FALLBACK_WIDTH
    assert "ε ≤ ε*" in lines[0] and "eps" not in " ".join(lines).replace("--eps", "")


def test_a_terminal_without_unicode_gets_plain_ascii():
    env = dict(os.environ, PYTHONIOENCODING="ascii", PYTHONPATH=os.pathsep.join(sys.path))
    done = subprocess.run(
        [sys.executable, "-m", "vorobound", "solve"],
        capture_output=True,
        env=env,
        check=False,
        timeout=120,
    )
    assert done.returncode == 0
    text = done.stdout.decode("ascii")  # no byte outside ASCII
    assert "?" not in text  # nothing replaced: every symbol spelt out
    assert "eps_star" in text and "rho_f = 1.38" in text and "R <= rho_f*R_hat" in text


# --- a reading of every measurement a user cannot judge alone -----------------------------------


def test_reconstruct_reads_the_numbers_that_need_it():
    from dataclasses import replace

    import vorobound
    from vorobound.cli.reconstruct_cmd import READING_DOC, readings

    measured = vorobound.reconstruct(eps=0.3, sphere=1.0).summary
    summary = replace(
        measured,
        collapsed_facets=1_987_675,
        edge_ratio_min=6.372e-9,
        min_angle_min_deg=0.0,
        normal_deviation_max_deg=84.42,
        flipped_facets=4,
    )
    lines = readings(summary)
    assert len(lines) == 3 and all(READING_DOC in line for line in lines)
    assert "1,987,675 in/out pairs with no area" in lines[0] and "harmless" in lines[0]
    assert "min edge ratio 6.37e-09" in lines[1] and "sliver" in lines[1]
    assert "4 facets above 90° face inward" in lines[2] and "matters" in lines[2]
    fine = replace(summary, collapsed_facets=0, edge_ratio_min=0.3, min_angle_min_deg=20.0,
                   flipped_facets=0)  # fmt: skip
    fine = readings(fine)
    assert len(fine) == 2 and "no sliver facets" in fine[0] and "faces outward" in fine[1]


def test_notation_keeps_the_star_of_eps_star():
    """'eps* for ...' is ε*, not a product ε·for (found when the branches were merged)."""
    from vorobound.cli.notation import to_unicode

    text = to_unicode("no eps* for rigorous; R <= rho_f*R_hat")
    assert "ε* for" in text and "ρ_f·R̂" in text
