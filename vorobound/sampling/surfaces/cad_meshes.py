"""Triangle meshes that look like CAD exports: few vertices, long thin triangles, sharp edges.

Each part comes as a coarse and a fine triangulation of the same geometry, so that an estimate
of the local feature size can be tested for independence of the triangulation: a capped
cylinder, a bar, a plate, a cube and an L-bracket with a bore. Every mesh is closed and
consistently oriented (outward). :func:`gear` is a large part for the speed benchmarks: a spur
gear of many teeth as a CAD export writes it, every triangle long and thin.

The coarse copies are what exporters write: a cylinder with one ring of vertices at each end
and caps fanned from one rim vertex, boxes of 12 triangles. The fine copies split the same
faces into many small ones.
"""

from __future__ import annotations

import math

import numpy as np

from ...errors import InputError
from ...mesh import TriangleMesh


def _checked_count(value: int, name: str, low: int, high: int) -> int:
    if (
        isinstance(value, bool)
        or not isinstance(value, int | np.integer)
        or not low <= value <= high
    ):
        raise InputError(f"{name} must be a whole number in [{low}, {high}], got {value!r}")
    return int(value)


def _positive(value: float, name: str) -> float:
    value = float(value)
    if not (math.isfinite(value) and value > 0):
        raise InputError(f"{name} must be positive and finite, got {value}")
    return value


def capped_cylinder(
    radius: float = 1.0,
    length: float = 100.0,
    segments: int = 32,
    rings: int = 2,
    fan_caps: bool = True,
) -> TriangleMesh:
    """A closed cylinder along z from 0 to ``length`` with flat caps.

    Parameters
    ----------
    radius, length : float
        Cylinder radius and length.
    segments : int
        Vertices per ring (the circle is a regular polygon of that many sides).
    rings : int
        Rings of vertices along the length (2: one at each end, the long thin triangles of a
        CAD export).
    fan_caps : bool
        True: each cap is a fan from one rim vertex (slivers, as exporters write them);
        False: a fan from a centre vertex.
    """
    radius, length = _positive(radius, "radius"), _positive(length, "length")
    segments = _checked_count(segments, "segments", 3, 100_000)
    rings = _checked_count(rings, "rings", 2, 100_000)
    angle = 2 * math.pi * np.arange(segments) / segments
    z = np.linspace(0.0, length, rings)
    circle = np.c_[radius * np.cos(angle), radius * np.sin(angle)]
    points = np.concatenate([np.c_[circle, np.full(segments, h)] for h in z])
    faces = []
    k = np.arange(segments)
    for ring in range(rings - 1):
        a, b = ring * segments + k, ring * segments + (k + 1) % segments
        c, d = a + segments, b + segments
        faces += [np.c_[a, b, d], np.c_[a, d, c]]
    top = (rings - 1) * segments
    if fan_caps:
        j = np.arange(1, segments - 1)
        faces += [
            np.c_[np.zeros_like(j), j + 1, j],
            np.c_[top + np.zeros_like(j), top + j, top + j + 1],
        ]
    else:
        centres = len(points) + np.arange(2)
        points = np.vstack([points, [[0.0, 0.0, 0.0], [0.0, 0.0, length]]])
        nxt = (k + 1) % segments
        faces += [np.c_[np.full(segments, centres[0]), nxt, k]]
        faces += [np.c_[np.full(segments, centres[1]), top + k, top + nxt]]
    name = f"cylinder r={radius:g} length={length:g} {segments}x{rings}" + (
        " fan caps" if fan_caps else ""
    )
    return TriangleMesh(points, np.concatenate(faces).astype(np.int64), name)


