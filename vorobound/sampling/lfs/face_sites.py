"""Points spread over the faces of a mesh at a requested spacing, on the smooth patches.

The estimate of the local feature size must not depend on how an exporter triangulated a
part, so it is computed from points inside the faces, not only from the vertices. Every face
is split by longest-edge bisection (which keeps even a needle's pieces well shaped) until no
piece is longer than the spacing asked for at its centroid; each piece contributes its
centroid, with the piece's area. Given the patch of each face, the thin pieces of long thin
faces (whose width is the face's, not the spacing) are halved across their longest edge
rather than quartered, and those of one patch lying close together are merged into one site
that stands for all of them (:func:`merge_thin`): the sites then follow the area of a patch,
not the number of its faces.

On a curved patch the centroid is moved onto a smooth surface through the vertices: the cubic
point-normal triangle of Vlachos et al. ("Curved PN triangles", 2001) built from the patch's
vertex normals. On a flat patch that surface is the face itself. The site's normal is the
normalized interpolation of the corner normals.

Feature edges get points of their own, at the same spacing, for the feature terms of the
estimate (docs/lfs.md).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ...errors import InputError
from ...mesh.rows import unique_rows

MAX_SITES = 4_000_000
"""Largest number of face pieces produced (refused beyond; about 0.5 GB of sites)."""
MAX_LEVELS = 60
"""Bisection levels at most (a needle 10¹⁸ times longer than the spacing needs about 60)."""


@dataclass(frozen=True)
class FaceSites:
    """Points on the faces: centroids of the bisection pieces, lifted onto their patch."""

    points: np.ndarray
    """(n, 3) positions on the smooth patch surface."""
    normals: np.ndarray
    """(n, 3) unit normal lines (interpolated corner normals)."""
    face: np.ndarray
    """(n,) face of each point."""
    areas: np.ndarray
    """(n,) area of each point's piece (the pieces tile the faces)."""
    sizes: np.ndarray
    """(n,) longest edge of each point's piece."""
    corners: np.ndarray | None
    """(n, 3, 3) the piece itself, on the flat face (None with ``reach``: a merged site stands
    for several pieces, and the reach is what the estimate needs of them)."""
    reach: np.ndarray | None = None
    """(n,) distance from each point to the farthest corner of the pieces it stands for (None:
    its own piece's)."""


@dataclass(frozen=True)
class EdgeSites:
    """Points on the feature edges."""

    points: np.ndarray
    edge: np.ndarray
    """(n,) index into the feature edges."""
    lengths: np.ndarray
    """(n,) length of each point's piece of its edge."""


