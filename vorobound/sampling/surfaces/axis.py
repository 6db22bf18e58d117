"""An analytic surface turned onto another coordinate axis (the x or y axis instead of z).

The turn is a cyclic permutation of the coordinates (a rotation, so outward normals stay
outward): with axis y, the surface's own (a, b, c) is the world's (y, z, x)... written the
other way, local = world[:, PERMUTATION[axis]]. Measuring (closest points, L, inside, random
points) goes through the permutation; sampling a turned surface is refused by the commands
(sample about z and permute the columns).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ...errors import InputError

AXES = ("x", "y", "z")
PERMUTATION = {"x": [1, 2, 0], "y": [2, 0, 1], "z": [0, 1, 2]}
"""local = world[:, PERMUTATION[axis]]: the local z is the world's ``axis``."""


def checked_axis(axis) -> str:
    """``axis`` as one of x, y, z (any case), or an InputError."""
    text = str(axis).strip().lower()
    if text not in AXES:
        raise InputError(f"axis: expected x, y or z, got {axis!r}")
    return text


class AxisShape:
    """``shape`` (about z) turned so that its axis is the world's ``axis``."""

    def __init__(self, shape, axis: str):
        self._shape, self.axis = shape, checked_axis(axis)
        self._to_local = np.asarray(PERMUTATION[self.axis])
        self._to_world = np.argsort(self._to_local)
        self.name = f"{shape.name}, axis {self.axis}"

    def __getattr__(self, name):
        return getattr(self._shape, name)

    def _local(self, points: np.ndarray) -> np.ndarray:
        return np.asarray(points)[:, self._to_local]

    def _world(self, points: np.ndarray) -> np.ndarray:
        return np.asarray(points)[:, self._to_world]

    def closest(self, points: np.ndarray):
        found = self._shape.closest(self._local(points))
        return dataclasses.replace(
            found, points=self._world(found.points), normal=self._world(found.normal)
        )

    def project(self, points: np.ndarray):
        found = self._shape.project(self._local(points))
        return None if found is None else (self._world(found[0]), found[1])

    def lfs_at(self, points: np.ndarray) -> np.ndarray:
        return self._shape.lfs_at(self._local(points))

    def inside(self, points: np.ndarray) -> np.ndarray:
        return self._shape.inside(self._local(points))

    def random_points(self, count: int, rng):
        points, lfs = self._shape.random_points(count, rng)
        return self._world(points), lfs
