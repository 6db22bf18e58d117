"""Accuracy and speed of ``vorobound lfs`` (:func:`vorobound.sampling.lfs.estimate.estimate_lfs`).

Run: ``python benchmarks/bench_lfs.py [--quick]``. Prints five tables; docs/lfs.md shows the
same measurements, rendered by docs/examples/lfs_*.py from the functions here:

* accuracy: relative error of L at the vertices of generated sphere and torus meshes against
  the exact L (sphere: R; torus: min(r, distance to the axis)), from the vertices only
  (``samples=0``) and with the default fitted edge midpoints, with the targets of the issue
  (median ≤ 1e-3, largest ≤ 2 %);
* added points: where the edge midpoints are placed (flat triangle, PN triangle, quartic fit,
  exact surface), how far that is from the surface, and the error of L that results;
* growth: time and accuracy against the sample size N on one mesh;
* speed: wall time against the vertex count, with the bare scipy Delaunay triangulation of the
  same (jittered) vertices as the in-run baseline (ratio column); target: 10⁵ vertices in
  ≤ 30 s on 2 cores;
* a cube: L near its sharp edges, in units of the mesh edge length;
* CAD parts (issue table): the meshes a new user exports (long thin triangles, sharp edges),
  the true range of L against the estimate;
* triangulation independence: L of a coarse and a fine triangulation of each CAD test part at
  common surface points (target: within 5 %), and the advised sample counts (within 10 %);
* scale (``--scale``): a 10⁵-face CAD-like part (an L-bracket with a bore) through the command
  line, ``vorobound lfs`` (target ≤ 60 s) and ``vorobound advise --mesh`` (≤ 90 s), wall and
  CPU seconds and peak memory of each process; the stage split of the estimate on brackets and
  torus grids of growing size, and the growth exponent of its time (``--big`` adds the
  10⁶-vertex torus: target ≤ 10 min and ≤ 8 GB). Each measurement is a process of its own.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
import warnings
from dataclasses import dataclass

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))

import numpy as np  # noqa: E402

from vorobound.errors import VoroboundWarning  # noqa: E402
from vorobound.sampling.io.meshes import TriangleMesh  # noqa: E402
from vorobound.sampling.lfs.curved import edge_midpoints  # noqa: E402
from vorobound.sampling.lfs.estimate import estimate_lfs  # noqa: E402
from vorobound.sampling.lfs.medial import JITTER, nearest_spacing  # noqa: E402
from vorobound.sampling.lfs.mesh_quality import prepare_mesh, vertex_normals  # noqa: E402
from vorobound.sampling.surfaces import analytic as surfaces  # noqa: E402
from vorobound.sampling.surfaces import cad_meshes  # noqa: E402
from vorobound.sampling.surfaces.demo_meshes import cube_mesh, icosphere, torus_mesh  # noqa: E402
from vorobound.sampling.surfaces.mesh import points_on_mesh  # noqa: E402

MEDIAN_TARGET, WORST_TARGET, SECONDS_TARGET = 1e-3, 0.02, 30.0


@dataclass(frozen=True)
class Case:
    """A generated mesh whose vertices lie on a surface with known L."""

    label: str
    mesh: TriangleMesh
    shape: surfaces.RevolutionShape

    @property
    def exact(self) -> np.ndarray:
        return self.shape.lfs_at(self.mesh.points)


@dataclass(frozen=True)
class Errors:
    """Relative error of L at the vertices, and the run that produced it."""

    median: float
    p99: float
    largest: float
    over: float
    """Largest overestimate (L − exact)/exact, 0 if L never exceeds the exact value: the
    direction that makes a sampling density derived from L too coarse."""
    samples: int
    seconds: float

    @property
    def meets_targets(self) -> bool:
        return self.median <= MEDIAN_TARGET and self.largest <= WORST_TARGET


def timed(mesh: TriangleMesh, **options):
    """``estimate_lfs`` without its warnings, and its wall time."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", VoroboundWarning)
        start = time.perf_counter()
        estimate = estimate_lfs(mesh, **options)
        return estimate, time.perf_counter() - start


def measure(case: Case, **options) -> Errors:
    estimate, seconds = timed(case.mesh, **options)
    return errors_of(estimate.lfs, case.exact, estimate.sample_count, seconds)


