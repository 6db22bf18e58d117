"""Values of the last refinement round, found again for the sites that come back unchanged.

Each round of :func:`~vorobound.sampling.lfs.estimate.estimate_lfs` cuts the faces again at
a spacing from the last round's L. Where L hardly moved, the pieces, and so the sites, are the
same as before (bit for bit: the cuts are computed the same way), and so are the values that
depend on a site alone. A site is known by its kind, its owner (vertex, face or feature edge)
and its coordinates.

The largest empty tangent ball also depends on the cap it starts from (the other terms at the
site, which change with the feature sites). Its old value r_old, found from the cap c_old, is
min(c_old, r), r the minimum over the triangles, and it gives the new one, min(c_new, r),
exactly whenever r_old < c_old (then r_old = r) or c_new ≤ c_old (then no triangle is below
c_new either). Only a ball that met no triangle below a cap that has since grown is searched
again.
"""

from __future__ import annotations

import numpy as np


def site_keys(kind: int, owner: np.ndarray, points: np.ndarray) -> np.ndarray:
    """One key per site: its kind, owner and coordinates, as 32 raw bytes."""
    columns = np.empty((len(points), 4))
    columns[:, 0] = kind * 2.0**40 + np.asarray(owner, dtype=float)
    columns[:, 1:] = points
    return columns.view(np.dtype((np.void, 32))).reshape(-1)


class RoundMemo:
    """Named per-site arrays of the last round, and the lookup of a new round's sites."""

    def __init__(self):
        self._sorted = np.zeros(0, dtype=np.dtype((np.void, 32)))
        self._order = np.zeros(0, dtype=np.int64)
        self._values: dict[str, np.ndarray] = {}

    def match(self, keys: np.ndarray) -> np.ndarray:
        """For each key, the row of the same site in the last round, or −1."""
        if not len(self._sorted) or not len(keys):
            return np.full(len(keys), -1)
        at = np.minimum(np.searchsorted(self._sorted, keys), len(self._sorted) - 1)
        return np.where(self._sorted[at] == keys, self._order[at], -1)

    def get(self, name: str, rows: np.ndarray) -> np.ndarray:
        """The remembered ``name`` at ``rows`` (from :meth:`match`, all ≥ 0)."""
        if not len(rows):
            return np.zeros(0)
        return self._values[name][rows]

    def remember(self, keys: np.ndarray, **values: np.ndarray) -> None:
        """Replace the memory by this round's sites and their values (one row per key)."""
        self._order = np.argsort(keys, kind="stable")
        self._sorted = keys[self._order]
        self._values = dict(values)
