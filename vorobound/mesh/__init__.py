"""The triangle mesh: vertices and triangles with their derived data (edges, edge lengths,
vertex→face and vertex→label tables, a k-d tree, estimates such as L) computed on first use
and cached on the object (:mod:`.triangles`), its topology (:mod:`.topology`), the nearest
point of an allowed label (:mod:`.nearest`) and the distinct rows of integer tables
(:mod:`.rows`). Readers of mesh files live in :mod:`vorobound.sampling.io.meshes`; what a mesh
is as a surface to sample, in :mod:`vorobound.sampling.surfaces.mesh`.
"""

from .triangles import MIN_AREA_RTOL, TriangleMesh, fingerprint, has_area, triangle_shapes

__all__ = ["MIN_AREA_RTOL", "TriangleMesh", "fingerprint", "has_area", "triangle_shapes"]