def errors_of(values, exact, samples: int, seconds: float) -> Errors:
    signed = (values - exact) / exact
    error = np.abs(signed)
    return Errors(
        float(np.median(error)),
        float(np.quantile(error, 0.99)),
        float(error.max()),
        max(float(signed.max()), 0.0),
        samples,
        seconds,
    )


def single_precision(case: Case) -> Case:
    """The same mesh with coordinates rounded to float32, as an STL file stores them."""
    points = case.mesh.points.astype(np.float32).astype(float)
    mesh = TriangleMesh(points, case.mesh.triangles, case.mesh.name)
    return Case(case.label + ", single precision", mesh, case.shape)


def torus_case(major: float, minor: float, around: int, tube: int, jitter: float = 0.0) -> Case:
    mesh = torus_mesh(major, minor, around, tube, jitter=jitter, seed=1)
    label = f"torus ({major:g}, {minor:g}) {around}×{tube}" + (
        f", jitter {jitter:g}" if jitter else ""
    )
    return Case(label, mesh, surfaces.TorusShape(major, minor))


def sphere_case(level: int) -> Case:
    return Case(f"icosphere level {level}", icosphere(1.0, level), surfaces.SphereShape(1.0))


def accuracy_cases(quick: bool = False) -> list[Case]:
    """Spheres, both tori on grids and jittered, and single-precision copies (as STL stores
    them)."""
    cases = [sphere_case(3), sphere_case(5)]
    grids = [(96, 32), (192, 64)] + ([] if quick else [(384, 128)])
    for major in (3.0, 1.5):
        cases += [torus_case(major, 1.0, a, t) for a, t in grids]
        cases += [torus_case(major, 1.0, a, t, jitter=0.2) for a, t in ((96, 32), (192, 64))]
    rounded = [torus_case(3.0, 1.0, 192, 64), torus_case(1.5, 1.0, 96, 32, 0.2), sphere_case(5)]
    rounded += [] if quick else [sphere_case(6)]
    return cases + [single_precision(case) for case in rounded]


def accuracy(case: Case) -> tuple[Errors, Errors]:
    """Errors from the vertices only and with the default sample."""
    return measure(case, samples=0), measure(case)


def added_point_rows(mesh: TriangleMesh, shape) -> list[tuple[str, float, Errors]]:
    """(placement, median distance of the added points from the surface / edge length, errors
    of L at the original vertices) for each way of adding one point per edge."""
    prepared = prepare_mesh(mesh)
    points, edges = prepared.points, prepared.edges
    normals = vertex_normals(prepared)
    ends = points[edges]
    length = np.linalg.norm(ends[:, 1] - ends[:, 0], axis=1)
    fitted = edge_midpoints(prepared, normals, np.zeros(len(edges), dtype=bool), len(edges))
    order = np.lexsort(fitted.edges.T[::-1])
    assert len(fitted.edges) == len(edges), "every edge of these meshes gets a fit"
    flat = ends.mean(axis=1)
    placements = {
        "flat triangles": flat,
        "PN triangles (cubic, from vertex normals)": _pn_midpoints(ends, normals[edges]),
        "quartic fit (this estimator)": fitted.points[order],
        "exact surface (nearest point)": _to_unit(
            prepared, shape.project(_to_mesh(prepared, flat))[0]
        ),
    }
    exact = shape.lfs_at(mesh.points)
    vertices_only, _ = timed(mesh, samples=0)
    rows = [("none (vertices only)", 0.0, errors_of(vertices_only.lfs, exact, len(points), 0.0))]
    for label, added in placements.items():
        on_mesh = _to_mesh(prepared, added)
        distance = np.linalg.norm(on_mesh - shape.project(on_mesh)[0], axis=1) / prepared.scale
        split = _split(prepared, added)
        estimate, _ = timed(split, samples=0)
        values = estimate.lfs[: len(points)][prepared.original_to_merged]
        rows.append(
            (
                label,
                float(np.median(distance / length)),
                errors_of(values, exact, len(split.points), 0.0),
            )
        )
    return rows


def _to_mesh(prepared, unit_points):
    return prepared.centre + prepared.scale * unit_points


def _to_unit(prepared, mesh_points):
    return (mesh_points - prepared.centre) / prepared.scale