def face_sites(
    points: np.ndarray,
    faces: np.ndarray,
    corner_normals: np.ndarray,
    curved: np.ndarray,
    spacing: Callable[[np.ndarray, np.ndarray], np.ndarray],
    max_sites: int = MAX_SITES,
    slope=None,
    groups: np.ndarray | None = None,
    floor: np.ndarray | None = None,
) -> FaceSites:
    """Split every face until its pieces are at most ``spacing(centroid)`` long.

    A face is first cut into slabs parallel to its shortest edge and each slab into columns
    (:func:`_slabs`), which turns even a needle into pieces of aspect ratio about one; pieces
    still longer than the spacing at their centroid (L varies along the face) are split into
    four by their edge midpoints until they are not.

    Parameters
    ----------
    points, faces : ndarray
        Vertices (m, 3) and triangles (f, 3).
    corner_normals : ndarray (f, 3, 3)
        Normal at each face corner (within the face's patch).
    curved : ndarray (f,) of bool
        Faces of curved patches (their sites are lifted onto the PN surface).
    spacing : callable
        Maps (k, 3) points and their (k,) faces to (k,) positive lengths.
    slope : float or ndarray (f,), optional
        A Lipschitz constant of ``spacing`` on each face (|spacing(x) − spacing(y)| ≤
        slope·|x − y| for x, y on one face). With it, a piece whose size is below (or above)
        the bound this gives from the spacing at its parent's centroid is kept (or split)
        without asking ``spacing`` again: the pieces are the same, the spacing is asked at
        fewer points (:func:`_decided`).
    groups : ndarray (f,), optional
        The patch of each face. With it, thin pieces (the pieces of long thin faces, whose
        width is the face's, not the spacing) of one patch are merged into one site where
        all of them lie within the spacing of it (:func:`merge_thin`).
    floor : ndarray (f,), optional
        A lower bound of ``spacing`` on each face: a piece no longer than it is kept without
        asking ``spacing`` (the pieces are the same; where the spacing is at its floor, as on
        most pieces of a part's long thin faces, it is not asked at all).
    """
    if groups is None:
        return _face_sites(
            points, faces, corner_normals, curved, spacing, max_sites, slope, floor=floor
        )
    corners = points[faces]
    centroid = corners.mean(axis=1)
    first = np.asarray(spacing(centroid, np.arange(len(faces))), dtype=float)
    count = _first_pieces(corners, first)
    if count.sum() <= CHUNK_PIECES:
        return _face_sites(
            points, faces, corner_normals, curved, spacing, max_sites, slope, groups, floor
        )
    # Long thin faces make many pieces before they merge: cut the faces in batches, each of
    # one patch's faces near one another (in cells of 1/64 of the part), so that a batch
    # holds most of the pieces a merge joins and the pieces of one batch at a time are in
    # memory. A cube split between two batches gives two merged sites, each within the
    # spacing of its pieces.
    extent = np.ptp(centroid, axis=0).max()
    cell = np.floor(64 * (centroid - centroid.min(axis=0)) / (extent if extent > 0 else 1.0))
    order = np.lexsort((cell[:, 2], cell[:, 1], cell[:, 0], groups))
    batch = np.floor(np.cumsum(count[order]) / CHUNK_PIECES).astype(np.int64)
    cuts = np.flatnonzero(np.diff(batch)) + 1
    slopes = None if slope is None else np.broadcast_to(np.asarray(slope, float), len(faces))
    parts: list[dict] = []
    total = 0
    for chosen in np.split(order, cuts):

        def local(x, face, chosen=chosen):
            return spacing(x, chosen[face])

        part = _face_sites(
            points,
            faces[chosen],
            corner_normals[chosen],
            curved[chosen],
            local,
            max_sites,
            None if slopes is None else slopes[chosen],
            groups[chosen],
            None if floor is None else floor[chosen],
        )
        total += len(part.points)
        if total > max_sites:
            raise _too_many(max_sites)
        # Every batch is cut with its groups, so every part carries the reach of its sites.
        assert part.reach is not None
        parts.append(dict(vars(part), face=chosen[part.face]))

    def joined(name: str) -> np.ndarray:
        """The parts' ``name`` in one array; the parts' own arrays are let go as it is made,
        so that the sites are held about once, not twice, while they are joined."""
        return np.concatenate([p.pop(name) for p in parts])

    return FaceSites(
        points=joined("points"),
        normals=joined("normals"),
        face=joined("face"),
        areas=joined("areas"),
        sizes=joined("sizes"),
        corners=None,
        reach=joined("reach"),
    )


CHUNK_PIECES = 250_000
"""With ``groups``, faces whose first pieces are more than this many are cut in batches of
about this many first pieces (:func:`face_sites`)."""


def _first_pieces(corners: np.ndarray, spacing: np.ndarray) -> np.ndarray:
    """Pieces of each face's slabs (:func:`_slabs`) at ``spacing``: slabs times columns."""
    lengths = np.linalg.norm(corners - np.roll(corners, -1, axis=1), axis=2)
    step = spacing / np.sqrt(2)
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        slabs = np.ceil(np.sort(lengths, axis=1)[:, 2] / step)
        columns = np.maximum(np.ceil(lengths.min(axis=1) / step), 1)
    out = slabs * columns
    return np.where(np.isfinite(out), out, 1.0)


