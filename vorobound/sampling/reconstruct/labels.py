"""Inside/outside labels of seeds from the balls alone: the two sheets of the union's boundary.

The boundary of the union of balls ∂∪B is made of sphere patches meeting along circle arcs,
and its vertices are exactly the uncovered seeds (of guide and half-covered triples). Around a
closed surface it has two sheets, one on each side; the two seeds of a guide triangle lie on
different sheets. The rule:

1. **Sheets.** Two seeds are on one sheet when an uncovered arc of ∂∪B joins them: every
   uncovered seed lies on the three circles where its balls' spheres meet pairwise; along each
   circle the seeds are sorted by angle, and consecutive seeds are joined when the middle of
   the arc between them lies outside every other ball. The sheets are the connected
   components.
2. **Pairs of sheets.** The guide triangles join sheets in pairs (one seed on each); the
   sheets are 2-coloured so that every guide triangle has one seed of each colour. A guide
   triangle with both seeds on one sheet means the union's boundary is not two sheets there,
   and the rule refuses.
3. **Which side is outside.** Each set of paired sheets surrounds one surface component.
   Oriented towards their colour-0 seeds, its guide triangles enclose a signed volume: if it is
   positive, colour 0 faces away from the component (outside it). A component nested inside
   an odd number of others (a cavity) swaps its sides, counted with the generalized winding
   number of the other components' oriented guide triangles.

Seeds on a sheet that no guide triangle pairs (a pocket of half-covered seeds) are labelled by
the winding number of all oriented guide triangles.

References
----------
The seeds and guide triangles of Section 4.1 (the seeds are the vertices of ∂∪B).
"""

from __future__ import annotations

import numpy as np

from ...errors import InputError
from ..balls import Balls
from ..guides.seeds import COVER_RTOL, SeededTriangles, lifted_balls, other_power

WINDING_INSIDE = 0.5
"""A point is enclosed by oriented triangles where their winding number exceeds this."""


class NotTwoSheets(InputError):
    """The union of balls' boundary does not split into an inside and an outside sheet."""


