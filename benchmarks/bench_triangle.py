"""Throughput of the weighted-triangle batch kernel against straightforward center solves.

Run: ``python benchmarks/bench_triangle.py [--n 2000000]``. Prints triangles per second for

* ``vorobound``: :func:`vorobound.weighted_triangles` (both centers, radii, Theorem 1, ...),
  which runs the compiled kernel when numba is installed (``pip install '.[fast]'``);
* ``numpy``: the same function forced onto its pure-numpy path (``VOROBOUND_PURE_NUMPY=1``);
* ``edges`` and ``edges numpy``: :func:`vorobound.theorem1_from_edges` on the same triangles'
  edge lengths, compiled and numpy;
* ``loop``: per-triangle ``numpy.linalg.solve`` of the two 2×2 center systems in a Python
  loop (timed on a subsample and scaled);
* ``batched``: the same 2×2 solves as one batched ``numpy.linalg.solve`` call, then the radii
  and their difference,

the ratios, and the peak traced memory of the kernel for two batch sizes (chunking keeps the
temporaries bounded, so the peak grows only with the outputs). Rates are per second of wall
time (the kernel runs on one thread per core) and, for the kernel and the batched solve, per
CPU-second of the process (what the load of a shared machine hardly changes), with the load
average before and after.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
import tracemalloc

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
from vorobound import theorem1_from_edges, weighted_triangles  # noqa: E402
from vorobound.geometry.triangle import COMPILED_MIN_ROWS, compiled_available  # noqa: E402

TINY_N = COMPILED_MIN_ROWS
"""Triangles of a --tiny run: the fewest that still take the compiled kernel."""
TINY_LOOP_N = 200


def straightforward_batched(points: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """R − R̂ by solving 2×2 systems in the plane basis for both centers, then subtracting."""
    i_min = np.argmin(weights, axis=1)
    order = (i_min[:, None] + np.arange(3)) % 3
    p = np.take_along_axis(points, order[:, :, None], axis=1)
    w = np.take_along_axis(weights, order, axis=1)
    w = w - w[:, :1]
    u, v = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    basis = np.stack([u, v], axis=1)
    gram = basis @ basis.transpose(0, 2, 1)
    rhs = np.einsum("nii->ni", gram) / 2
    circ = np.linalg.solve(gram, rhs[..., None])[..., 0]
    ortho = np.linalg.solve(gram, (rhs - w[:, 1:] / 2)[..., None])[..., 0]
    x = np.einsum("ni,nij->nj", circ, basis)
    xh = np.einsum("ni,nij->nj", ortho, basis)
    return np.linalg.norm(x, axis=1) - np.linalg.norm(xh, axis=1)


def straightforward_loop(points: np.ndarray, weights: np.ndarray) -> np.ndarray:
    out = np.empty(len(points))
    for i in range(len(points)):
        j = int(np.argmin(weights[i]))
        a, b, c = points[i][[j, (j + 1) % 3, (j + 2) % 3]]
        wb = weights[i][(j + 1) % 3] - weights[i][j]
        wc = weights[i][(j + 2) % 3] - weights[i][j]
        basis = np.array([b - a, c - a])
        gram = basis @ basis.T
        rhs = np.diag(gram) / 2
        x = np.linalg.solve(gram, rhs) @ basis
        xh = np.linalg.solve(gram, rhs - np.array([wb, wc]) / 2) @ basis
        out[i] = np.linalg.norm(x) - np.linalg.norm(xh)
    return out


def best_time(fn, repeats: int = 3) -> float:
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - start)
    return best


def best_cpu_time(fn, repeats: int = 3) -> float:
    """Fewest CPU seconds of the process (all its threads) over ``repeats`` calls."""
    best = float("inf")
    for _ in range(repeats):
        start = time.process_time()
        fn()
        best = min(best, time.process_time() - start)
    return best


def peak_memory_mb(n: int, rng: np.random.Generator) -> tuple[float, float]:
    points = rng.standard_normal((n, 3, 3))
    weights = rng.random((n, 3)) * 0.1
    tracemalloc.start()
    result = weighted_triangles(points, weights)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    outputs = sum(getattr(result, f).nbytes for f in result.__dataclass_fields__)
    return peak / 2**20, outputs / 2**20


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=2_000_000, help="triangles in the batch")
    parser.add_argument("--loop-n", type=int, default=20_000, help="subsample for the loop")
    parser.add_argument(
        "--tiny", action="store_true", help=f"--n {TINY_N} --loop-n {TINY_LOOP_N} (CI: it runs)"
    )
    args = parser.parse_args()
    if args.tiny:
        args.n, args.loop_n = TINY_N, TINY_LOOP_N
    rng = np.random.default_rng(0)
    points = rng.standard_normal((args.n, 3, 3))
    weights = rng.random((args.n, 3)) * 0.1

    lengths = np.stack(
        [np.linalg.norm(points[:, (i + 2) % 3] - points[:, (i + 1) % 3], axis=1) for i in range(3)],
        axis=1,
    )
    load = os.getloadavg()[0]
    weighted_triangles(points[:COMPILED_MIN_ROWS], weights[:COMPILED_MIN_ROWS])  # compile
    theorem1_from_edges(lengths[:COMPILED_MIN_ROWS], weights[:COMPILED_MIN_ROWS])
    t_ours = best_time(lambda: weighted_triangles(points, weights))
    cpu_ours = best_cpu_time(lambda: weighted_triangles(points, weights))
    t_edges = best_time(lambda: theorem1_from_edges(lengths, weights))
    os.environ["VOROBOUND_PURE_NUMPY"] = "1"
    t_numpy = best_time(lambda: weighted_triangles(points, weights))
    t_edges_numpy = best_time(lambda: theorem1_from_edges(lengths, weights))
    del os.environ["VOROBOUND_PURE_NUMPY"]
    t_batched = best_time(lambda: straightforward_batched(points, weights))
    cpu_batched = best_cpu_time(lambda: straightforward_batched(points, weights))
    sub = slice(0, args.loop_n)
    t_loop = best_time(lambda: straightforward_loop(points[sub], weights[sub]), 1) * (
        args.n / args.loop_n
    )
    rate = {
        name: args.n / t
        for name, t in (
            ("vorobound", t_ours),
            ("numpy", t_numpy),
            ("edges", t_edges),
            ("edges numpy", t_edges_numpy),
            ("batched", t_batched),
            ("loop", t_loop),
        )
    }
    kernel = "compiled (numba)" if compiled_available() else "numpy (numba not installed)"
    print(f"triangles: {args.n:,} random 3-D, {os.cpu_count()} cores, kernel: {kernel}")
    for name, r in rate.items():
        print(f"  {name:12s} {r / 1e6:9.3f} M triangles/s")
    print(
        f"  per CPU-second: vorobound {args.n / cpu_ours / 1e6:.3f} M, batched "
        f"{args.n / cpu_batched / 1e6:.3f} M (load {load:.1f} → {os.getloadavg()[0]:.1f})"
    )
    print(f"  ratio vorobound / loop    : {rate['vorobound'] / rate['loop']:8.1f}x")
    print(f"  ratio vorobound / batched : {rate['vorobound'] / rate['batched']:8.2f}x")
    print(f"  ratio numpy path / batched: {rate['numpy'] / rate['batched']:8.2f}x")
    for n in (args.n // 4, args.n):
        peak, outputs = peak_memory_mb(n, rng)
        print(
            f"  peak traced memory, n={n:,}: {peak:8.1f} MB (outputs {outputs:.1f} MB, "
            f"temporaries {peak - outputs:.1f} MB)"
        )


if __name__ == "__main__":
    main()