def _face_sites(
    points,
    faces,
    corner_normals,
    curved,
    spacing,
    max_sites=MAX_SITES,
    slope=None,
    groups=None,
    floor=None,
) -> FaceSites:
    """:func:`face_sites` of one batch of faces."""
    # The pieces follow the corner order: put the corners in vertex order, so a face listed
    # in either orientation (or rotated) gives the same sites.
    order = np.argsort(faces, axis=1, kind="stable")
    faces = np.take_along_axis(faces, order, axis=1)
    corner_normals = np.take_along_axis(corner_normals, order[:, :, None], axis=1)
    corners = points[faces]
    centroid = corners.mean(axis=1)
    first = np.asarray(spacing(centroid, np.arange(len(faces))), dtype=float)
    owner, bary = _slabs(corners, first, max_sites)
    # The spacing at each piece's parent (the face's centroid for the first pieces).
    parent_middle, parent_limit = centroid[owner], first[owner]
    slopes = None if slope is None else np.broadcast_to(np.asarray(slope, float), len(faces))
    done_owner, done_bary, done_xyz, done_size, done_low = [], [], [], [], []
    for level in range(MAX_LEVELS):
        xyz = np.einsum("nkc,ncd->nkd", bary, corners[owner])
        size = np.linalg.norm(xyz - np.roll(xyz, -1, axis=1), axis=2).max(axis=1)
        middle = xyz.mean(axis=1)
        limit = np.empty(len(owner))
        # A face left whole (most faces of a fine mesh) has its spacing already.
        known = (middle == centroid[owner]).all(axis=1) if level == 0 else np.zeros(0, bool)
        limit[known] = first[owner[known]]
        ask = np.flatnonzero(~known) if level == 0 else np.arange(len(owner))
        split = np.zeros(len(owner), dtype=bool)
        low = np.full(len(owner), np.nan)  # a lower bound on the spacing at the piece
        if slopes is not None or floor is not None:
            keep, cut, bound = _decided(
                size[ask],
                owner[ask],
                middle[ask],
                parent_middle[ask],
                parent_limit[ask],
                slopes,
                floor,
            )
            split[ask[cut]] = True
            low[ask[keep]] = bound[keep]
            limit[ask[keep | cut]] = np.nan  # decided without it (never used again)
            ask = ask[~(keep | cut)]
        limit[ask] = np.asarray(spacing(middle[ask], owner[ask]), dtype=float)
        split[ask] = size[ask] > limit[ask]
        if level == 0:
            split[known] = size[known] > limit[known]
        low = np.where(np.isnan(low), limit, low)
        done_owner.append(owner[~split])
        done_bary.append(bary[~split])
        done_xyz.append(xyz[~split])
        done_size.append(size[~split])
        done_low.append(low[~split])
        if not split.any():
            break
        owner, bary = owner[split], bary[split]
        # With groups, a thin piece is halved across its longest edge (two pieces, each
        # about half as long and as wide as it), not quartered (four, each half as wide too:
        # a needle's pieces would multiply by four per level where two suffice).
        halve = np.zeros(len(owner), dtype=bool)
        if groups is not None:
            cut_xyz = xyz[split]
            cut_area = 0.5 * np.linalg.norm(
                np.cross(cut_xyz[:, 1] - cut_xyz[:, 0], cut_xyz[:, 2] - cut_xyz[:, 0]), axis=1
            )
            halve = cut_area < THIN * size[split] ** 2
        children = np.where(halve, 2, 4)
        if sum(len(o) for o in done_owner) + int(children.sum()) > max_sites:
            raise _too_many(max_sites)
        # A piece split without asking hands its parent's point and spacing down: its children
        # measure their reach from there.
        moved = np.isnan(limit[split])
        parent_middle = np.where(moved[:, None], parent_middle[split], middle[split])
        parent_limit = np.where(moved, parent_limit[split], limit[split])
        four, two = ~halve, halve
        parent_middle = np.concatenate(
            [np.repeat(parent_middle[four], 4, axis=0), np.repeat(parent_middle[two], 2, axis=0)]
        )
        parent_limit = np.concatenate(
            [np.repeat(parent_limit[four], 4), np.repeat(parent_limit[two], 2)]
        )
        bary = np.concatenate([_quarter(bary[four]), _halve(bary[two], xyz[split][two])])
        owner = np.concatenate([np.repeat(owner[four], 4), np.repeat(owner[two], 2)])
    else:
        raise InputError("face subdivision did not converge (the spacing is far too small)")
    owner = np.concatenate(done_owner)
    bary = np.concatenate(done_bary)
    xyz, size = np.concatenate(done_xyz), np.concatenate(done_size)  # size: longest edge
    area = 0.5 * np.linalg.norm(np.cross(xyz[:, 1] - xyz[:, 0], xyz[:, 2] - xyz[:, 0]), axis=1)
    reach = None
    if groups is not None:
        low = np.concatenate(done_low)
        # Without the spacing at a piece (a face left whole), its own size bounds it below.
        low = np.where(np.isfinite(low), low, size)
        chosen, area, reach = merge_thin(xyz, area, size, low, groups[owner])
        owner, bary, xyz, size = owner[chosen], bary[chosen], xyz[chosen], size[chosen]
    centre = bary.mean(axis=1)  # barycentric coordinates of the piece's centroid
    position = np.einsum("nc,ncd->nd", centre, corners[owner])
    lifted = curved[owner]
    if lifted.any():
        position[lifted] = pn_points(
            corners[owner[lifted]], corner_normals[owner[lifted]], centre[lifted]
        )
    normal = np.einsum("nc,ncd->nd", centre, corner_normals[owner])
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    if reach is not None:
        # From the site (lifted onto its patch) to the farthest corner it stands for: its own
        # piece's, or (merged) at most the reach from the flat centroid plus the lift.
        own = np.linalg.norm(xyz - position[:, None], axis=2).max(axis=1)
        lift = np.linalg.norm(position - xyz.mean(axis=1), axis=1)
        reach = np.where(np.isnan(reach), own, reach + lift)
    # With groups every site has its reach; the pieces' corners are not kept (the largest
    # array of the sites, not needed then).
    corners = xyz if reach is None else None
    return FaceSites(position, normal, owner, area, size, corners, reach)


