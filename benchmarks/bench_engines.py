"""Each stage against the engine underneath, side by side in the same run (issue 35).

Run: ``python benchmarks/bench_engines.py check --sizes 1e5,1e6``,
``python benchmarks/bench_engines.py tile --sizes 1e6``,
``python benchmarks/bench_engines.py binding --sizes 1e5`` and
``python benchmarks/bench_engines.py reconstruct --eps 0.03 [--stages]`` and
``python benchmarks/bench_engines.py cells --eps 0.03 [--cube]`` and
``python benchmarks/bench_engines.py delaunay --sizes 2.6e5,1e6``. Every measurement runs
in its own fresh process; printed are CPU and wall seconds and the load average before and after
(the machine is shared: CPU seconds are the steadier measure).

* ``check``: on the torus row sample of about N balls (benchmarks/bench_scale.py makes it, in
  ``--data``), CGAL's bare regular triangulation of the balls with the filler points check
  uses (GUDHI ``DelaunayComplex`` built, no simplex tree; then with its simplex tree), against
  ``vorobound check --balls F --eps E --workers 1`` end to end (``--engines auto,gudhi``: one
  run per engine; ``auto`` is geogram's where it was built). Beside CGAL, geogram's exact
  regular triangulation of the same points (:func:`vorobound.sampling.geogram_delaunay
  .regular_tetrahedra`), then the check's route (the triangles among the balls, read in C++).
  Target: check ≤ 2.5× the bare triangulation at 10⁶ balls.
* ``tile``: the stages of one tile of that sample (a sixth of the balls, one thread), each
  timed apart against CGAL's triangulation of the same tile: filler points, CGAL, geogram's
  regular triangulation with the triangles read (the ``geogram`` engine's route), GUDHI's
  simplex tree, its serialization, reading the triangles, freeing both, the seeds (their
  geometry and the coverage queries) and the 16 nearest neighbours of the pair conditions.
* ``binding``: the other maintained CGAL binding on PyPI, the SWIG bindings of the ``cgal``
  package (not a dependency: the task prints a skip line when it is not installed), on the same
  balls and filler points as ``check``: its own regular triangulation, then the two ways it can
  hand the triangles over (a Python loop over ``finite_facets`` mapping every vertex back to its
  ball, or ``write_to_file`` read back with numpy, the vertices mapped by a Python loop over
  ``finite_vertices``), against GUDHI's ``DelaunayComplex`` with its simplex tree read by
  :mod:`vorobound.sampling.simplex_kernel`, the route ``check`` takes.
* ``reconstruct``: the seeds of the torus (3, 1) at ε (0.03: about 5.4·10⁵ seeds), CGAL's
  Delaunay tetrahedralization of them (``DelaunayComplex`` built; then with its simplex tree)
  against M̂ from the seeds (:func:`vorobound.sampling.reconstruct.facets.inout_facets`, CGAL
  with the compiled steps and with the numpy steps, and qhull) and the whole ``reconstruct`` of
  the surface. Target: M̂ ≤ 1.5× CGAL's
  tetrahedralization.
* ``cells``: the tetrahedra of the seeds and their face-neighbour table (what M̂ starts from),
  four ways on the same seeds (the torus (3, 1) at ε, or with ``--cube`` the CAD cube [−1, 1]³
  of issue 32 at ε): CGAL's bare triangulation (GUDHI ``DelaunayComplex`` built, the issue's
  baseline); CGAL's route (that, GUDHI's simplex tree read in bulk, the compiled face
  neighbours); M̂'s route (geogram's compiled module with its double-double stage, the same
  neighbours); qhull (``scipy.spatial.Delaunay``, the cross-check); and the ``cgal`` package's
  SWIG bindings (not a dependency: a skip line when not installed): the seeds handed over as
  one array (``Point_set_3.insert_range``), ``Delaunay_triangulation_3`` built from them in one
  call, ``write_to_file`` at 17 digits (exact coordinates) read back with numpy, vertices
  matched to the seeds by sorting, the cells and their neighbour table brought to M̂'s layout
  (finite cells, rows ascending, rows in lexicographic order). Each in a fresh process, with
  its peak memory; the SWIG route's arrays are compared with CGAL's route's (a digest). A
  sixth route, geogram's tetrahedra alone, shows the share of the neighbours, and a seventh
  the same with its double-double stage off (the same tetrahedra, compared by digest).
* ``delaunay``: the unweighted triangulation three ways (CGAL's bare build; the CGAL route of
  :func:`vorobound.sampling.simplices.delaunay_tetrahedra`, simplex tree read in bulk; geogram's
  compiled module, ``lfs``'s route) on N uniform random points and on the jittered vertices of
  the torus (3, 1) with about N vertices, as ``lfs`` triangulates them; the arrays of the two
  routes compared (equal in general position).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))


def _cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def _child(task: str, *args: str) -> dict:
    """One measurement in a fresh process (this script with ``--child``)."""
    load = os.getloadavg()[0]
    done = subprocess.run(
        [sys.executable, __file__, "--child", task, *args],
        capture_output=True,
        text=True,
        check=False,
    )
    if done.returncode:
        raise SystemExit(f"{task} failed: {done.stderr}")
    out = json.loads(done.stdout.strip().splitlines()[-1])
    out["load"] = (load, os.getloadavg()[0])
    return out


def _read_balls(path: str):
    import numpy as np
    import pyarrow.parquet as pq

    table = pq.read_table(path)
    centers = np.column_stack([table[c].to_numpy() for c in ("x", "y", "z")])
    return centers, table["r"].to_numpy()


def child_cgal_balls(path: str) -> dict:
    """CGAL's regular triangulation of the balls with check's filler points."""
    import gudhi
    import numpy as np

    from vorobound.sampling.guides.triangles import filler_points

    centers, radii = _read_balls(path)
    filler = filler_points(centers, float(radii.max()))
    points = np.vstack([centers, filler])
    weights = np.concatenate([radii**2, np.zeros(len(filler))])
    cpu, wall = _cpu(), time.perf_counter()
    complex_ = gudhi.DelaunayComplex(points=points, weights=weights, precision="fast")
    built = (_cpu() - cpu, time.perf_counter() - wall)
    tree = complex_.create_simplex_tree()
    with_tree = (_cpu() - cpu, time.perf_counter() - wall)
    return {"balls": len(centers), "filler": len(filler), "built": built, "tree": with_tree,
            "simplices": int(tree.num_simplices())}  # fmt: skip


def child_geogram_balls(path: str) -> dict:
    """geogram's exact regular triangulation of the same balls and filler points: its finite
    tetrahedra (geogram's order), then the check's route, the triangles among the balls read in
    C++ (lexicographic order)."""
    import numpy as np

    from vorobound.sampling import geogram_delaunay
    from vorobound.sampling.guides.triangles import filler_points

    centers, radii = _read_balls(path)
    filler = filler_points(centers, float(radii.max()))
    points = np.vstack([centers, filler])
    weights = np.concatenate([radii**2, np.zeros(len(filler))])
    cpu, wall = _cpu(), time.perf_counter()
    tetrahedra = geogram_delaunay.regular_tetrahedra(points, weights, ordered=False)
    cells = (_cpu() - cpu, time.perf_counter() - wall)
    cpu, wall = _cpu(), time.perf_counter()
    triangles = geogram_delaunay.regular_triangles(points, weights, len(centers))
    route = (_cpu() - cpu, time.perf_counter() - wall)
    if tetrahedra is None or triangles is None:
        raise SystemExit("geogram's regular triangulation refused the balls")
    return {"cells": cells, "route": route, "tetrahedra": len(tetrahedra),
            "triangles": len(triangles), "peak_gb": _peak_gb()}  # fmt: skip


def child_binding(path: str) -> dict:
    """The ``cgal`` package's SWIG regular triangulation and its two ways out, against GUDHI."""
    import gudhi
    import numpy as np

    from vorobound.sampling.guides.triangles import filler_points
    from vorobound.sampling.simplices import tree_simplices

    try:
        from CGAL.CGAL_Kernel import Point_3, Weighted_point_3
        from CGAL.CGAL_Triangulation_3 import Regular_triangulation_3
    except ImportError:
        return {"skipped": "the cgal package (SWIG bindings) is not installed"}
    centers, radii = _read_balls(path)
    filler = filler_points(centers, float(radii.max()))
    points = np.vstack([centers, filler])
    weights = np.concatenate([radii**2, np.zeros(len(filler))])
    seconds: dict[str, float] = {}

    def lap(name: str, start: float) -> float:
        seconds[name] = _cpu() - start
        return _cpu()

    start = _cpu()
    tree = gudhi.DelaunayComplex(points=points, weights=weights, precision="fast")
    start = lap("GUDHI DelaunayComplex (built)", start)
    gudhi_triangles = tree_simplices(tree.create_simplex_tree(), tetrahedra=False)[0]
    start = lap("GUDHI simplex tree + bulk read (check's route)", start)
    wrapped = [
        Weighted_point_3(Point_3(*map(float, p)), float(w))
        for p, w in zip(points, weights, strict=True)
    ]
    start = lap("SWIG: weighted points made in Python", start)
    triangulation = Regular_triangulation_3()
    triangulation.insert(wrapped)
    start = lap("SWIG: Regular_triangulation_3 (built)", start)
    index = {tuple(p): i for i, p in enumerate(points.tolist())}

    def ball(vertex) -> int:
        p = vertex.point().point()
        return index[(p.x(), p.y(), p.z())]

    looped = []
    for cell, opposite in triangulation.finite_facets():
        looped.append([ball(cell.vertex(k)) for k in range(4) if k != opposite])
    start = lap("SWIG: loop over finite_facets", start)
    with tempfile.TemporaryDirectory() as folder:
        text = os.path.join(folder, "triangulation.txt")
        triangulation.write_to_file(text)
        order = [-1] + [ball(v) for v in triangulation.finite_vertices()]
        with open(text) as stream:
            stream.readline()
            n_vertices = int(stream.readline())
            for _ in range(n_vertices):
                stream.readline()
            n_cells = int(stream.readline())
            cells = np.loadtxt(stream, dtype=np.int64, max_rows=n_cells, ndmin=2)
        start = lap("SWIG: write_to_file, read back, vertices mapped", start)
    mapped = np.asarray(order)[cells]
    return {"balls": len(centers), "filler": len(filler), "seconds": seconds,
            "triangles": {"gudhi": int(len(gudhi_triangles)), "swig loop": len(looped)},
            "cells": int((mapped >= 0).all(axis=1).sum())}  # fmt: skip


def child_check(path: str, eps: str, engine: str = "auto") -> dict:
    """``vorobound check`` on one worker, in this process."""
    wall = time.perf_counter()
    done = subprocess.run(
        [sys.executable, "-m", "vorobound", "check", "--balls", path, "--eps", eps,
         "--workers", "1", "--json", "--engine", engine],
        capture_output=True, text=True, check=False,
    )  # fmt: skip
    wall = time.perf_counter() - wall
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode not in (0, 1):
        raise SystemExit(done.stderr)
    summary = json.loads(done.stdout)
    tiles = summary.get("tiles", {})
    return {"cpu": usage.ru_utime + usage.ru_stime, "wall": wall, "engine": summary.get("engine"),
            "guide": summary.get("n_guide_triangles"), "tiles": tiles.get("count"),
            "halo": tiles.get("halo_share"), "stages": tiles.get("cpu_seconds", {}),
            "driver": tiles.get("driver_cpu_seconds", {})}  # fmt: skip


def child_tile(path: str) -> dict:
    """One tile's stages, timed apart: the 1/6 of the balls with the smallest x and y (the
    size of a tile of 10⁶ balls), on one thread; CPU seconds of each step."""
    import math

    import gudhi
    import numpy as np
    from scipy.spatial import cKDTree

    from vorobound.geometry.threads import limited_threads
    from vorobound.sampling import geogram_delaunay, simplex_kernel
    from vorobound.sampling.balls import Balls
    from vorobound.sampling.guides.seeds import classify, lifted_balls, other_power, seed_pairs
    from vorobound.sampling.guides.triangles import filler_points
    from vorobound.sampling.sampler import conditions
    from vorobound.sampling.simplices import kernel_available

    centers, radii = _read_balls(path)
    cut = math.sqrt(1 / 6)
    x, y = np.quantile(centers[:, 0], cut), np.quantile(centers[:, 1], cut)
    keep = (centers[:, 0] <= x) & (centers[:, 1] <= y)
    balls = Balls(centers[keep], radii[keep])
    kernel_available()  # numba's load: a one-off cost of the process
    seconds: dict[str, float] = {}

    def timed(name, work):
        start = _cpu()
        out = work()
        seconds[name] = _cpu() - start
        return out

    with limited_threads(1):
        w = balls.weights
        filler = timed("filler points", lambda: filler_points(balls.centers, math.sqrt(w.max())))
        points = np.vstack([balls.centers, filler])
        weights = np.concatenate([w, np.zeros(len(filler))])
        complex_ = timed("CGAL triangulation", lambda: gudhi.DelaunayComplex(
            points=points, weights=weights, precision="fast"))  # fmt: skip
        if geogram_delaunay.available():  # the geogram engine's route, for comparison
            geogram_delaunay.regular_triangles(points[:1000], weights[:1000], 1000)  # loaded
            timed("geogram triangulation + triangles", lambda: geogram_delaunay
                  .regular_triangles(points, weights, len(balls)))  # fmt: skip
        tree = timed("GUDHI simplex tree", complex_.create_simplex_tree)
        start = _cpu()
        del complex_
        seconds["CGAL freed"] = _cpu() - start
        start = _cpu()
        data = np.asarray(tree.__getstate__()).view(np.uint8)
        seconds["tree serialized"] = _cpu() - start
        none3, none4 = np.empty((0, 3), np.int64), np.empty((0, 4), np.int64)
        n_tri, _, _ = simplex_kernel.read_tree(data, none3, none4)  # compiled code loaded
        triangles = np.empty((n_tri, 3), np.int64)
        start = _cpu()
        simplex_kernel.read_tree(data, triangles, none4)
        seconds["triangles read"] = _cpu() - start
        start = _cpu()
        del tree, data
        seconds["simplex tree freed"] = _cpu() - start
        triples = triangles[(triangles < len(balls)).all(axis=1)]
        classify(balls, triples[:100])  # compiled code loaded
        timed("seeds, all", lambda: classify(balls, triples))
        geometry, seeds = timed("seeds: geometry", lambda: seed_pairs(balls, triples))
        top = float(w.max())
        lifted = cKDTree(lifted_balls(balls, top))
        has = np.isfinite(seeds).all(axis=(1, 2))
        start = _cpu()
        for side in (0, 1):
            other_power(lifted, top, seeds[has, side], triples[has])
        seconds["seeds: coverage queries"] = _cpu() - start
        timed("neighbour conditions: 16 nearest", lambda: conditions.neighbours(balls.centers))
    return {"balls": len(balls), "filler": len(filler), "triangles": len(triples),
            "seconds": seconds}  # fmt: skip


def child_seeds(eps: str, out: str) -> dict:
    """The whole reconstruct of the torus (3, 1) at ε, per stage; saves the labelled seeds."""
    import numpy as np

    from vorobound.bounds.params import QualityParams
    from vorobound.reports.reconstruct import reconstruct_surface
    from vorobound.sampling.surfaces.analytic import TorusShape

    marks = {}

    def progress(task, done, total):
        marks.setdefault(task, (_cpu(), time.perf_counter()))

    cpu, wall = _cpu(), time.perf_counter()
    report = reconstruct_surface(TorusShape(3, 1), float(eps), QualityParams(), progress=progress)
    total = (_cpu() - cpu, time.perf_counter() - wall)
    np.save(out, np.column_stack([report.seeds.points, report.seeds.inside]))
    mhat = [marks[k] for k in marks if k.startswith("Delaunay")]
    after = [m for k, m in marks.items() if k == "topology" or k.startswith("topology")]
    return {"seeds": len(report.seeds), "total": total, "correct": report.topology_correct,
            "stages": list(marks), "mhat_start": mhat[0] if mhat else None,
            "topology_start": after[0] if after else None}  # fmt: skip


def child_cgal_seeds(path: str) -> dict:
    import gudhi
    import numpy as np

    seeds = np.load(path)[:, :3]
    cpu, wall = _cpu(), time.perf_counter()
    complex_ = gudhi.DelaunayComplex(points=seeds, precision="fast")
    built = (_cpu() - cpu, time.perf_counter() - wall)
    tree = complex_.create_simplex_tree()
    return {"built": built, "tree": (_cpu() - cpu, time.perf_counter() - wall),
            "tetrahedra": int(tree.num_simplices_by_dimension()[3])}  # fmt: skip


def child_mhat(path: str, triangulation: str, compiled: str = "auto") -> dict:
    """M̂ of the seeds; ``compiled`` "auto", "yes" (numba steps) or "no" (numpy steps)."""
    import numpy as np

    from vorobound.sampling.reconstruct.facets import inout_facets

    data = np.load(path)
    from vorobound.sampling.simplices import kernel_available

    kernel_available()  # numba's import is a one-off cost of the process, like importing scipy
    use = {"auto": None, "yes": True, "no": False}[compiled]
    cpu, wall = _cpu(), time.perf_counter()
    found = inout_facets(data[:, :3], data[:, 3] > 0.5, triangulation=triangulation, compiled=use)
    return {"mhat": (_cpu() - cpu, time.perf_counter() - wall),
            "facets": found.surface.n_facets, "skipped": found.skipped_seeds}  # fmt: skip


def child_stages(path: str) -> dict:
    """CPU seconds of each step of M̂ on CGAL with the compiled steps, called one by one as
    :func:`vorobound.sampling.reconstruct.facets.inout_facets` calls them (numba and its
    kernels loaded first, so each step is its own cost)."""
    import gudhi
    import numpy as np

    from vorobound.sampling import simplices
    from vorobound.sampling.reconstruct import facets

    data = np.load(path)
    inside = data[:, 3] > 0.5
    shift, unit = facets.seed_frame(data[:, :3])
    points = (data[:, :3] - shift) / unit
    kernel = facets._facets_kernel()
    warm = np.random.default_rng(0).random((40, 3))  # loads every compiled step once
    facets.inout_facets(warm, warm[:, 0] < 0.5, compiled=True)
    simplices.tree_simplices(gudhi.DelaunayComplex(points=warm).create_simplex_tree(), True)
    steps, cpu = {}, [_cpu()]

    def lap(name):
        cpu.append(_cpu())
        steps[name] = cpu[-1] - cpu[-2]

    complex_ = gudhi.DelaunayComplex(points=points, precision="fast")
    lap("CGAL DelaunayComplex")
    tree = complex_.create_simplex_tree()
    del complex_
    lap("simplex tree")
    data_bytes = tree.__getstate__()
    lap("serialization (__getstate__)")
    del data_bytes
    cpu[-1] = _cpu()
    _, tets = simplices.tree_simplices(tree, True, triangles=False)
    steps["reading (numba, with its serialization)"] = _cpu() - cpu[-1]
    cpu.append(_cpu())
    del tree
    lap("freeing the tree")
    neighbors, _ = kernel.face_neighbours(tets, len(points))
    lap("face neighbours")
    centres = facets.circumcentres(points, tets, neighbors, kernel)
    lap("circumcentres")
    cycles = facets._compiled_cycles(kernel, points, tets, neighbors, inside)
    lap("cycles and orientation")
    facets._weld(points, inside, *centres, cycles)
    lap("welding")
    return {"steps": steps, "tetrahedra": len(tets)}


def child_cube_seeds(eps: str, out: str) -> dict:
    """The labelled seeds of ``reconstruct --mesh cube.stl --eps E`` (the cube of issue 32)."""
    import numpy as np

    sys.path.insert(0, os.path.dirname(__file__))
    from bench_reconstruct import _reconstruct_cube

    seeds = _reconstruct_cube(float(eps), None).seeds
    np.save(out, np.column_stack([seeds.points, seeds.inside]))
    return {"seeds": len(seeds)}


def swig_cells(points, lap):
    """Tetrahedra (t, 4; rows ascending, in lexicographic order) and face neighbours (−1 on the
    hull) of CGAL's Delaunay triangulation through the ``cgal`` package's SWIG bindings, in M̂'s
    layout; ``lap(step)`` is called after each step."""
    import numpy as np
    from CGAL.CGAL_Point_set_3 import Point_set_3
    from CGAL.CGAL_Triangulation_3 import Delaunay_triangulation_3

    cloud = Point_set_3()
    cloud.insert_range(np.ascontiguousarray(points, dtype=float).ravel())
    lap("SWIG: seeds as one array (Point_set_3)")
    triangulation = Delaunay_triangulation_3()
    triangulation.insert(cloud.points())  # one call: CGAL sorts them in space itself
    del cloud
    lap("SWIG: Delaunay_triangulation_3 (built)")
    with tempfile.TemporaryDirectory() as folder:
        text = os.path.join(folder, "triangulation.txt")
        triangulation.write_to_file(text, 17)  # 17 digits: every coordinate exact
        del triangulation
        lap("SWIG: write_to_file, triangulation freed")
        with open(text, "rb") as stream:
            data = stream.read()
    ends = np.flatnonzero(np.frombuffer(data, np.uint8) == ord("\n"))
    n_vertices = int(data[ends[0] + 1 : ends[1]])
    vertices = np.fromstring(data[ends[1] + 1 : ends[1 + n_vertices]], sep=" ").reshape(-1, 3)
    n_cells = int(data[ends[1 + n_vertices] + 1 : ends[2 + n_vertices]])
    numbers = np.fromstring(data[ends[2 + n_vertices] + 1 :], dtype=np.int64, sep=" ")
    del data, ends
    cells, across = numbers[: 4 * n_cells].reshape(-1, 4), numbers[4 * n_cells :].reshape(-1, 4)
    lap("SWIG: the file parsed (numpy)")
    # The file lists the vertices in CGAL's order (0: the infinite vertex): match them to the
    # seeds by sorting both (a repeated seed is one vertex, matched to its first copy).
    by_seed = np.lexsort(points.T[::-1])
    ordered = points[by_seed]
    first = np.ones(len(points), dtype=bool)
    first[1:] = (ordered[1:] != ordered[:-1]).any(axis=1)
    by_vertex = np.lexsort(vertices.T[::-1])
    if not np.array_equal(vertices[by_vertex], ordered[first]):
        raise SystemExit("SWIG: the vertices written are not the seeds")
    seed_of = np.empty(n_vertices + 1, dtype=np.int64)
    seed_of[0] = -1
    seed_of[1 + by_vertex] = by_seed[first]
    finite = (cells != 0).all(axis=1)
    renumber = np.full(n_cells, -1, dtype=np.int64)
    renumber[finite] = np.arange(int(finite.sum()))
    tets, across = seed_of[cells[finite]], renumber[across[finite]]
    del cells, numbers
    lap("SWIG: vertices matched, finite cells")
    corner = np.argsort(tets, axis=1)
    tets, across = np.take_along_axis(tets, corner, 1), np.take_along_axis(across, corner, 1)
    row = np.lexsort(tets.T[::-1])
    rank = np.empty_like(row)
    rank[row] = np.arange(len(row))
    tets, across = tets[row], across[row]
    across = np.where(across >= 0, rank[np.maximum(across, 0)], -1)
    lap("SWIG: rows ascending, in lexicographic order")
    return tets, across


def child_cells(path: str, route: str) -> dict:
    """The tetrahedra and face neighbours of the seeds at ``path`` by one route: "cgal" (GUDHI
    ``DelaunayComplex`` built, no more), "gudhi" (CGAL's route), "exact" (M̂'s route),
    "geogram" (the package's compiled
    module, tetrahedra only: lfs's route), "qhull" or "swig"."""
    import hashlib

    import numpy as np

    from vorobound.sampling.reconstruct import facets

    data = np.load(path)
    shift, unit = facets.seed_frame(data[:, :3])
    points = np.ascontiguousarray((data[:, :3] - shift) / unit)
    kernel = facets._facets_kernel()
    if route in ("gudhi", "exact"):  # numba and the kernels' machine code loaded first
        warm = np.random.default_rng(0).random((40, 3))
        facets.inout_facets(warm, warm[:, 0] < 0.5, compiled=True)
    if route in ("geogram", "geogram_no_dd", "exact"):
        from vorobound.sampling import geogram_delaunay

        if not geogram_delaunay.available():
            return {"skipped": "the package's compiled module was not built"}
    if route == "swig":
        try:
            import CGAL.CGAL_Triangulation_3  # noqa: F401
        except ImportError:
            return {"skipped": "the cgal package (SWIG bindings) is not installed"}
    steps: dict[str, float] = {}
    marks = [_cpu()]

    def lap(name: str) -> None:
        marks.append(_cpu())
        steps[name] = marks[-1] - marks[-2]

    cpu, wall = _cpu(), time.perf_counter()
    if route == "cgal":
        import gudhi

        gudhi.DelaunayComplex(points=points, precision="fast")
        tets = across = np.empty((0, 4), dtype=np.int64)
    elif route == "gudhi":
        tets, across, _ = facets._exact_tetrahedra(points, kernel, "cgal")
    elif route == "exact":
        tets, across, _ = facets._exact_tetrahedra(points, kernel)
    elif route in ("geogram", "geogram_no_dd"):
        geogram_delaunay.set_double_double(route == "geogram")
        tets = geogram_delaunay.delaunay_tetrahedra(points)
        across = np.empty((0, 4), dtype=np.int64)
    elif route == "qhull":
        tets, across, _ = facets._qhull_tetrahedra(points)
    else:
        tets, across = swig_cells(points, lap)
    spent = (_cpu() - cpu, time.perf_counter() - wall)
    digest = hashlib.sha1(tets.tobytes() + across.tobytes()).hexdigest()[:12]
    return {"cpu_wall": spent, "peak_gb": _peak_gb(), "tetrahedra": len(tets),
            "steps": steps, "digest": digest, "seeds": len(points)}  # fmt: skip


def _delaunay_points(kind: str, count: int):
    """N uniform random points in the unit cube, or the jittered vertices ``lfs`` triangulates
    for a torus (3, 1) of about N vertices (the sample handed to the Delaunay engine)."""
    import numpy as np

    if kind == "random":
        return np.random.default_rng(0).random((count, 3))
    import vorobound.sampling.lfs.delaunay as lfs_delaunay
    from vorobound.sampling.lfs.estimate import estimate_lfs
    from vorobound.sampling.surfaces.demo_meshes import torus_mesh

    around = max(8, round((4 * count) ** 0.5))
    mesh = torus_mesh(3.0, 1.0, around, max(4, count // around), jitter=0.2, seed=1)
    caught = []

    class Caught(Exception):
        pass

    def catch(points, ordered=True):
        caught.append(points)
        raise Caught

    lfs_delaunay.engine_tetrahedra = catch
    lfs_delaunay.delaunay_neighbours = catch  # geogram's route, tried first
    try:
        estimate_lfs(mesh)
    except Caught:
        pass
    return caught[0]


def child_delaunay(kind: str, count: str, route: str) -> dict:
    """One route of ``delaunay`` on one point set (module docstring)."""
    import hashlib

    import numpy as np

    points = np.ascontiguousarray(_delaunay_points(kind, int(float(count))))
    cpu, wall = _cpu(), time.perf_counter()
    if route == "cgal":
        import gudhi

        gudhi.DelaunayComplex(points=points, precision="fast")
        tets = np.empty((0, 4), dtype=np.int64)
    else:
        from vorobound.sampling.simplices import delaunay_tetrahedra

        if route == "route":
            tets = delaunay_tetrahedra(points, engine="cgal")
        else:  # in geogram's own row order, as lfs asks (ordered for the digest, untimed)
            tets = delaunay_tetrahedra(points, engine="geogram", ordered=False)
    spent = (_cpu() - cpu, time.perf_counter() - wall)
    if route == "geogram":
        from vorobound.sampling.geogram_delaunay import lexicographic_rows

        tets = lexicographic_rows(tets, len(points))
    digest = hashlib.sha1(tets.tobytes()).hexdigest()[:12]
    return {"cpu_wall": spent, "peak_gb": _peak_gb(), "points": len(points),
            "tetrahedra": len(tets), "digest": digest}  # fmt: skip


DELAUNAY_ROUTES = {
    "cgal": "CGAL Delaunay (GUDHI DelaunayComplex, built)",
    "route": "CGAL route: + simplex tree, read in bulk",
    "geogram": "geogram (compiled module), lfs's route",
}


def bench_delaunay(sizes: list[int]) -> None:
    for kind in ("random", "torus"):
        for count in sizes:
            runs = {route: _child("delaunay", kind, str(count), route) for route in DELAUNAY_ROUTES}
            base = runs["cgal"]["cpu_wall"]
            print(f"{kind}: {runs['cgal']['points']:,} points")
            for route, label in DELAUNAY_ROUTES.items():
                found = runs[route]
                text = _pair(label, found["cpu_wall"], base, found["load"])
                print(f"{text}  peak {found['peak_gb']:.2f} GB")
            same = runs["route"]["digest"] == runs["geogram"]["digest"]
            print(
                f"  tetrahedra: {runs['route']['tetrahedra']:,}; the routes' arrays equal: {same}"
            )


def _peak_gb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6


def _pair(label: str, cpu_wall, base, load=None) -> str:
    ratio = cpu_wall[0] / base[0]
    text = f"  {label:44s} {cpu_wall[0]:7.2f} CPU-s {cpu_wall[1]:7.2f} s wall  {ratio:5.2f}×"
    return text + (f"  load {load[0]:.1f} → {load[1]:.1f}" if load else "")


def bench_check(data: str, sizes: list[int], engines: list[str]) -> None:
    sys.path.insert(0, os.path.dirname(__file__))
    from bench_scale import sample_file

    from vorobound.sampling import geogram_delaunay

    for count in sizes:
        path, eps = sample_file(data, count)
        cgal = _child("cgal_balls", str(path))
        geogram = _child("geogram_balls", str(path)) if geogram_delaunay.available() else None
        base = cgal["built"]
        print(f"{cgal['balls']:,} balls (+{cgal['filler']:,} filler points), ε = {eps}")
        print(_pair("CGAL regular triangulation (built)", base, base, cgal["load"]))
        print(_pair("CGAL + simplex tree", cgal["tree"], base))
        if geogram is not None:
            print(_pair("geogram regular triangulation (cells)", geogram["cells"], base,
                        geogram["load"]))  # fmt: skip
            print(_pair("geogram + triangles of the balls", geogram["route"], base))
        for engine in engines:
            check = _child("check", str(path), str(eps), engine)
            label = f"vorobound check --workers 1 ({check['engine']})"
            print(_pair(label, (check["cpu"], check["wall"]), base, check["load"]))
            stages = {**check["stages"], **{f"driver {k}": v for k, v in check["driver"].items()}}
            rest = check["cpu"] - sum(stages.values())
            print(f"    {check['tiles']} tiles, halo {100 * check['halo']:.1f} %; CPU-s by stage: "
                  + ", ".join(f"{k} {v:.2f}" for k, v in stages.items())
                  + f", the rest (start-up, imports, merge) {rest:.2f}")  # fmt: skip


def _on_sample(task: str, data: str, count: int) -> dict:
    """``task`` run in a fresh process on the torus row sample of about ``count`` balls."""
    sys.path.insert(0, os.path.dirname(__file__))
    from bench_scale import sample_file

    path, _ = sample_file(data, count)
    return _child(task, str(path))


def _print_steps(seconds: dict, base: str, unit: str, width: int) -> None:
    """One line per step: CPU seconds and the ratio to the step named ``base``."""
    for name, spent in seconds.items():
        print(f"  {name:{width}s} {spent:7.2f} CPU-s  {spent / seconds[base]:5.2f}× {unit}")


def bench_tile(data: str, count: int) -> None:
    tile = _on_sample("tile", data, count)
    print(f"one tile: {tile['balls']:,} balls (+{tile['filler']:,} filler points), "
          f"{tile['triangles']:,} candidate triangles; load {tile['load'][0]:.1f} → "
          f"{tile['load'][1]:.1f}")  # fmt: skip
    _print_steps(tile["seconds"], "CGAL triangulation", "CGAL", 36)


def bench_binding(data: str, count: int) -> None:
    found = _on_sample("binding", data, count)
    if "skipped" in found:
        print(f"binding: skipped ({found['skipped']})")
        return
    print(f"{found['balls']:,} balls (+{found['filler']:,} filler points); triangles: "
          f"{found['triangles']}; finite cells read back: {found['cells']:,}; load "
          f"{found['load'][0]:.1f} → {found['load'][1]:.1f}")  # fmt: skip
    _print_steps(found["seconds"], "GUDHI DelaunayComplex (built)", "GUDHI's CGAL", 50)


def bench_reconstruct(eps: str, with_stages: bool = False) -> None:
    with tempfile.TemporaryDirectory() as folder:
        seeds = os.path.join(folder, "seeds.npy")
        whole = _child("seeds", eps, seeds)
        cgal = _child("cgal_seeds", seeds)
        mhat = _child("mhat", seeds, "exact", "yes")
        on_cgal = _child("mhat", seeds, "cgal", "yes")
        plain = _child("mhat", seeds, "exact", "no")
        qhull = _child("mhat", seeds, "qhull", "yes")
        stages = _child("stages", seeds) if with_stages else None
    base = cgal["built"]
    print(f"torus (3, 1), ε = {eps}: {whole['seeds']:,} seeds, {cgal['tetrahedra']:,} tetrahedra")
    print(_pair("CGAL Delaunay (built)", base, base, cgal["load"]))
    print(_pair("CGAL + simplex tree", cgal["tree"], base))
    print(_pair(f"M̂ on geogram ({mhat['facets']:,} facets)", mhat["mhat"], base, mhat["load"]))
    print(_pair(f"M̂ on CGAL ({on_cgal['facets']:,} facets)", on_cgal["mhat"], base,
                on_cgal["load"]))  # fmt: skip
    print(_pair(f"M̂ on geogram, numpy steps ({plain['facets']:,})", plain["mhat"], base,
                plain["load"]))  # fmt: skip
    print(_pair(f"M̂ on qhull ({qhull['facets']:,} facets)", qhull["mhat"], base, qhull["load"]))
    print(_pair("reconstruct --torus 3,1 (whole, no files)", whole["total"], base, whole["load"]))
    print(f"  M̂ correct: {whole['correct']}; skipped seeds {mhat['skipped']}, {qhull['skipped']}")
    if stages is not None:
        print("  the steps of M̂ on CGAL, one by one (serialization counted once):")
        unit = stages["steps"]["CGAL DelaunayComplex"]
        for name, seconds in stages["steps"].items():
            if name.startswith("reading"):
                seconds -= stages["steps"]["serialization (__getstate__)"]
                name = "reading the serialized tree (numba)"
            print(f"    {name:40s} {seconds:7.2f} CPU-s {seconds / unit:5.2f}×")


CELL_ROUTES = {
    "cgal": "CGAL Delaunay (GUDHI DelaunayComplex, built)",
    "gudhi": "CGAL + simplex tree, read, neighbours",
    "swig": "cgal package (SWIG): tetrahedra + neighbours",
    "geogram": "geogram (compiled module): tetrahedra",
    "geogram_no_dd": "geogram without its double-double stage",
    "exact": "M̂'s route: geogram + neighbours",
    "qhull": "qhull (scipy Delaunay): + neighbours",
}
"""The routes of ``cells``, in the order run."""


def bench_cells(eps: str, cube: bool, repeat: int = 1) -> None:
    with tempfile.TemporaryDirectory() as folder:
        seeds = os.path.join(folder, "seeds.npy")
        _child("cube_seeds" if cube else "seeds", eps, seeds)
        runs = {route: [] for route in CELL_ROUTES}
        for _ in range(repeat):  # alternated, so each route sees the same loads
            for route in CELL_ROUTES:
                runs[route].append(_child("cells", seeds, route))
    base = min((r["cpu_wall"] for r in runs["cgal"]), key=lambda cw: cw[0])
    part = "cube [−1, 1]³" if cube else "torus (3, 1)"
    print(f"{part}, ε = {eps}: {runs['cgal'][0]['seeds']:,} seeds")
    for route, label in CELL_ROUTES.items():
        if "skipped" in runs[route][0]:
            print(f"  {label}: skipped ({runs[route][0]['skipped']})")
            continue
        for found in runs[route]:
            text = _pair(label, found["cpu_wall"], base, found["load"])
            print(f"{text}  peak {found['peak_gb']:.2f} GB")
        found = min(runs[route], key=lambda r: r["cpu_wall"][0])
        for name, spent in found["steps"].items():
            print(f"    {name:44s} {spent:7.2f} CPU-s  {spent / base[0]:5.2f}× CGAL built")
    tets = {r: runs[r][0].get("tetrahedra", 0) for r in ("gudhi", "qhull", "geogram")}
    stage = runs["geogram"][0].get("digest") == runs["geogram_no_dd"][0].get("digest")
    swig = runs["swig"][0]
    same = "skipped" if "skipped" in swig else swig["digest"] == runs["gudhi"][0]["digest"]
    print(
        f"  tetrahedra: {tets['gudhi']:,} (CGAL), {tets['qhull']:,} (qhull), {tets['geogram']:,} "
        "(geogram); SWIG's arrays equal "
        f"to CGAL's route's: {same}; geogram's the same with and without its double-double "
        f"stage: {stage}"
    )


def main() -> None:
    if len(sys.argv) > 2 and sys.argv[1] == "--child":
        print(json.dumps(globals()[f"child_{sys.argv[2]}"](*sys.argv[3:])))
        return
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "what", choices=["check", "tile", "binding", "reconstruct", "cells", "delaunay", "tiny"]
    )
    parser.add_argument("--sizes", default="1e5,1e6")
    parser.add_argument("--eps", default="0.03")
    parser.add_argument(
        "--stages", action="store_true", help="reconstruct: also time M̂'s steps one by one"
    )
    parser.add_argument("--cube", action="store_true", help="cells: the cube's seeds")
    parser.add_argument(
        "--engines", default="auto", help="check: the --engine of each check run, comma-separated"
    )
    parser.add_argument("--repeat", type=int, default=1, help="cells: runs of each route")
    parser.add_argument("--data", default=os.path.join(tempfile.gettempdir(), "vorobound-bench"))
    args = parser.parse_args()
    if args.what == "tiny":  # CI: every measurement at a size that takes seconds
        bench_check(args.data, [20_000], ["auto"])
        bench_tile(args.data, 20_000)
        bench_binding(args.data, 20_000)
        bench_reconstruct("0.3", True)
        bench_cells("0.3", False)
        bench_delaunay([2000])
    elif args.what == "delaunay":
        bench_delaunay([int(float(s)) for s in args.sizes.split(",")])
    elif args.what == "check":
        engines = args.engines.split(",")
        bench_check(args.data, [int(float(s)) for s in args.sizes.split(",")], engines)
    elif args.what == "binding":
        bench_binding(args.data, int(float(args.sizes.split(",")[-1])))
    elif args.what == "tile":
        bench_tile(args.data, int(float(args.sizes.split(",")[-1])))
    elif args.what == "cells":
        bench_cells(args.eps, args.cube, args.repeat)
    else:
        bench_reconstruct(args.eps, args.stages)


if __name__ == "__main__":
    main()
