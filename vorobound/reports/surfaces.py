"""Surfaces for the sample-count estimates: area and ∫ dA / L² (L the local feature size)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import VoroboundError


@dataclass(frozen=True)
class Surface:
    """What the sample-count estimates need from a surface."""

    name: str
    area: float
    inv_lfs_sq_integral: float
    """∫ dA / L(x)²: dimensionless, the number of (L-sized) patches the surface holds."""
    lfs_min: float
    """Smallest local feature size on the surface (sets the smallest ball radius)."""
    exact: bool
    """True when the covering/packing counts are exact bounds (sphere), not estimates."""


def sphere(radius: float) -> Surface:
    """Sphere: L = R everywhere (the medial axis is the center)."""
    _positive(radius, "sphere radius")
    return Surface(f"sphere R={radius:g}", 4 * math.pi * radius**2, 4 * math.pi, radius, True)


def torus(major: float, minor: float) -> Surface:
    """Ring torus (R > r): L(φ) = min(r, R + r cos φ).

    The medial axis is the core circle (distance r) and the symmetry axis (distance
    R + r cos φ, the distance of the point from the axis); φ is the angle around the tube.
    """
    _positive(minor, "torus minor radius")
    if not major > minor:
        raise VoroboundError(f"a ring torus needs R > r, got R={major:g}, r={minor:g}")
    from scipy.integrate import quad

    def integrand(phi):
        rho = major + minor * math.cos(phi)
        return minor * rho / min(minor, rho) ** 2

    # L switches from r to the axis distance where R + r cos φ = r.
    c = (minor - major) / minor
    breaks = [math.acos(c), 2 * math.pi - math.acos(c)] if c > -1 else []
    total, _ = quad(
        integrand, 0, 2 * math.pi, points=breaks or None, limit=200, epsabs=0, epsrel=1e-12
    )
    return Surface(
        f"torus R={major:g}, r={minor:g}",
        4 * math.pi**2 * major * minor,
        2 * math.pi * total,
        min(minor, major - minor),
        False,
    )


def planar_area(area: float, lfs: float) -> Surface:
    """A surface known only by its area, with constant local feature size."""
    _positive(area, "area")
    _positive(lfs, "lfs")
    return Surface(f"area {area:g}, L={lfs:g}", area, area / lfs**2, lfs, False)


def mesh_surface(path: Path, lfs: float | None = None, sizing: Path | None = None) -> Surface:
    """A triangle mesh read with meshio; L constant (``lfs``) or per vertex (``sizing`` CSV)."""
    if (lfs is None) == (sizing is None):
        raise VoroboundError("a mesh needs either --lfs L or --sizing FILE (one value per vertex)")
    try:
        import meshio
    except ImportError:
        raise VoroboundError("reading meshes needs meshio: pip install meshio") from None
    try:
        mesh = meshio.read(path)
    except Exception as exc:  # meshio raises many types for unreadable files
        raise VoroboundError(f"cannot read mesh {path}: {exc}") from None
    cells = [block.data for block in mesh.cells if block.type == "triangle"]
    if not cells:
        raise VoroboundError(f"mesh {path} has no triangles")
    tri = np.concatenate(cells)
    pts = np.asarray(mesh.points, dtype=float)
    if pts.shape[1] == 2:
        pts = np.column_stack([pts, np.zeros(len(pts))])
    cross = np.cross(pts[tri[:, 1]] - pts[tri[:, 0]], pts[tri[:, 2]] - pts[tri[:, 0]])
    areas = 0.5 * np.linalg.norm(cross, axis=1)
    if sizing is not None:
        vertex_lfs = _read_sizing(sizing, len(pts))
        tri_lfs = vertex_lfs[tri].mean(axis=1)
    else:
        _positive(lfs, "lfs")
        tri_lfs = np.full(len(tri), lfs)
    return Surface(
        f"mesh {Path(path).name}",
        float(areas.sum()),
        float((areas / tri_lfs**2).sum()),
        float(tri_lfs.min()),
        False,
    )


def _read_sizing(path: Path, count: int) -> np.ndarray:
    try:
        lines = [ln.strip() for ln in Path(path).read_text().splitlines() if ln.strip()]
    except OSError as exc:
        raise VoroboundError(f"cannot read sizing file {path}: {exc.strerror}") from None
    values = []
    for index, line in enumerate(lines):
        try:
            values.append(float(line.split(",")[-1]))
        except ValueError:
            if index == 0:
                continue  # a header
            raise VoroboundError(f"sizing file {path}, line {index + 1}: not a number") from None
    data = np.array(values)
    if len(data) != count:
        raise VoroboundError(f"sizing file {path} has {len(data)} values for {count} vertices")
    if not (np.isfinite(data).all() and (data > 0).all()):
        raise VoroboundError(f"sizing file {path}: every value must be positive and finite")
    return data


def _positive(value, name: str) -> None:
    if value is None or not (math.isfinite(value) and value > 0):
        raise VoroboundError(f"{name} must be positive and finite, got {value}")