THIN = 0.1
"""Pieces whose area is below this times their longest edge squared are thin (a slab piece of
a well-shaped face: 0.25; of a face 20 times longer than wide: about 0.025)."""
MERGE_PASSES = ((1.0, 0.0), (1.0, 0.5), (0.5, 0.0), (0.5, 0.5), (0.25, 0.0), (0.25, 0.5))
"""The grids of :func:`merge_thin`, one pass each over the thin pieces not merged yet: cubes of
about the first number times their spacing (a power of two), shifted by the second number of
cube sides. Large cubes first (a merged site then stands for many pieces), small ones for what
is left; the shifted grid joins pieces a cube boundary kept apart."""
MERGE_REACH = 1 / np.sqrt(3)
"""A merge is kept where every corner of its pieces lies within this times their spacing s
from the site: the bound a single piece of longest edge s meets (its centroid is within
s/√3 of its corners), so a merged site stands for no more surface than a piece does."""
MERGE_FLAT = 0.005
"""... and where the spacing of its pieces varies by at most this share (L nearly constant
over them: where L changes, the pieces stay sites of their own). With the larger merges of
:data:`MERGE_PASSES`, 5 % let L of the coarse L-bracket move away from the fine one's
(docs/lfs.md, triangulation independence); 0.5 % keeps it where single cubes had it."""


