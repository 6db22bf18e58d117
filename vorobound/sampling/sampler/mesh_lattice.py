"""Candidate lattices on triangle meshes: adaptive square cells in the plane of each triangle.

A maximal σ-sparse subset of the candidates is an ε-sample when every surface point x lies
within d of a candidate q with

    d·(1 + k·λ) ≤ k·L(q),   k = (1 − σ')·ε/(1 + λσ'ε),   σ' = σ(1 + SPARSITY_SLACK),

λ the Lipschitz constant of L: then the smallest L on the cell is at least L(q) − λd, and
:func:`vorobound.sampling.sampler.lattice.cell_reach` applies to it (its docstring has the
proof). For an L given per vertex and linear on each triangle, λ is the triangle's gradient and
the alternative d ≤ ε(L_min − σ'L_max) over the triangle holds as well.

Each triangle is put in its own plane frame: the longest edge on the x axis, the opposite
vertex above it. Rows of height ≤ a cover the triangle, each row is cut into cells of width
≤ a over the triangle's extent in it (so every cell meets the triangle), and a cell's candidate
is the point of the triangle nearest a random point of the cell. Projection onto a convex set
does not increase distances, so the candidate is within the cell's diagonal d of every point
of the cell that lies in the triangle. Cells that fail the condition are cut into m × m
smaller ones (m from the ratio by which they failed; pieces that miss the triangle are
dropped), until all pass. The count follows the area over (k·L)², whatever the triangles'
shapes: a 100-long sliver of a CAD export costs what its area costs.

Feature edges get candidates of their own along the edge and their corners one each; the
sampler visits corners first, then edges, then faces (VoroCrust protects sharp features
first). The slab sampler (:mod:`.slabs`) builds these cells slab by slab and stops cutting a
cell once a sample provably covers it; :func:`expected_candidates` counts the plain lattice,
the measure of cost `advise` shows.
"""

from __future__ import annotations

import math

import numpy as np

from ...errors import InputError
from .lattice import MAX_CANDIDATES, SPARSITY_SLACK, candidate_limit_error

MAX_LEVELS = 60
"""Most rounds of cutting (each one at least halves a failing cell's side)."""


LATTICE_WASTE = 1.15
"""Measured ratio of the lattice's size to its ideal one (cells at exactly the allowed size),
from rounding the cuts up: 1.09 on the capped cylinder at ε = 0.05 (benchmarks/bench_lfs.py)."""


def expected_candidates(inv_lfs_sq_integral: float, eps: float, sigma: float, lam: float):
    """About how many face candidates the lattice makes: square cells whose diagonal is
    k·L/(1 + kλ) (module docstring) over ∫ dA/L², times LATTICE_WASTE."""
    s = sigma * (1 + SPARSITY_SLACK)
    k = (1 - s) * eps / (1 + lam * s * eps)
    side = k / (1 + k * lam) / math.sqrt(2)
    return LATTICE_WASTE * inv_lfs_sq_integral / side**2


class _Frames:
    """Plane frame of each triangle: origin B, unit axes ex (along the longest edge BC) and
    ey; C = (w, 0) and the opposite vertex A = (ax, h) with 0 ≤ ax ≤ w."""

    def __init__(self, corners: np.ndarray):
        edges = np.roll(corners, -1, axis=1) - corners  # edge i from corner i to i + 1
        longest = np.argmax((edges**2).sum(axis=2), axis=1)
        rows = np.arange(len(corners))
        self.order = np.stack([longest, (longest + 1) % 3, (longest + 2) % 3], axis=1)
        b = corners[rows, self.order[:, 0]]
        c = corners[rows, self.order[:, 1]]
        a = corners[rows, self.order[:, 2]]
        bc = c - b
        self.w = np.linalg.norm(bc, axis=1)
        self.ex = bc / self.w[:, None]
        ba = a - b
        self.ax = np.clip((ba * self.ex).sum(axis=1), 0.0, self.w)
        up = ba - self.ax[:, None] * self.ex
        self.h = np.linalg.norm(up, axis=1)
        self.ey = up / self.h[:, None]
        self.origin = b

    def left(self, t, y):
        return self.ax[t] * y / self.h[t]

    def right(self, t, y):
        return self.w[t] + (self.ax[t] - self.w[t]) * y / self.h[t]

    def embed(self, t, x, y):
        return self.origin[t] + x[:, None] * self.ex[t] + y[:, None] * self.ey[t]

    def barycentric(self, t, x, y):
        """Barycentric coordinates of plane points in the input corner order."""
        beta_a = y / self.h[t]  # weight of A
        beta_c = (x - self.ax[t] * beta_a) / self.w[t]  # weight of C
        beta_b = 1 - beta_a - beta_c
        out = np.empty((len(t), 3))
        rows = np.arange(len(t))
        for column, weight in enumerate((beta_b, beta_c, beta_a)):
            out[rows, self.order[t, column]] = weight
        return out

    def closest(self, t, px, py):
        """The point of triangle t nearest (px, py), in the plane frame."""
        y = np.clip(py, 0.0, self.h[t])
        inside = (py >= 0) & (py <= self.h[t])
        lo, hi = self.left(t, y), self.right(t, y)
        x = np.clip(px, lo, hi)
        exact = inside & (px >= lo) & (px <= hi)
        if exact.all():
            return px, py
        out_x, out_y = np.where(exact, px, x), np.where(exact, py, y)
        todo = np.flatnonzero(~exact)
        best = np.full(len(todo), np.inf)
        tt = t[todo]
        qx, qy = px[todo], py[todo]
        zero = np.zeros(len(todo))
        for (x0, y0), (x1, y1) in (
            ((zero, zero), (self.w[tt], zero)),
            ((self.w[tt], zero), (self.ax[tt], self.h[tt])),
            ((self.ax[tt], self.h[tt]), (zero, zero)),
        ):
            dx, dy = x1 - x0, y1 - y0
            s = np.clip(((qx - x0) * dx + (qy - y0) * dy) / (dx * dx + dy * dy), 0.0, 1.0)
            cx, cy = x0 + s * dx, y0 + s * dy
            dist = (cx - qx) ** 2 + (cy - qy) ** 2
            better = dist < best
            best = np.where(better, dist, best)
            out_x[todo] = np.where(better, cx, out_x[todo])
            out_y[todo] = np.where(better, cy, out_y[todo])
        return out_x, out_y


