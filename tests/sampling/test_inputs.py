"""Inputs as users have them: quad and polygon meshes (split into triangles with a note), ball
and sizing tables with semicolons or tabs, and messages that name the line of the file."""

import json
import warnings

import meshio
import numpy as np
import pytest

from vorobound.errors import InputError, ReadError, VoroboundWarning
from vorobound.sampling.io.balls import read_balls
from vorobound.sampling.io.faces import triangulate
from vorobound.sampling.io.meshes import read_sizing, read_triangle_mesh

AREA_RTOL = 1e-12
RNG = np.random.default_rng(3)

# --- polygons split into triangles ---------------------------------------------------------

L_SHAPE = [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]  # non-convex hexagon, area 3
STAR = [  # a non-convex decagon: a five-pointed star
    (r * np.cos(a), r * np.sin(a))
    for a, r in zip(np.linspace(0, 2 * np.pi, 10, endpoint=False), [1.0, 0.4] * 5, strict=True)
]
DART = [(0, 0), (2, 1), (0, 2), (0.5, 1)]  # non-convex quad: only the diagonal 1-3 is inside
PENTAGON = [(np.cos(a), np.sin(a)) for a in np.linspace(0, 2 * np.pi, 5, endpoint=False)]


def _shoelace(polygon) -> float:
    x, y = np.asarray(polygon, dtype=float).T
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def _placed(polygon, rotation) -> np.ndarray:
    """The planar polygon as 3-D points on a tilted plane away from the origin."""
    flat = np.column_stack([np.asarray(polygon, dtype=float), np.zeros(len(polygon))])
    return flat @ rotation.T + np.array([5.0, -3.0, 2.0])


def _rotation(seed: int) -> np.ndarray:
    q, r = np.linalg.qr(np.random.default_rng(seed).standard_normal((3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


@pytest.mark.parametrize(
    "polygon", [L_SHAPE, STAR, DART, PENTAGON], ids=["L", "star", "dart", "pentagon"]
)
@pytest.mark.parametrize("seed", [0, 1])
def test_planar_polygons_are_tiled_exactly(polygon, seed):
    rotation = _rotation(seed)
    points = _placed(polygon, rotation)
    normal = rotation[:, 2]  # the polygon is counter-clockwise seen from +z before rotation
    corners = len(polygon)
    for start in range(corners):  # whichever vertex the file lists first
        face = np.roll(np.arange(corners), -start)[None, :]
        triangles = triangulate(points, [face]).triangles
        assert triangles.shape == (corners - 2, 3)
        p = points[triangles]
        normals = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
        assert (normals @ normal > 0).all(), "a triangle faces the other way (overlap)"
        area = 0.5 * float(np.linalg.norm(normals, axis=1).sum())
        assert area == pytest.approx(_shoelace(polygon), rel=AREA_RTOL)


def test_a_triangle_stored_as_a_quad_is_one_triangle():
    points = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0.0]])
    result = triangulate(points, [np.array([[0, 1, 2, 2]])])
    assert result.triangles.tolist() == [[0, 1, 2]] and result.dropped == 1


def _quad_torus(n=24, m=12):
    u = np.linspace(0, 2 * np.pi, n, endpoint=False)
    v = np.linspace(0, 2 * np.pi, m, endpoint=False)
    uu, vv = np.meshgrid(u, v, indexing="ij")
    points = np.stack(
        [(3 + np.cos(vv)) * np.cos(uu), (3 + np.cos(vv)) * np.sin(uu), np.sin(vv)], -1
    ).reshape(-1, 3)
    index = np.arange(n * m).reshape(n, m)
    right = np.roll(index, -1, 0)
    quads = np.stack([index, right, np.roll(right, -1, 1), np.roll(index, -1, 1)], -1)
    return points, quads.reshape(-1, 4)


def test_a_closed_quad_surface_becomes_a_closed_oriented_triangle_surface():
    points, quads = _quad_torus()
    triangles = triangulate(points, [quads]).triangles
    assert len(triangles) == 2 * len(quads)
    directed = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    assert len({tuple(e) for e in directed.tolist()}) == len(directed)  # consistently oriented
    undirected = np.sort(directed, axis=1)
    _, counts = np.unique(undirected, axis=0, return_counts=True)
    assert (counts == 2).all()  # closed: every edge between exactly two triangles
    euler = len(points) - len(counts) + len(triangles)
    assert euler == 0  # a torus


@pytest.mark.parametrize("suffix", [".obj", ".ply", ".vtu", ".vtk"])
def test_quad_and_polygon_mesh_files_are_read_with_a_note(tmp_path, suffix):
    points, quads = _quad_torus()
    hexagons = np.array([[0, 1, 2, 3, 4, 5]])  # one extra face, to have a polygon block
    path = tmp_path / f"torus{suffix}"
    if suffix == ".obj":  # written by hand: older meshio writes no polygons to OBJ
        lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in points.tolist()]
        lines += ["f " + " ".join(str(i + 1) for i in face) for face in [*quads, *hexagons]]
        path.write_text("\n".join(lines) + "\n")
    else:
        meshio.write(path, meshio.Mesh(points, [("quad", quads), ("polygon", hexagons)]))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        mesh = read_triangle_mesh(path)
    notes = [str(w.message) for w in caught if issubclass(w.category, VoroboundWarning)]
    expected = f"{len(quads)} quadrilateral and 1 polygonal faces split into triangles"
    assert any(expected in note for note in notes), notes
    assert len(mesh.triangles) == 2 * len(quads) + 4
    assert mesh.triangle_areas().min() > 0


