"""Why the L-bracket's coarse and fine triangulations disagree, and what closes the gap.

Run: ``python benchmarks/bench_lfs_agreement.py [--part bracket]`` (a few minutes). For each
variant of the estimator, the relative difference of L between the coarse and the fine copy
of the part at 20 000 points of the fine surface (as ``bench_lfs.py --cad``), with the CPU
seconds of the two estimates; then the raw values of the two copies at the same points of the
flat faces (those points added to both estimates as face sites), which says how much of the
difference is in the site values rather than in the interpolation between the sites.
docs/lfs.md ("Triangulation independence") quotes these numbers.

Variants (docs/lfs.md, "How it is estimated"):

* ``flat``: every site's value flat over its shrunk piece radius, as before the tangent planes;
* ``flat, pieces L/2``: the same with face pieces half as long on flat patches;
* ``tangent plane``: the default;
* ``flat, pieces 0.2·L``: flat values, pieces 0.2·L everywhere and no piece floor above 1/128
  of its face's longest edge.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import sys
import time
import warnings

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))

import numpy as np  # noqa: E402

from benchmarks.bench_lfs import surface_points  # noqa: E402
from vorobound.errors import VoroboundWarning  # noqa: E402
from vorobound.mesh import TriangleMesh  # noqa: E402
from vorobound.sampling.lfs import estimate as module  # noqa: E402
from vorobound.sampling.lfs import rounds as settings  # noqa: E402
from vorobound.sampling.lfs.face_sites import FaceSites  # noqa: E402
from vorobound.sampling.lfs.mesh_quality import prepare_mesh  # noqa: E402
from vorobound.sampling.lfs.thickness import RayCaster  # noqa: E402
from vorobound.sampling.surfaces.cad_meshes import coarse_and_fine  # noqa: E402

POINTS = 20_000
"""Points of the fine surface where the two copies are compared."""
TINY_PART, TINY_POINTS = "cube", 500


@contextlib.contextmanager
def variant(flat_planes: bool, spacing: dict | None = None, min_pieces: int | None = None):
    """The estimator with its module settings changed for the block."""
    saved = (settings.site_gradients, settings.SITE_SPACING, settings.MIN_PIECES)
    if flat_planes:
        fitted = settings.site_gradients

        def no_planes(*args, **kwargs):
            slopes, planes = fitted(*args, **kwargs)
            return slopes, np.zeros_like(planes)

        settings.site_gradients = no_planes
    settings.SITE_SPACING = spacing or settings.SITE_SPACING
    settings.MIN_PIECES = min_pieces or settings.MIN_PIECES
    try:
        yield
    finally:
        settings.site_gradients, settings.SITE_SPACING, settings.MIN_PIECES = saved


def estimate(mesh):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", VoroboundWarning)
        start = time.process_time()
        # A fresh mesh object: the estimate is cached on the object, and each variant of the
        # settings must compute its own.
        result = module.estimate_lfs(TriangleMesh(mesh.points, mesh.triangles, mesh.name))
        return result, time.process_time() - start


def differences(a: np.ndarray, b: np.ndarray) -> str:
    rel = np.abs(a - b) / np.minimum(a, b)
    over = rel > 0.05
    lower = f"{(a < b)[over].mean():.2f}" if over.any() else "-"
    return (
        f"share above 5 % {100 * over.mean():5.2f} %  p99 {np.percentile(rel, 99):.3f}"
        f"  largest {rel.max():.3f}  coarse lower {lower}"
    )


def with_probes(mesh, probes: np.ndarray):
    """The estimate with ``probes`` (points on flat faces) added as face sites in every round,
    and the rows of the probes among its sites."""
    from scipy.spatial import cKDTree

    prepared = prepare_mesh(mesh)
    inner = (probes - prepared.centre) / prepared.scale
    _, face, closest = RayCaster(prepared.points, prepared.triangles).closest(inner)
    plain = settings.face_sites

    def face_sites(points, faces, corner_normals, curved, spacing, *rest, **options):
        made = plain(points, faces, corner_normals, curved, spacing, *rest, **options)
        corners = points[faces[face]]
        normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
        normal /= np.linalg.norm(normal, axis=1)[:, None]
        # Oriented like the face's own sites (their normal lines point inward or outward).
        own = {int(f): n for f, n in zip(made.face, made.normals, strict=True)}
        pairs = zip(face, normal, strict=True)
        flip = np.array([float(np.dot(own.get(int(f), n), n)) < 0 for f, n in pairs])
        normal[flip] *= -1
        tiny = 1e-9 * (corners - corners.mean(axis=1)[:, None])
        # A probe stands for a tiny piece around it: its corners, or (where the sites carry
        # their reach instead, as merged sites do) its distance to them.
        pieces = closest[:, None] + tiny
        reach = np.linalg.norm(tiny, axis=2).max(axis=1)
        return FaceSites(
            np.vstack([made.points, closest]),
            np.vstack([made.normals, normal]),
            np.concatenate([made.face, face]),
            np.concatenate([made.areas, np.full(len(face), 1e-30)]),
            np.concatenate([made.sizes, np.full(len(face), 1e-9)]),
            None if made.corners is None else np.vstack([made.corners, pieces]),
            None if made.reach is None else np.concatenate([made.reach, reach]),
        )

    settings.face_sites = face_sites
    try:
        result, _ = estimate(mesh)
    finally:
        settings.face_sites = plain
    distance, rows = cKDTree(result.sites.points).query(probes)
    assert distance.max() < 1e-6 * np.ptp(probes, axis=0).max()
    return result, rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--part", default="bracket", choices=sorted(coarse_and_fine()))
    parser.add_argument(
        "--tiny",
        action="store_true",
        help=f"--part {TINY_PART}, {TINY_POINTS:,} points (CI: it runs; the numbers mean nothing)",
    )
    args = parser.parse_args()
    count = POINTS
    if args.tiny:
        args.part, count = TINY_PART, TINY_POINTS
    coarse, fine = coarse_and_fine()[args.part]
    points = surface_points(fine, count)
    print(f"{args.part}: {coarse.name} / {fine.name}")
    variants = {
        "flat": dict(flat_planes=True),
        "flat, pieces L/2": dict(flat_planes=True, spacing={"curved": 0.5, "flat": 0.5}),
        "tangent plane": dict(flat_planes=False),
        "flat, pieces 0.2·L": dict(
            flat_planes=True, spacing={"curved": 0.2, "flat": 0.2}, min_pieces=128
        ),
    }
    for name, options in variants.items():
        with variant(**options):
            (a, ta), (b, tb) = estimate(coarse), estimate(fine)
        print(f"{name:22s} {differences(a.at(points), b.at(points))}  CPU {ta:.1f} s / {tb:.1f} s")
    # Raw values at the same points of the flat faces (a curved face's sites are lifted onto
    # its own smooth surface, which differs between the copies).
    probes = points[_on_flat_patches(fine, points)][:4000]
    (ca, rows_a), (cb, rows_b) = with_probes(coarse, probes), with_probes(fine, probes)
    print(
        f"raw values at {len(probes)} common points of flat faces: "
        f"{differences(ca.sites.raw[rows_a], cb.sites.raw[rows_b])}"
    )


def _on_flat_patches(mesh, points: np.ndarray) -> np.ndarray:
    """Which points lie on faces of flat patches."""
    from vorobound.sampling.lfs.patches import find_patches

    prepared = prepare_mesh(mesh)
    patches = find_patches(prepared, module.SHARP_ANGLE)
    inner = (points - prepared.centre) / prepared.scale
    _, face, _ = RayCaster(prepared.points, prepared.triangles).closest(inner)
    return patches.flat[patches.face_patch[face]]


if __name__ == "__main__":
    main()