def sheet_labels(balls: Balls, seeded: SeededTriangles) -> np.ndarray:
    """(m, 2) inside labels of the seeds of ``seeded`` (guide and half-covered triples), by the
    sheets of ∂∪B (module docstring); False where a seed is covered.

    Raises
    ------
    NotTwoSheets
        A guide triangle has both seeds on one sheet.
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    row, side = np.nonzero(seeded.uncovered)
    count = len(row)
    arcs = _uncovered_arcs(balls, seeded.triples[row], seeded.seeds[row, side])
    graph = coo_matrix((np.ones(len(arcs)), (arcs[:, 0], arcs[:, 1])), shape=(count, count))
    sheets, sheet = connected_components(graph, directed=False)
    vertex = np.full(seeded.uncovered.shape, -1)
    vertex[row, side] = np.arange(count)
    guide = np.flatnonzero(seeded.guide)
    ends = sheet[vertex[guide]]
    if (ends[:, 0] == ends[:, 1]).any():
        first = guide[np.flatnonzero(ends[:, 0] == ends[:, 1])[0]]
        raise NotTwoSheets(
            "the union of balls' boundary is not two sheets: both seeds of the guide triangle "
            f"of balls {seeded.triples[first].tolist()} lie on one sheet"
        )
    colour, group = _two_colours(sheets, ends)
    triangle_group = group[ends[:, 0]]
    outside = _outside_colour(balls, seeded, guide, colour[ends], triangle_group)
    paired = group >= 0
    inside_sheet = np.zeros(sheets, dtype=bool)
    inside_sheet[paired] = colour[paired] != outside[group[paired]]
    labels = np.zeros(seeded.uncovered.shape, dtype=bool)
    labels[row, side] = inside_sheet[sheet]
    lone = ~paired[sheet]
    if lone.any():
        toward = np.argmax(colour[ends] == outside[triangle_group][:, None], axis=1)
        triangles = _oriented_triangles(balls, seeded, guide, toward)
        points = seeded.seeds[row[lone], side[lone]]
        labels[row[lone], side[lone]] = _winding(balls.centers, triangles, points) > WINDING_INSIDE
    return labels


def _uncovered_arcs(balls: Balls, triples: np.ndarray, points: np.ndarray) -> np.ndarray:
    """(a, 2) pairs of seeds joined by an uncovered arc of a circle ∂B_i ∩ ∂B_j."""
    from scipy.spatial import cKDTree

    count = len(points)
    seed_id = np.repeat(np.arange(count), 3)
    first = triples[:, [0, 0, 1]].reshape(-1)
    second = triples[:, [1, 2, 2]].reshape(-1)
    low, high = np.minimum(first, second), np.maximum(first, second)
    centre, axis_u, axis_v = _circle_frames(balls, low, high)
    offset = points[seed_id] - centre
    angle = np.arctan2((offset * axis_v).sum(1), (offset * axis_u).sum(1))
    key = low * len(balls) + high
    order = np.lexsort((angle, key))
    key, angle, seed_id = key[order], angle[order], seed_id[order]
    low, high = low[order], high[order]
    centre, axis_u, axis_v = centre[order], axis_u[order], axis_v[order]
    # Each entry's successor on its circle (the first one for the last: the arc wraps round).
    starts = np.flatnonzero(np.concatenate([[True], key[1:] != key[:-1]]))
    ends = np.concatenate([starts[1:], [len(key)]])
    group = np.repeat(np.arange(len(starts)), ends - starts)
    nxt = np.arange(len(key)) + 1
    nxt[ends - 1] = starts
    many = (ends - starts)[group] > 1
    here = np.flatnonzero(many)
    there = nxt[here]
    turn = angle[there] - angle[here]
    turn = np.where(turn <= 0, turn + 2 * np.pi, turn)
    middle = angle[here] + turn / 2
    radius = _circle_radius(balls, low[here], high[here])
    probe = centre[here] + radius[:, None] * (
        np.cos(middle)[:, None] * axis_u[here] + np.sin(middle)[:, None] * axis_v[here]
    )
    tree = cKDTree(lifted_balls(balls))
    own = np.column_stack([low[here], high[here], high[here]])
    power = other_power(tree, float(balls.weights.max()), probe, own)
    floor = COVER_RTOL * np.minimum(balls.weights[low[here]], balls.weights[high[here]])
    open_arc = power >= floor
    return np.column_stack([seed_id[here][open_arc], seed_id[there][open_arc]])


def _circle_frames(balls: Balls, low: np.ndarray, high: np.ndarray):
    """Centre and two unit axes spanning the plane of each circle ∂B_low ∩ ∂B_high."""
    p, q = balls.centers[low], balls.centers[high]
    gap = q - p
    length_sq = (gap * gap).sum(1)
    along = (length_sq + balls.weights[low] - balls.weights[high]) / (2 * length_sq)
    centre = p + along[:, None] * gap
    normal = gap / np.sqrt(length_sq)[:, None]
    helper = np.eye(3)[np.argmin(np.abs(normal), axis=1)]
    axis_u = np.cross(normal, helper)
    axis_u /= np.linalg.norm(axis_u, axis=1, keepdims=True)
    axis_v = np.cross(normal, axis_u)
    return centre, axis_u, axis_v


def _circle_radius(balls: Balls, low: np.ndarray, high: np.ndarray) -> np.ndarray:
    p, q = balls.centers[low], balls.centers[high]
    length_sq = ((q - p) ** 2).sum(1)
    along = (length_sq + balls.weights[low] - balls.weights[high]) / (2 * length_sq)
    return np.sqrt(np.maximum(balls.weights[low] - along**2 * length_sq, 0.0))


def _two_colours(count: int, ends: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Colour (0/1) of each sheet so that every pair in ``ends`` has both colours, and the
    group (connected set of paired sheets) of each sheet (-1: paired with none)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    a, b = ends[:, 0], ends[:, 1]
    rows = np.concatenate([2 * a, 2 * a + 1])
    cols = np.concatenate([2 * b + 1, 2 * b])
    cover = coo_matrix((np.ones(len(rows)), (rows, cols)), shape=(2 * count, 2 * count))
    _, label = connected_components(cover, directed=False)
    if (label[0::2] == label[1::2]).any():
        raise NotTwoSheets(
            "the union of balls' boundary is not two sheets: its sheets cannot be split into "
            "inside and outside (an odd cycle of guide triangles)"
        )
    colour = (label[0::2] > label[1::2]).astype(np.int64)
    touched = np.zeros(count, dtype=bool)
    touched[ends.reshape(-1)] = True
    pair = np.minimum(label[0::2], label[1::2])
    _, group = np.unique(pair, return_inverse=True)
    group = np.where(touched, group, -1)
    if touched.any():
        _, group[touched] = np.unique(group[touched], return_inverse=True)
    return colour, group


def _outside_colour(balls, seeded, guide, colours, groups) -> np.ndarray:
    """Per group, the colour whose seeds lie outside the solid (step 3 of the rule)."""
    count = int(groups.max()) + 1 if len(groups) else 0
    triangles = _oriented_triangles(balls, seeded, guide, np.argmin(colours, axis=1))
    corners = balls.centers[triangles]
    volume = np.einsum("ij,ij->i", corners[:, 0], np.cross(corners[:, 1], corners[:, 2])) / 6
    outer = (np.bincount(groups, volume, count) < 0).astype(np.int64)
    if count < 2:
        return outer
    # Cavities: a group inside an odd number of others has its sides swapped.
    first = np.array([np.flatnonzero(groups == g)[0] for g in range(count)])
    probe = seeded.seeds[guide[first], 0]
    depth = np.zeros(count, dtype=np.int64)
    for g in range(count):
        enclosed = np.abs(_winding(balls.centers, triangles[groups == g], probe))
        enclosed[g] = 0.0
        depth += enclosed > WINDING_INSIDE
    return np.where(depth % 2 == 1, 1 - outer, outer)


def _oriented_triangles(balls, seeded, guide, toward: np.ndarray) -> np.ndarray:
    """The guide triangles' ball triples, turned so that each normal points towards its seed
    ``toward`` (0 or 1)."""
    triples = seeded.triples[guide]
    corners = balls.centers[triples]
    normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    target = seeded.seeds[guide, toward]
    ahead = np.einsum("ij,ij->i", normal, target - corners[:, 0]) > 0
    return np.where(ahead[:, None], triples, triples[:, ::-1])


def _winding(vertices, triangles, points) -> np.ndarray:
    import igl

    if len(triangles) == 0 or len(points) == 0:
        return np.zeros(len(points))
    return igl.winding_number(
        np.ascontiguousarray(vertices, dtype=float),
        np.ascontiguousarray(triangles, dtype=np.int64),
        np.ascontiguousarray(points, dtype=float),
    )