def test_cli_reads_a_quad_mesh_with_one_warning_line(run_cli, tmp_path):
    points, quads = _quad_torus()
    path = tmp_path / "torus.obj"
    meshio.write(path, meshio.Mesh(points, [("quad", quads)]))
    code, out, err = run_cli("advise", "--mesh", str(path), "--lfs", "1", "--json")
    samplable = json.loads(out)["recommendation"]["samplable"]
    assert code == (1 if samplable is False else 0), err  # exit 1: `sample` cannot build it
    notes = [line for line in err.splitlines() if "split into triangles" in line]
    assert notes == [f"warning: mesh torus.obj: {len(quads)} quadrilateral faces split into "
                     f"triangles ({2 * len(quads)} triangles in all)"]  # fmt: skip


# --- tables with other delimiters ----------------------------------------------------------

CENTERS = RNG.random((12, 3))
RADII = 0.1 + 0.1 * RNG.random(12)


def _table(delimiter: str, header: str | None, rows=None, decimal: str = ".") -> str:
    rows = np.column_stack([CENTERS, RADII]) if rows is None else rows
    lines = [] if header is None else [delimiter.join(header.split(","))]
    for row in rows:
        lines.append(delimiter.join(repr(float(v)).replace(".", decimal) for v in row))
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize(
    "delimiter", [",", ";", "\t", "  "], ids=["comma", "semicolon", "tab", "spaces"]
)
@pytest.mark.parametrize("header", [None, "x,y,z,r", "r,x,y,z"])
def test_balls_in_any_common_delimiter(tmp_path, delimiter, header):
    rows = np.column_stack([CENTERS, RADII])
    if header == "r,x,y,z":
        rows = rows[:, [3, 0, 1, 2]]
    path = tmp_path / "b.csv"
    path.write_text(_table(delimiter, header, rows))
    balls = read_balls(path)
    assert np.array_equal(balls.centers, CENTERS) and np.array_equal(balls.radii, RADII)


def test_decimal_commas_are_named_as_the_problem(tmp_path):
    path = tmp_path / "b.csv"
    path.write_text(_table(";", "x,y,z,r", decimal=","))
    with pytest.raises(ReadError, match=r"line 2: .* not a number \(a decimal comma"):
        read_balls(path)


def test_a_mixed_up_row_names_its_line_and_why(tmp_path):
    text = _table(";", "x,y,z,r").splitlines()
    text[5] = text[5].replace(";", ",", 1)  # line 6 separates two columns by a comma
    text[7] = text[7].rsplit(";", 1)[0]  # line 8 has 3 columns
    path = tmp_path / "b.csv"
    path.write_text("\n".join(text) + "\n")
    with pytest.raises(ReadError, match=r"line 6: .* \(columns separated by commas\? line 1 "):
        read_balls(path)
    text[5] = text[5].replace(",", ";", 1)
    path.write_text("\n".join(text) + "\n")
    with pytest.raises(ReadError, match=r"line 8: 3 columns where line 1 has 4 .*semicolons"):
        read_balls(path)


def _lines_with(tmp_path, rows, comment=True):
    """A CSV with a header, a comment and a blank line: ball i is on file line i + 4."""
    body = _table(",", "x,y,z,r", rows).splitlines()
    lines = [body[0], "# exported by a test", "", *body[1:]]
    path = tmp_path / "b.csv"
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.mark.parametrize(
    "column, row, value, message",
    [
        (3, 6, -1.0, "line 10: the radius is -1.0"),
        (3, 0, np.nan, "line 4: the radius is nan"),
        (1, 9, np.inf, "line 13: the center is not finite"),
        (3, 2, 1e60, "line 6: radii must lie in"),
        (0, 11, 1e60, "line 15: coordinates must lie within"),
    ],
)
def test_value_messages_name_the_file_line(tmp_path, column, row, value, message):
    rows = np.column_stack([CENTERS, RADII])
    rows[row, column] = value
    path = _lines_with(tmp_path, rows)
    assert (
        path.read_text()
        .splitlines()[int(message.split()[1].rstrip(":")) - 1]
        .startswith(repr(float(rows[row, 0])))
    )
    with pytest.raises(InputError, match=message):
        read_balls(path)


def test_duplicate_centers_name_both_lines(tmp_path):
    rows = np.column_stack([CENTERS, RADII])
    rows[8, :3] = rows[2, :3]
    with pytest.raises(InputError, match="lines 6 and 12: the centers coincide"):
        read_balls(_lines_with(tmp_path, rows))


def test_array_inputs_name_the_zero_based_index(tmp_path):
    path = tmp_path / "b.npz"
    radii = RADII.copy()
    radii[3] = 0.0
    np.savez(path, points=CENTERS, radii=radii)
    with pytest.raises(InputError, match=r"ball 3 \(0-based\): the radius is 0.0"):
        read_balls(path)


def test_cli_message_names_the_line(run_cli, tmp_path):
    rows = np.column_stack([CENTERS, RADII])
    rows[6, 3] = -1.0
    path = _lines_with(tmp_path, rows)
    code, out, err = run_cli("check", "--eps", "0.1", "--balls", str(path), "--json")
    assert code == 2 and out == ""
    assert err.strip().splitlines() == [
        "error: balls b.csv, line 10: the radius is -1.0; radii must be positive and finite "
        "(1 such rows)"
    ]


def test_sizing_files_with_semicolons_and_line_numbers(tmp_path):
    values = (0.5 + RNG.random(7)).tolist()
    path = tmp_path / "sizing.csv"
    path.write_text("x;y;z;lfs\n" + "\n".join(f"0;0;{i};{v!r}" for i, v in enumerate(values)))
    assert read_sizing(path, 7).tolist() == values
    path.write_text("lfs\n\n" + "\n".join(repr(v) for v in [*values[:4], -1.0, *values[5:]]))
    with pytest.raises(ReadError, match=r"line 7: -1.0 is not a local feature size"):
        read_sizing(path, 7)
