"""M̂ of one seed set as typed fields: the view of ``vorobound reconstruct``'s JSON it prints.

:meth:`ReconstructSummary.of` reads the ``--json`` object of one reconstruction
(:meth:`vorobound.api.reconstruct.ReconstructResult.to_dict`) field by field
(:func:`~vorobound.api.result.typed_view`); docs/reconstruct.md describes the fields. A sweep
and draws print their typed rows (:class:`vorobound.reports.reconstruct_sweep.SweepRow`,
:class:`vorobound.reports.reconstruct_draws.DrawsRow`) directly.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from .result import typed_view


@dataclass(frozen=True)
class ReconstructSummary:
    """M̂ of one seed set: how it was seeded, its topology against the surface's, and (with a
    surface) how far from it and how well oriented it is (the JSON keys of the same names)."""

    source: str
    eps: float | None
    """ε of the sample (None: seeds measured without one)."""
    n_samples: int | None
    """Balls (None: seeds read from a file)."""
    n_guide_triangles: int | None
    n_half_covered: int | None
    engine: str | None
    n_seeds: int
    n_inside_seeds: int
    labels: str
    """What labelled the seeds inside or outside."""
    sheet_label_disagreements: int | None
    n_facets: int
    collapsed_facets: int
    """In/out pairs whose facet has no area."""
    closed_manifold: bool
    boundary_edges: int
    nonmanifold_edges: int
    nonmanifold_vertices: int
    unbounded_facets: int
    euler_characteristic: int
    components: int
    genus: float | None
    expected_euler_characteristic: int | None
    """The surface's (None: no surface to compare with)."""
    expected_components: int | None
    topology_correct: bool | None
    edge_ratio_min: float | None
    """Shortest over longest edge of a facet."""
    edge_ratio_median: float | None
    min_angle_min_deg: float | None
    min_angle_median_deg: float | None
    measured: bool
    """M̂ was measured against the surface (the distances and normals below)."""
    hausdorff_over_eps_lfs: float | None = None
    mhat_to_surface_over_eps_lfs: float | None = None
    surface_to_mhat_over_eps_lfs: float | None = None
    normal_deviation_max_deg: float | None = None
    normal_deviation_median_deg: float | None = None
    flipped_facets: int | None = None
    """Facets whose normal deviates by more than 90°."""
    note: str | None = None
    """Why M̂ is empty, when it is."""

    @classmethod
    def of(cls, data: Mapping) -> ReconstructSummary:
        """The view of one reconstruction's JSON object."""
        return typed_view(
            cls, data, eps=data["params"].get("eps"), measured="hausdorff_over_eps_lfs" in data
        )