def _pn_midpoints(ends: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """Midpoint of the cubic edge curve of a PN triangle (Vlachos et al., 2001):
    (a + b)/2 − (w_ab·n_a + w_ba·n_b)/8 with w_ab = (b − a)·n_a; blind to the normals' signs."""
    a, b = ends[:, 0], ends[:, 1]
    w_ab = ((b - a) * normals[:, 0]).sum(axis=1)
    w_ba = ((a - b) * normals[:, 1]).sum(axis=1)
    return 0.5 * (a + b) - (w_ab[:, None] * normals[:, 0] + w_ba[:, None] * normals[:, 1]) / 8


def _split(prepared, middles: np.ndarray) -> TriangleMesh:
    """The prepared mesh with each triangle split into four at the given edge points (in the
    mesh's own units)."""
    edges, faces = prepared.edges, prepared.triangles
    count = len(prepared.points)
    key = edges[:, 0] * count + edges[:, 1]
    order = np.argsort(key)

    def middle(a, b):
        low, high = np.minimum(a, b), np.maximum(a, b)
        return count + order[np.searchsorted(key, low * count + high, sorter=order)]

    a, b, c = faces.T
    ab, bc, ca = middle(a, b), middle(b, c), middle(c, a)
    split = np.concatenate(
        [np.c_[a, ab, ca], np.c_[b, bc, ab], np.c_[c, ca, bc], np.c_[ab, bc, ca]]
    )
    points = _to_mesh(prepared, np.vstack([prepared.points, middles]))
    return TriangleMesh(points, split, "split")


def growth_cases(quick: bool = False) -> list[tuple[Case, tuple[int, ...]]]:
    """Meshes and sample sizes (multiples of the vertex count) for the growth table."""
    cases = [
        (torus_case(3.0, 1.0, 96, 32), (1, 2, 3, 4)),
        (torus_case(1.5, 1.0, 192, 64), (1, 2, 3, 4)),
    ]
    if not quick:
        cases.append((torus_case(3.0, 1.0, 384, 128, jitter=0.2), (1, 2)))
    return cases


def growth(case: Case, multiple: int) -> Errors:
    """Errors and time with samples = multiple × (vertices)."""
    return measure(case, samples=multiple * len(case.mesh.points))


def speed_meshes(quick: bool) -> list[TriangleMesh]:
    meshes = [torus_mesh(3.0, 1.0, 4 * n, n) for n in (32, 64, 128)]
    meshes += [icosphere(1.0, level) for level in (5, 6)]
    if not quick:
        meshes += [torus_mesh(3.0, 1.0, 768, 128), icosphere(1.0, 7)]
    return meshes


def speed_row(mesh: TriangleMesh) -> tuple[int, float, float, int, float]:
    """(vertices, seconds from the vertices only, seconds of the bare Delaunay triangulation of
    the same jittered and shuffled vertices, default sample size, seconds with it)."""
    from scipy.spatial import Delaunay

    _, alone = timed(mesh, samples=0)
    random = np.random.default_rng(0)
    points = mesh.points / np.ptp(mesh.points, axis=0).max()
    moved = points + JITTER * nearest_spacing(points)[:, None] * random.standard_normal(
        points.shape
    )
    start = time.perf_counter()
    Delaunay(moved[random.permutation(len(points))])
    base = time.perf_counter() - start
    estimate, seconds = timed(mesh)
    return len(mesh.points), alone, base, estimate.sample_count, seconds


def cube_rows(divisions=(4, 8, 16)) -> list[tuple[int, float, float, float, int]]:
    """(divisions, h, median L on the cube edges / h, one step in / h, added midpoints)."""
    rows = []
    for count in divisions:
        mesh = cube_mesh(1.0, count)
        estimate, _ = timed(mesh)
        h = 2.0 / count
        gap = np.sort(1 - np.abs(mesh.points), axis=1)[:, 1]  # distance to the nearest edge
        on_edge, one_in = np.isclose(gap, 0), np.isclose(gap, h)
        rows.append(
            (
                count,
                h,
                float(np.median(estimate.lfs[on_edge]) / h),
                float(np.median(estimate.lfs[one_in]) / h),
                estimate.added_samples,
            )
        )
    return rows


def issue_meshes() -> list[tuple[str, TriangleMesh, str, float]]:
    """The five meshes of the issue that reported 50x overestimates: (label, mesh, true range
    of L, its upper end)."""
    return [
        (
            "cylinder r = 1, length 100, 32 segments, 2 rings, flat caps",
            cad_meshes.capped_cylinder(1.0, 100.0, 32, 2),
            "≤ 1",
            1.0,
        ),
        (
            "same cylinder, r = 10⁻³",
            cad_meshes.capped_cylinder(1e-3, 100.0, 32, 2),
            "≤ 10⁻³",
            1e-3,
        ),
        ("box 100 × 1 × 1 (12 triangles)", cad_meshes.bar(), "≤ 0.5", 0.5),
        ("plate 100 × 100 × 1 (12 triangles)", cad_meshes.plate(), "≤ 0.5", 0.5),
        (
            "same cylinder, 200 rings along its length",
            cad_meshes.capped_cylinder(1.0, 100.0, 32, 200),
            "≤ 1",
            1.0,
        ),
    ]


def issue_row(mesh: TriangleMesh) -> tuple[float, float, float, float]:
    """(smallest, largest L at the vertices, largest L at 20 000 surface points, seconds)."""
    estimate, seconds = timed(mesh)
    surface = estimate.at(surface_points(mesh, 20_000))
    return float(estimate.lfs.min()), float(estimate.lfs.max()), float(surface.max()), seconds


def surface_points(mesh: TriangleMesh, count: int, seed: int = 0) -> np.ndarray:
    """Points uniform by area on the mesh's triangles."""
    return points_on_mesh(mesh, count, np.random.default_rng(seed))


@dataclass(frozen=True)
class Agreement:
    """L of the coarse and fine copies of one part at common points, and their advice."""

    name: str
    vertices: tuple[int, int]
    median: float
    p99: float
    largest: float
    over_target: float
    """Share of the points where the two differ by more than 5 %."""
    integral_ratio: float
    """∫dA/L² of the coarse copy over the fine one (the advised counts are proportional)."""
    feature_ratio: float
    """∫ds/L along the features, coarse over fine (the feature-ball counts)."""
    seconds: tuple[float, float]


def agreement(name: str, coarse: TriangleMesh, fine: TriangleMesh) -> Agreement:
    a, ta = timed(coarse)
    b, tb = timed(fine)
    points = surface_points(fine, 20_000)
    la, lb = a.at(points), b.at(points)
    rel = np.abs(la - lb) / np.minimum(la, lb)
    return Agreement(
        name,
        (len(coarse.points), len(fine.points)),
        float(np.median(rel)),
        float(np.percentile(rel, 99)),
        float(rel.max()),
        float((rel > 0.05).mean()),
        a.surface().inv_lfs_sq_integral / b.surface().inv_lfs_sq_integral,
        a.feature_inv_lfs / b.feature_inv_lfs if b.feature_inv_lfs else 1.0,
        (ta, tb),
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="skip the meshes over 40k vertices")
    parser.add_argument("--cad", action="store_true", help="only the CAD tables")
    parser.add_argument("--scale", action="store_true", help="only the scale tables (minutes)")
    parser.add_argument("--big", action="store_true", help="--scale with the 10^6-vertex torus")
    parser.add_argument(
        "--tiny", action="store_true", help="every table on tiny meshes (CI: nothing rots)"
    )
    args = parser.parse_args()
    if args.tiny:
        tiny()
        return
    if args.scale or args.big:
        _scale().tables(args.big)
        return
    cad_tables()
    if args.cad:
        return
    print("\n## Accuracy (relative error of L at the vertices): vertices only | default sample")
    print(
        f"{'mesh':44s} {'median':>8s} {'largest':>8s} {'time':>7s} | {'samples':>7s} "
        f"{'median':>8s} {'largest':>8s} {'time':>7s}"
    )
    for case in accuracy_cases(args.quick):
        alone, default = accuracy(case)
        print(
            f"{case.label:44s} {alone.median:8.1e} {alone.largest:8.1e} {alone.seconds:6.2f}s | "
            f"{default.samples:7d} {default.median:8.1e} {default.largest:8.1e} "
            f"{default.seconds:6.2f}s{'' if default.meets_targets else '  (misses a target)'}"
        )
    for case in (torus_case(1.5, 1.0, 96, 32), torus_case(1.5, 1.0, 96, 32, jitter=0.2)):
        print(f"\n## One added point per edge of the {case.label}")
        print(f"{'placement':44s} {'distance/h':>10s} {'median':>8s} {'largest':>8s}")
        for label, distance, found in added_point_rows(case.mesh, case.shape):
            print(f"{label:44s} {distance:10.1e} {found.median:8.1e} {found.largest:8.1e}")
    print("\n## Growth with the sample size N")
    print(f"{'mesh':38s} {'N':>7s} {'time':>8s} {'median':>8s} {'largest':>8s}")
    for case, multiples in growth_cases(args.quick):
        for multiple in multiples:
            found = growth(case, multiple)
            print(
                f"{case.label:38s} {found.samples:7d} {found.seconds:7.2f}s {found.median:8.1e} "
                f"{found.largest:8.1e}"
            )
    print("\n## Speed (baseline: scipy Delaunay of the same jittered, shuffled vertices)")
    print(
        f"{'mesh':28s} {'vertices':>8s} {'alone':>7s} {'Delaunay':>8s} {'ratio':>5s} "
        f"{'samples':>7s} {'default':>7s}"
    )
    for mesh in speed_meshes(args.quick):
        count, alone, base, samples, seconds = speed_row(mesh)
        flag = "" if count < 90_000 or seconds <= SECONDS_TARGET else " (over 30 s)"
        print(
            f"{mesh.name:28s} {count:8d} {alone:6.2f}s {base:7.2f}s {alone / base:5.2f} "
            f"{samples:7d} {seconds:6.2f}s{flag}"
        )
    print(f"load average: {os.getloadavg()[0]:.2f} (the machine is shared)")
    print("\n## Cube [-1, 1]^3: L near its sharp edges, in mesh edge lengths h")
    print(f"{'divisions':>9s} {'h':>6s} {'on edges':>8s} {'one step in':>11s} {'midpoints':>9s}")
    for count, h, on_edge, one_in, added in cube_rows():
        print(f"{count:9d} {h:6.3f} {on_edge:8.3f} {one_in:11.3f} {added:9d}")


def tiny() -> None:
    """Every table's code on the smallest meshes (that it runs; the numbers mean nothing),
    but the added points (26 CPU-s even on the coarsest grid where every edge gets a fit;
    docs/examples/lfs_points.py runs them in the slow tests)."""
    case = torus_case(1.5, 1.0, 48, 16)
    for errors in (*accuracy(sphere_case(1)), growth(case, 1)):
        assert np.isfinite(errors.median), errors
    count, *_ = speed_row(icosphere(1.0, 1))
    cubes = cube_rows((4,))
    low, high, surface, _ = issue_row(cad_meshes.bar())
    a = agreement("cube", *cad_meshes.coarse_and_fine()["cube"])
    print(
        f"tiny: speed row of {count} vertices, {len(cubes)} cube "
        f"row, bar L {low:.3g}–{high:.3g} (surface {surface:.3g}), cube coarse/fine median "
        f"{a.median:.1e}"
    )
    _scale().tables(big=False, tiny=True)


def cad_tables() -> None:
    print("\n## CAD parts of the issue: true range of L and the estimate")
    for label, mesh, truth, _ in issue_meshes():
        low, high, surface, seconds = issue_row(mesh)
        print(
            f"{label:62s} {truth:>7s}  {low:.4g} – {high:.4g} "
            f"(surface max {surface:.4g}) {seconds:.1f}s"
        )
    print("\n## Coarse vs fine triangulation of one part (relative difference of L)")
    for name, (coarse, fine) in cad_meshes.coarse_and_fine().items():
        a = agreement(name, coarse, fine)
        print(
            f"{name:9s} {a.vertices[0]:>6d}/{a.vertices[1]:<7d} median {a.median:.1e} p99 "
            f"{a.p99:.2e} max {a.largest:.2e}  ∫1/L² ratio {a.integral_ratio:.4f}  feature "
            f"{a.feature_ratio:.4f}  {a.seconds[0]:.1f}s / {a.seconds[1]:.1f}s"
        )


def _scale():
    """benchmarks/lfs_scale.py, the scale tables and the processes that measure them."""
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import lfs_scale

    return lfs_scale


if __name__ == "__main__":
    if sys.argv[1:2] == ["--child"]:
        _scale().child(sys.argv[2:])
    elif sys.argv[1:2] == ["--measure"]:
        _scale().measure_child(sys.argv[2:])
    else:
        main()