def merge_thin(xyz, area, size, spacing, group):
    """Thin pieces of one patch (``group``) merged into sites that stand for several: the
    representative piece stands for all, with their summed area (the sites still tile the
    surface). A merge is kept only where every corner of its pieces lies within MERGE_REACH
    = 1/√3 times the smallest spacing s of its pieces from the representative's centroid
    (``spacing``: a lower bound of the spacing at each piece), the bound every single piece no
    longer than s meets, and where the spacing of its pieces varies by at most MERGE_FLAT: so
    a merged site stands for no more surface than a piece of the spacing does, and the
    resolution of L the spacing asks for is kept.

    The merges are proposed on grids of cubes (:data:`MERGE_PASSES`), one pass per grid over
    the thin pieces no earlier pass merged (:func:`_merge_pass`).

    Returns (the pieces kept as sites, their areas, their reach: the distance from each merged
    one's centroid to the farthest corner it stands for, NaN for a piece of its own).
    """
    count = len(xyz)
    keep = np.ones(count, dtype=bool)
    new_area, new_reach = area.copy(), np.full(count, np.nan)
    rows = np.flatnonzero(area < THIN * size**2)
    middle = xyz.mean(axis=1)
    for cell, shift in MERGE_PASSES:
        if len(rows) < 2:
            break
        rows = _merge_pass(
            rows, (cell, shift), xyz, middle, area, spacing, group, keep, new_area, new_reach
        )
    chosen = np.flatnonzero(keep)
    return chosen, new_area[chosen], new_reach[chosen]


def _merge_pass(rows, grid, xyz, middle, area, spacing, group, keep, new_area, new_reach):
    """One pass of :func:`merge_thin` over the thin pieces ``rows`` on ``grid`` (cube size
    relative to the spacing, shift in cube sides): in each cube of one patch, the piece
    nearest the area-weighted centroid of the cube's pieces is the representative; a piece
    joins it where its spacing lies within a factor √(1 + MERGE_FLAT) of the
    representative's, s_r, and its corners within MERGE_REACH·s_r/√(1 + MERGE_FLAT) of the
    representative's centroid (so the merge meets both conditions of :func:`merge_thin`, which
    are checked again as stated). Writes the merges into ``keep``, ``new_area`` and
    ``new_reach``; returns the pieces left for the next pass."""
    cell, shift = grid
    level = np.floor(np.log2(cell * spacing[rows]))
    cube = np.floor(middle[rows] / np.exp2(level)[:, None] + shift)
    cluster = _row_labels(np.c_[group[rows], level, cube])
    clusters = int(cluster.max()) + 1
    weight = area[rows]
    total = np.bincount(cluster, weight, clusters)
    centre = (
        np.stack(
            [np.bincount(cluster, weight * middle[rows, k], clusters) for k in range(3)], axis=1
        )
        / np.where(total > 0, total, 1.0)[:, None]
    )
    # The representative: the member nearest the merged centroid (ties: the first).
    gap = np.linalg.norm(middle[rows] - centre[cluster], axis=1)
    nearest = np.full(clusters, np.inf)
    np.minimum.at(nearest, cluster, gap)
    tied = np.flatnonzero(gap == nearest[cluster])
    first = np.full(clusters, len(rows))
    np.minimum.at(first, cluster[tied], tied)
    rep = rows[first]
    own = spacing[rep][cluster]
    far = np.linalg.norm(xyz[rows] - middle[rep][cluster][:, None], axis=2).max(axis=1)
    spread = np.sqrt(1 + MERGE_FLAT)
    joins = (spacing[rows] >= own / spread) & (spacing[rows] <= own * spread)
    joins &= far <= MERGE_REACH * own / spread
    joins[first] = True
    member, cluster, far = rows[joins], cluster[joins], far[joins]
    reach = np.zeros(clusters)
    np.maximum.at(reach, cluster, far)
    bound = np.full(clusters, np.inf)
    np.minimum.at(bound, cluster, spacing[member])
    top = np.zeros(clusters)
    np.maximum.at(top, cluster, spacing[member])
    members = np.bincount(cluster, minlength=clusters)
    merged = (members > 1) & (reach <= MERGE_REACH * bound) & (top <= (1 + MERGE_FLAT) * bound)
    gone = member[merged[cluster]]
    keep[gone] = False
    keep[rep[merged]] = True
    new_area[rep[merged]] = np.bincount(cluster, area[member], clusters)[merged]
    new_reach[rep[merged]] = reach[merged]
    left = np.ones(len(keep), dtype=bool)
    left[gone] = False
    return rows[left[rows]]