def _first_cells(frames, side, eps: float):
    """Rows of height ≤ side across each triangle, cut into cells of width ≤ side."""
    t_all = np.arange(len(frames.w))
    rows = np.maximum(1, np.ceil(frames.h / side)).astype(np.int64)
    if not float(rows.sum()) <= MAX_CANDIDATES:
        raise candidate_limit_error(float(rows.sum()), eps, at_least=True)
    t = np.repeat(t_all, rows)
    j = np.arange(len(t)) - np.repeat(np.cumsum(rows) - rows, rows)
    ch = frames.h[t] / rows[t]
    y0, y1 = j * ch, (j + 1) * ch
    lo = np.minimum(frames.left(t, y0), frames.left(t, y1))
    hi = frames.right(t, y0)
    width = np.maximum(hi - lo, 0.0)
    columns = np.maximum(1, np.ceil(width / side[t])).astype(np.int64)
    if not float(columns.sum()) <= MAX_CANDIDATES:
        raise candidate_limit_error(float(columns.sum()), eps, at_least=True)
    row = np.repeat(np.arange(len(t)), columns)
    i = np.arange(len(row)) - np.repeat(np.cumsum(columns) - columns, columns)
    cw = width[row] / columns[row]
    return t[row], lo[row] + i * cw, y0[row], cw, ch[row]


def _cut(frames, t, x0, y0, cw, ch, cut):
    """Each cell into cut × cut equal cells, keeping those that may meet the triangle."""
    pieces = cut * cut
    owner = np.repeat(np.arange(len(t)), pieces)
    index = np.arange(len(owner)) - np.repeat(np.cumsum(pieces) - pieces, pieces)
    m = cut[owner]
    i, j = index % m, index // m
    w, h = cw[owner] / m, ch[owner] / m
    nx, ny = x0[owner] + i * w, y0[owner] + j * h
    tt = t[owner]
    cx, cy = frames.closest(tt, nx + w / 2, ny + h / 2)
    # A rectangle misses the triangle if its centre is farther than half its diagonal.
    keep = (cx - nx - w / 2) ** 2 + (cy - ny - h / 2) ** 2 <= (w * w + h * h) / 4 * (1 + 1e-12)
    return tt[keep], nx[keep], ny[keep], w[keep], h[keep]


def _corner_candidates(shape):
    corners = np.asarray(getattr(shape, "corner_points", np.zeros((0, 3))), dtype=float)
    if not len(corners):
        return np.zeros((0, 3)), np.zeros(0)
    return corners, _positive(shape.lfs_of_points(corners), shape)


def _edge_candidates(shape, eps, s, rng):
    """Points along the feature edges, each piece short against σ'εL at its point (so the
    first accepted samples follow the features)."""
    segments = np.asarray(getattr(shape, "feature_segments", np.zeros((0, 2, 3))), dtype=float)
    if not len(segments):
        return np.zeros((0, 3)), np.zeros(0)
    a, b = segments[:, 0], segments[:, 1]
    length = np.linalg.norm(b - a, axis=1)
    lam = float(shape.lipschitz)
    step = s * eps / (4 * (1 + lam * s * eps))
    middle = _positive(shape.lfs_of_points(0.5 * (a + b)), shape)
    low = np.maximum(middle - lam * length / 2, middle / 16)  # about the smallest L on it
    pieces = np.maximum(1, np.ceil(length / (step * low))).astype(np.int64)
    if not float(pieces.sum()) <= MAX_CANDIDATES:
        raise candidate_limit_error(float(pieces.sum()), eps, at_least=True)
    owner = np.repeat(np.arange(len(segments)), pieces)
    index = np.arange(len(owner)) - np.repeat(np.cumsum(pieces) - pieces, pieces)
    f = (index + rng.random(len(owner))) / pieces[owner]
    points = a[owner] + f[:, None] * (b - a)[owner]
    return points, _positive(shape.lfs_of_points(points), shape)


def _positive(lfs, shape) -> np.ndarray:
    lfs = np.asarray(lfs, dtype=float)
    if not (np.isfinite(lfs).all() and (lfs > 0).all()):
        raise InputError(f"{shape.name}: L must be positive and finite on the whole mesh")
    return lfs
