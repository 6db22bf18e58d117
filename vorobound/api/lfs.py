"""``vorobound lfs``: the local feature size L at the vertices of a triangle mesh."""

from __future__ import annotations

import os
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from ..progress import Progress
from .arguments import checked_arguments
from .result import Result, frame

if TYPE_CHECKING:
    from ..sampling.lfs.estimate import LfsEstimate


@dataclass(frozen=True, repr=False)
class LfsResult(Result):
    """The estimate of L on a mesh (numerical, not a certified bound) and what it rests on."""

    command = "lfs"
    mesh: str
    vertices: int
    triangles: int
    lfs_min: float
    lfs_median: float
    lfs_max: float
    lipschitz: float
    seconds: float
    written: tuple[str, ...] = field(repr=False, default=())
    estimate: LfsEstimate = field(repr=False, kw_only=True)
    """:class:`vorobound.sampling.lfs.estimate.LfsEstimate` (``.lfs`` per vertex, ``.at(x)``)."""
    asked: dict = field(repr=False, default_factory=dict)

    @property
    def face_sites(self) -> int:
        """Sites inside the faces at which L was evaluated."""
        sites = self.estimate.sites
        assert sites is not None  # an estimate always has its sites
        return int((sites.kind == 1).sum())

    @property
    def thickness_min(self) -> float | None:
        """The thinnest part of the mesh along the normals (None where nothing is finite)."""
        sites = self.estimate.sites
        assert sites is not None
        thickness = sites.thickness
        finite = thickness[thickness == thickness]
        finite = finite[abs(finite) != float("inf")]
        return float(finite.min()) if len(finite) else None

    def payload(self) -> dict:
        e = self.estimate
        report = e.mesh_report
        return {
            "params": {"mesh": self.mesh} | self.asked,
            "mesh": self.mesh,
            "method": e.method,
            "vertices": self.vertices,
            "triangles": self.triangles,
            "samples": e.sample_count,
            "added_samples": e.added_samples,
            "medial_points": len(e.medial_points),
            "lipschitz": self.lipschitz,
            "lfs_min": self.lfs_min,
            "lfs_median": self.lfs_median,
            "lfs_max": self.lfs_max,
            "sharp_angle": e.sharp_angle,
            "sharp_edges": len(e.sharp_edges),
            "patches": e.patches,
            "feature_edges": e.feature_edges,
            "feature_corners": len(e.feature_corners),
            "feature_length": e.feature_length,
            "feature_inv_lfs": e.feature_inv_lfs,
            "rounds": e.rounds,
            "face_sites": self.face_sites,
            "thickness_min": self.thickness_min,
            "disagreement": e.disagreement,
            "max_dihedral": e.max_dihedral,
            "boundary_edges": report.boundary_edges,
            "nonmanifold_edges": report.nonmanifold_edges,
            "degenerate_triangles": report.degenerate_triangles,
            "duplicate_vertices": report.duplicate_vertices,
            "warnings": list(e.warnings),
            "claim": "numerical",
            "written": list(self.written),
            "seconds": self.seconds,
        }

    def to_frame(self):
        """x, y, z, lfs per vertex (pandas optional)."""
        points = self.estimate.mesh.points
        return frame(
            [
                {"x": p[0], "y": p[1], "z": p[2], "lfs": value}
                for p, value in zip(points.tolist(), self.estimate.lfs.tolist(), strict=True)
            ]
        )


@checked_arguments
def lfs(
    *,
    mesh: str | os.PathLike,
    output: str | os.PathLike | Sequence[str | os.PathLike] | None = None,
    samples: int | None = None,
    lipschitz: float = 1.0,
    sharp_angle: float = 30.0,
    seed: int = 0,
    progress: Progress | None = None,
) -> LfsResult:
    """Local feature size L of the piecewise-smooth surface a mesh describes, at every vertex.

    Sharp edges (``sharp_angle`` degrees) split the surface into smooth patches; L is the
    largest λ-Lipschitz function (λ = ``lipschitz``) below the distance to the Voronoi poles
    of the curved patches, half the thickness across the part, the curvature radius and the
    size of the sharp features, evaluated at points spread inside the faces and refined until
    stable (docs/lfs.md). ``output``: one path or several, .csv (x,y,z,lfs: what ``sizing``
    reads) or .vtu (for ParaView), written as one set. The estimate is numerical.
    """
    import numpy as np

    from ..files import write_set
    from ..sampling.io.lfs_files import checked_lfs_output, lfs_writers
    from ..sampling.io.meshes import read_triangle_mesh
    from ..sampling.lfs.estimate import checked_lfs_options, estimate_lfs

    checked_lfs_options(samples, lipschitz, sharp_angle, seed)
    if output is None:
        paths = []
    elif isinstance(output, str | os.PathLike):
        paths = [output]
    else:
        paths = list(output)
    outputs = [checked_lfs_output(os.fspath(path)) for path in paths]
    start = time.perf_counter()
    triangle_mesh = read_triangle_mesh(os.fspath(mesh))
    options = {} if samples is None else {"samples": samples}
    estimate = estimate_lfs(
        triangle_mesh,
        lipschitz=lipschitz,
        sharp_angle=sharp_angle,
        seed=seed,
        progress=progress,
        **options,
    )
    seconds = time.perf_counter() - start
    written = tuple(os.fspath(p) for p in write_set(lfs_writers(outputs, estimate)))
    values = estimate.lfs
    return LfsResult(
        mesh=os.fspath(mesh),
        vertices=len(triangle_mesh.points),
        triangles=len(triangle_mesh.triangles),
        lfs_min=float(values.min()),
        lfs_median=float(np.median(values)),
        lfs_max=float(values.max()),
        lipschitz=estimate.lipschitz,
        seconds=seconds,
        written=written,
        estimate=estimate,
        asked={
            "samples": samples,
            "lipschitz": lipschitz,
            "sharp_angle": sharp_angle,
            "seed": seed,
        },
    )