def _row_labels(key: np.ndarray) -> np.ndarray:
    """The inverse of ``np.unique(key, axis=0)`` for rows of integer-valued floats: as
    integers through :func:`vorobound.mesh.rows.unique_rows` (packed keys, many times faster
    than sorting rows of floats) where they are exact, else numpy's call."""
    if not np.abs(key).max() < 2.0**52:  # beyond, not every float is an int64 exactly
        _, inverse = np.unique(key, axis=0, return_inverse=True)
        return inverse.reshape(-1)
    return unique_rows(key.astype(np.int64), return_inverse=True)[1]


DECIDED_RTOL = 1e-9
"""Margin of :func:`_decided` (relative): a piece this close to a bound is asked for."""


def _decided(size, owner, middle, parent_middle, parent, slopes, floor):
    """(kept, split, bound): pieces whose spacing s is known to be at least ``size`` (kept) or
    below it (split) without asking, and a lower bound of s at each piece. With ``slopes``:
    s ≥ parent − reach and s ≤ parent + reach (reach: the face's slope times the distance from
    the point where s is ``parent``); with ``floor``: s ≥ the face's floor, so a piece no
    longer than it is kept."""
    bound = np.full(len(size), -np.inf)
    split = np.zeros(len(size), dtype=bool)
    if slopes is not None:
        reach = slopes[owner] * np.linalg.norm(middle - parent_middle, axis=1)
        bound = (parent - reach) * (1 - DECIDED_RTOL)
        split = size > (parent + reach) * (1 + DECIDED_RTOL)
    kept = size <= bound
    if floor is not None:
        kept |= size <= floor[owner]
        bound = np.maximum(bound, floor[owner])
    return kept, split & ~kept, bound


def _too_many(max_sites: int) -> InputError:
    return InputError(
        f"the faces need more than {max_sites:,} pieces at the requested spacing: the local "
        "feature size is tiny compared with the part (check the mesh's units and its sharp "
        "features)"
    )