def box(size=(100.0, 1.0, 1.0), per_unit: float | None = None, name: str = "box") -> TriangleMesh:
    """A closed box [0, a] × [0, b] × [0, c].

    ``per_unit`` None: two triangles per face (12 in all, as exporters write a box); else each
    face is a grid of max(1, round(per_unit·side)) cells along each of its sides.
    """
    size = tuple(_positive(s, "box size") for s in size)
    if per_unit is not None:
        per_unit = _positive(per_unit, "per_unit")

    def cells(side: float) -> int:
        return 1 if per_unit is None else max(1, round(per_unit * side))

    points: list[np.ndarray] = []
    faces: list[np.ndarray] = []
    for axis in range(3):
        u_axis, v_axis = (axis + 1) % 3, (axis + 2) % 3
        nu, nv = cells(size[u_axis]), cells(size[v_axis])
        gu, gv = np.linspace(0, size[u_axis], nu + 1), np.linspace(0, size[v_axis], nv + 1)
        u, v = (a.reshape(-1) for a in np.meshgrid(gu, gv, indexing="ij"))
        i, j = (a.reshape(-1) for a in np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij"))
        corner = i * (nv + 1) + j
        quads = np.c_[corner, corner + nv + 1, corner + nv + 2, corner + 1]
        for high in (False, True):
            face_points = np.zeros((len(u), 3))
            face_points[:, axis] = size[axis] if high else 0.0
            face_points[:, u_axis], face_points[:, v_axis] = u, v
            base = sum(len(p) for p in points)
            q = quads + base if high else quads[:, ::-1] + base
            faces += [q[:, [0, 1, 2]], q[:, [0, 2, 3]]]
            points.append(face_points)
    unique, merged = np.unique(np.concatenate(points), axis=0, return_inverse=True)
    triangles = merged.reshape(-1)[np.concatenate(faces)]
    label = "x".join(f"{s:g}" for s in size)
    grid = "12 triangles" if per_unit is None else f"{per_unit:g} cells per unit"
    return TriangleMesh(unique, triangles.astype(np.int64), f"{name} {label} ({grid})")


def bar(per_unit: float | None = None) -> TriangleMesh:
    """The 100 × 1 × 1 bar of the issue (true L at most 0.5)."""
    return box((100.0, 1.0, 1.0), per_unit, "bar")


def plate(per_unit: float | None = None) -> TriangleMesh:
    """The 100 × 100 × 1 plate of the issue (true L at most 0.5)."""
    return box((100.0, 100.0, 1.0), per_unit, "plate")


def cube(per_unit: float | None = None) -> TriangleMesh:
    """A cube of side 2 (true L at most 1)."""
    return box((2.0, 2.0, 2.0), per_unit, "cube")


def l_bracket(
    arm: float = 10.0,
    thickness: float = 2.0,
    width: float = 8.0,
    bore: float = 0.6,
    segments: int = 16,
    spacing: float | None = None,
    rings: int = 1,
) -> TriangleMesh:
    """An L-shaped profile extruded along y, with a bore along y through the horizontal flange.

    The profile (x, z) is the L with outer corner at the origin: flanges of length ``arm`` and
    thickness ``thickness``; the bore of radius ``bore`` is centred in the horizontal flange at
    x = (arm + thickness)/2 + thickness/2, z = thickness/2. The end caps are triangulated by a
    conforming Delaunay triangulation of the profile's boundary points; the walls are strips
    between the two caps, split into ``rings`` − 1 … layers along y (``rings`` = 1: one strip,
    long thin triangles).

    Parameters
    ----------
    spacing : float, optional
        Largest distance between boundary points of the profile (default: the bore's segment
        length); smaller values give a finer cap.
    """
    from scipy.spatial import Delaunay

    arm, thickness, width = (
        _positive(v, n) for v, n in ((arm, "arm"), (thickness, "thickness"), (width, "width"))
    )
    bore = _positive(bore, "bore")
    segments = _checked_count(segments, "segments", 6, 10_000)
    rings = _checked_count(rings, "rings", 1, 10_000)
    if not (arm > 2 * thickness and bore < thickness / 2):
        raise InputError("need arm > 2·thickness and bore < thickness/2")
    centre = np.array([(arm + thickness) / 2 + thickness / 2, thickness / 2])
    step = spacing or 2 * bore * math.sin(math.pi / segments)
    outline = np.array(
        [[0, 0], [arm, 0], [arm, thickness], [thickness, thickness], [thickness, arm], [0, arm]],
        dtype=float,
    )
    boundary = []
    for start, stop in zip(outline, np.roll(outline, -1, axis=0), strict=True):
        pieces = max(1, math.ceil(np.linalg.norm(stop - start) / step))
        t = np.arange(pieces) / pieces
        boundary.append(start + t[:, None] * (stop - start))
    outer = np.concatenate(boundary)
    angle = 2 * math.pi * np.arange(segments) / segments
    hole = centre + bore * np.c_[np.cos(angle), np.sin(angle)]
    profile = np.vstack([outer, hole])
    cells = Delaunay(profile).simplices
    centroid = profile[cells].mean(axis=1)
    inside_l = (centroid[:, 0] <= thickness) | (centroid[:, 1] <= thickness)
    outside_hole = np.linalg.norm(centroid - centre, axis=1) > bore
    cells = cells[inside_l & outside_hole]
    loops = [np.arange(len(outer)), len(outer) + np.arange(segments)[::-1]]
    _require_conforming(cells, loops, "L-bracket profile")
    # Orient the cap triangles counter-clockwise in (x, z).
    p = profile[cells]
    signed = (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - (p[:, 2, 0] - p[:, 0, 0]) * (
        p[:, 1, 1] - p[:, 0, 1]
    )
    cells = np.where((signed < 0)[:, None], cells[:, ::-1], cells)
    layers = rings + 1
    ys = np.linspace(0.0, width, layers)
    count = len(profile)
    points = np.concatenate([np.c_[profile[:, 0], np.full(count, y), profile[:, 1]] for y in ys])
    # Normal of (x, z) counter-clockwise triangles mapped to (x, y, z) points along −y: the
    # y = 0 cap keeps that order (outward −y), the far cap reverses it.
    faces = [cells, cells[:, ::-1] + (layers - 1) * count]
    for loop in loops:
        a, b = loop, np.roll(loop, -1)
        for layer in range(layers - 1):
            lo, hi = layer * count, (layer + 1) * count
            faces += [np.c_[a + lo, a + hi, b + hi], np.c_[a + lo, b + hi, b + lo]]
    mesh = TriangleMesh(points, np.concatenate(faces).astype(np.int64), "")
    name = f"L-bracket arm={arm:g} t={thickness:g} w={width:g} bore={bore:g} {segments} seg"
    return TriangleMesh(mesh.points, _outward(mesh), name + f" step {step:.3g} rings {rings}")


def gear(
    teeth: int = 200,
    faces: int = 100_000,
    module: float = 1.0,
    width: float = 20.0,
    bore: float = 30.0,
) -> TriangleMesh:
    """A spur gear as a CAD export writes it: the tooth profile extruded along z, one strip of
    wall triangles across the whole face width, and caps fanned between the profile and the
    bore (long thin triangles everywhere: the median aspect is in the hundreds).

    The profile in polar coordinates: per tooth a root land, a rising flank (an involute-like
    curve), a tip land and a falling flank, with sharp corners between them; root radius
    m(z/2 − 1.25), tip radius m(z/2 + 1), m the module and z the number of teeth. The bore (a
    regular polygon of radius ``bore``) has a sixteenth of the profile's points.

    Parameters
    ----------
    teeth : int
        Number of teeth z.
    faces : int
        About how many triangles (8 per point of the profile and bore together: each loop gives
        two wall triangles per segment, and each cap one triangle per point of either loop).
    module, width, bore : float
        Tooth size m, face width (the extrusion length) and bore radius.
    """
    teeth = _checked_count(teeth, "teeth", 6, 100_000)
    faces = _checked_count(faces, "faces", 100, 100_000_000)
    module, width, bore = (
        _positive(v, n) for v, n in ((module, "module"), (width, "width"), (bore, "bore"))
    )
    root, tip = module * (teeth / 2 - 1.25), module * (teeth / 2 + 1)
    if not bore < root:
        raise InputError(f"the bore ({bore:g}) must lie inside the root circle ({root:g})")
    # faces ≈ 4·(profile + bore points), with a sixteenth of them on the bore.
    per_tooth = max(8, round(faces / 4 * 16 / 17 / teeth))
    u = np.arange(per_tooth) / per_tooth  # position within one tooth's angular pitch
    # Root land [0, .2), rising flank [.2, .4), tip land [.4, .6), falling flank [.6, .8),
    # root land [.8, 1); the flanks bulge like an involute.
    rise = np.clip((u - 0.2) / 0.2, 0, 1)
    fall = np.clip((0.8 - u) / 0.2, 0, 1)
    height = np.minimum(1 - (1 - rise) ** 1.5, 1 - (1 - fall) ** 1.5)
    radius = np.tile(root + (tip - root) * height, teeth)
    theta = 2 * math.pi * (np.arange(teeth)[:, None] + u).reshape(-1) / teeth
    outer = np.c_[radius * np.cos(theta), radius * np.sin(theta)]
    holes = max(6, round(len(outer) / 16))
    phi = 2 * math.pi * np.arange(holes) / holes
    inner = bore * np.c_[np.cos(phi), np.sin(phi)]
    profile = np.vstack([outer, inner])
    n_out = len(outer)
    # The cap: a zipper between the two loops in the order of their angles (both loops are
    # star-shaped about the axis, so the triangles do not overlap).
    angles = np.concatenate([theta, phi])
    order = np.argsort(angles, kind="stable")
    cell_list: list[tuple[int, int, int]] = []
    i = j = 0
    steps = np.r_[np.ones(n_out, dtype=bool), np.zeros(holes, dtype=bool)][order]
    for outer_step in steps.tolist():
        if outer_step:
            cell_list.append((i % n_out, (i + 1) % n_out, n_out + j % holes))
            i += 1
        else:
            cell_list.append((i % n_out, n_out + (j + 1) % holes, n_out + j % holes))
            j += 1
    cells = np.array(cell_list, dtype=np.int64)
    p = profile[cells]
    signed = (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - (p[:, 2, 0] - p[:, 0, 0]) * (
        p[:, 1, 1] - p[:, 0, 1]
    )
    cells = np.where((signed < 0)[:, None], cells[:, ::-1], cells)  # counter-clockwise
    count = len(profile)
    points = np.vstack([np.c_[profile, np.zeros(count)], np.c_[profile, np.full(count, width)]])
    tris = [cells[:, ::-1], cells + count]  # z = 0 faces down, z = width up
    for loop, forward in ((np.arange(n_out), True), (n_out + np.arange(holes), False)):
        a = loop if forward else loop[::-1]
        b = np.roll(a, -1)
        tris += [np.c_[a, b, b + count], np.c_[a, b + count, a + count]]
    name = f"gear z={teeth} m={module:g} width={width:g} bore={bore:g} {per_tooth} points per tooth"
    return TriangleMesh(points, np.concatenate(tris).astype(np.int64), name)


def triangle_aspect(mesh: TriangleMesh) -> np.ndarray:
    """Per triangle, its longest edge over the height onto it (1.15 for an equilateral one)."""
    p = mesh.points[mesh.triangles]
    edges = np.linalg.norm(p - np.roll(p, -1, axis=1), axis=2).max(axis=1)
    doubled = np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
    with np.errstate(divide="ignore"):
        return edges**2 / doubled


def _require_conforming(cells: np.ndarray, loops: list[np.ndarray], what: str) -> None:
    """Raise unless every boundary segment of ``loops`` is an edge of the triangulation."""
    edges = np.sort(np.concatenate([cells[:, [0, 1]], cells[:, [1, 2]], cells[:, [2, 0]]]), 1)
    have = {tuple(e) for e in edges.tolist()}
    for loop in loops:
        for a, b in zip(loop, np.roll(loop, -1), strict=True):
            if (min(a, b), max(a, b)) not in have:
                raise InputError(f"{what}: boundary points too sparse for a conforming cap")


def _outward(mesh: TriangleMesh) -> np.ndarray:
    """The faces oriented so that the signed volume is positive (outward normals)."""
    p = mesh.points[mesh.triangles]
    volume = np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum()
    return mesh.triangles if volume > 0 else mesh.triangles[:, ::-1]


def coarse_and_fine() -> dict[str, tuple[TriangleMesh, TriangleMesh]]:
    """Every part of the module as (coarse, fine), named."""
    return {
        "cylinder": (capped_cylinder(rings=2), capped_cylinder(rings=200, fan_caps=False)),
        "bar": (bar(), bar(4.0)),
        "plate": (plate(), plate(0.3)),
        "cube": (cube(), cube(4.0)),
        "bracket": (l_bracket(), l_bracket(spacing=0.1, rings=16)),
    }