def _slabs(corners: np.ndarray, spacing: np.ndarray, max_sites: int):
    """Cut each triangle into slabs parallel to its shortest edge AB (k slabs from the
    opposite corner C) and each slab into columns along AB, every piece at most ``spacing``
    long; returns (owner face, barycentric corners) of the pieces."""
    lengths = np.linalg.norm(corners - np.roll(corners, -1, axis=1), axis=2)  # edge k: k → k+1
    shortest = lengths.argmin(axis=1)
    step = spacing / np.sqrt(2)  # a piece's diagonal then stays below the spacing
    a_index, b_index = shortest, (shortest + 1) % 3
    c_index = (shortest + 2) % 3
    rows = np.arange(len(corners))
    side = lengths[rows, shortest]
    reach = np.maximum(lengths[rows, (shortest + 1) % 3], lengths[rows, (shortest + 2) % 3])
    with np.errstate(over="ignore", invalid="ignore"):
        slabs = np.ceil(reach / step)
        columns = np.ceil(side / step)
    if not (np.isfinite(slabs).all() and np.isfinite(columns).all()):
        raise InputError("the spacing of the face sites must be positive and finite")
    estimate = float((slabs * np.maximum(columns, 1)).sum())
    if estimate > max_sites:
        raise _too_many(max_sites)
    slabs, columns = slabs.astype(np.int64), np.maximum(columns, 1).astype(np.int64)
    # One row per slab i of face f (faces in order), then one entry per piece: slab i has
    # j = ceil((i + 1)/k · columns) columns, each an upper triangle and (above the first slab,
    # whose bottom is the corner C) a lower one, in that order along the slab.
    face = np.repeat(np.arange(len(corners)), slabs)
    slab = np.arange(len(face)) - np.repeat(np.cumsum(slabs) - slabs, slabs)
    k = slabs[face]
    top = (slab + 1) / k
    j = np.maximum(1, np.ceil(top * columns[face]).astype(np.int64))
    count = np.where(slab == 0, j, 2 * j)
    row = np.repeat(np.arange(len(face)), count)
    within = np.arange(len(row)) - np.repeat(np.cumsum(count) - count, count)
    lower = within >= j[row]
    m = within - np.where(lower, j[row], 0)
    t_low, t_high = (slab / k)[row], top[row]
    s_this, s_next = m / j[row], (m + 1) / j[row]
    # A point at height t and position s along the slab has weights t(1 − s), t·s, 1 − t on
    # the corners A, B, C.
    first = _at(t_low, s_this)
    second = np.where(lower[:, None], _at(t_high, s_next), _at(t_high, s_this))
    third = np.where(lower[:, None], _at(t_low, s_next), _at(t_high, s_next))
    owner = face[row]
    columns_abc = np.stack([a_index, b_index, c_index], axis=1)[owner]
    pieces = np.zeros((len(row), 3, 3))
    rows = np.arange(len(row))[:, None]
    for corner, weights in enumerate((first, second, third)):
        pieces[rows, corner, columns_abc] = weights
    return owner, pieces


def _at(t: np.ndarray, s: np.ndarray) -> np.ndarray:
    """(n, 3) weights of the slab corners A, B, C at height t and position s."""
    return np.stack([t * (1 - s), t * s, 1 - t], axis=1)


def _halve(bary: np.ndarray, xyz: np.ndarray) -> np.ndarray:
    """Each piece split in two at the midpoint of its longest edge (``xyz``: its corners)."""
    lengths = np.linalg.norm(xyz - np.roll(xyz, -1, axis=1), axis=2)  # edge k: k → k+1
    k = lengths.argmax(axis=1)
    rows = np.arange(len(bary))
    a, b, c = bary[rows, k], bary[rows, (k + 1) % 3], bary[rows, (k + 2) % 3]
    m = 0.5 * (a + b)
    out = np.empty((2 * len(bary), 3, 3))
    out[0::2] = np.stack([a, m, c], axis=1)
    out[1::2] = np.stack([m, b, c], axis=1)
    return out


def _quarter(bary: np.ndarray) -> np.ndarray:
    """Each piece split into four by its edge midpoints."""
    a, b, c = bary[:, 0], bary[:, 1], bary[:, 2]
    ab, bc, ca = 0.5 * (a + b), 0.5 * (b + c), 0.5 * (c + a)
    out = np.empty((4 * len(bary), 3, 3))
    out[0::4] = np.stack([a, ab, ca], axis=1)
    out[1::4] = np.stack([ab, b, bc], axis=1)
    out[2::4] = np.stack([ca, bc, c], axis=1)
    out[3::4] = np.stack([ab, bc, ca], axis=1)
    return out


def pn_points(corners: np.ndarray, normals: np.ndarray, bary: np.ndarray) -> np.ndarray:
    """Points of the cubic PN triangles (Vlachos et al. 2001) at barycentric ``bary``.

    ``corners`` (n, 3, 3) P1, P2, P3; ``normals`` (n, 3, 3) their unit normals; ``bary``
    (n, 3) the weights of P1, P2, P3. With equal normals the patch is the flat triangle.
    """
    p1, p2, p3 = corners[:, 0], corners[:, 1], corners[:, 2]
    n1, n2, n3 = normals[:, 0], normals[:, 1], normals[:, 2]

    def tangent(pi, pj, ni):
        w = ((pj - pi) * ni).sum(axis=1)[:, None]
        return (2 * pi + pj - w * ni) / 3

    b210, b120 = tangent(p1, p2, n1), tangent(p2, p1, n2)
    b021, b012 = tangent(p2, p3, n2), tangent(p3, p2, n3)
    b102, b201 = tangent(p3, p1, n3), tangent(p1, p3, n1)
    e = (b210 + b120 + b021 + b012 + b102 + b201) / 6
    v = (p1 + p2 + p3) / 3
    b111 = e + (e - v) / 2
    w1, w2, w3 = (bary[:, k][:, None] for k in range(3))
    return (
        p1 * w1**3
        + p2 * w2**3
        + p3 * w3**3
        + 3 * b210 * w1**2 * w2
        + 3 * b120 * w1 * w2**2
        + 3 * b201 * w1**2 * w3
        + 3 * b021 * w2**2 * w3
        + 3 * b102 * w1 * w3**2
        + 3 * b012 * w2 * w3**2
        + 6 * b111 * w1 * w2 * w3
    )


def edge_sites(
    points: np.ndarray,
    edges: np.ndarray,
    spacing: Callable[[np.ndarray, np.ndarray], np.ndarray],
) -> EdgeSites:
    """Midpoints of the pieces of each edge, split evenly to at most ``spacing`` long."""
    if len(edges) == 0:
        return EdgeSites(np.zeros((0, 3)), np.zeros(0, dtype=np.int64), np.zeros(0))
    a, b = points[edges[:, 0]], points[edges[:, 1]]
    length = np.linalg.norm(b - a, axis=1)
    step = np.asarray(spacing(0.5 * (a + b), np.arange(len(edges))), dtype=float)
    pieces = np.maximum(1, np.ceil(length / step))
    if pieces.sum() > MAX_SITES:
        raise InputError(f"the feature edges need more than {MAX_SITES:,} points")
    pieces = pieces.astype(np.int64)
    edge = np.repeat(np.arange(len(edges)), pieces)
    start = np.repeat(np.cumsum(pieces) - pieces, pieces)
    t = (np.arange(len(edge)) - start + 0.5) / pieces[edge]
    where = a[edge] + t[:, None] * (b[edge] - a[edge])
    return EdgeSites(where, edge, (length / pieces)[edge])


def face_curvature_radius(points, faces, corner_normals) -> np.ndarray:
    """Per face: 1/κ_max of the shape operator that maps edge vectors to normal changes.

    In the face's plane, dN = S·dP for the two edges from the first corner; S is symmetrized
    and its largest absolute eigenvalue is κ_max. Exact for the vertex normals of a sphere or a
    cylinder, whatever the shape of the triangle (also a needle along a cylinder's axis).
    inf on flat faces.
    """
    p = points[faces]
    n = corner_normals
    d1, d2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    g1, g2 = n[:, 1] - n[:, 0], n[:, 2] - n[:, 0]
    e1 = d1 / np.linalg.norm(d1, axis=1)[:, None]
    normal = np.cross(d1, d2)
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    e2 = np.cross(normal, e1)
    dp = np.stack(
        [np.c_[(d1 * e1).sum(1), (d1 * e2).sum(1)], np.c_[(d2 * e1).sum(1), (d2 * e2).sum(1)]],
        axis=2,
    )
    dn = np.stack(
        [np.c_[(g1 * e1).sum(1), (g1 * e2).sum(1)], np.c_[(g2 * e1).sum(1), (g2 * e2).sum(1)]],
        axis=2,
    )
    with np.errstate(all="ignore"):
        shape = dn @ np.linalg.inv(dp)
        shape = 0.5 * (shape + np.swapaxes(shape, 1, 2))
        kappa = np.abs(np.linalg.eigvalsh(shape)).max(axis=1)
        radius = np.where(kappa > 0, 1 / kappa, np.inf)
    return np.where(np.isfinite(radius) | (kappa == 0), radius, np.inf)
