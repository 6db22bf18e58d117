"""Compiled reader of a GUDHI simplex tree's serialized form (needs the optional numba).

:func:`vorobound.sampling.simplices.tree_simplices` hands this kernel the bytes of
``SimplexTree.__getstate__()`` (GUDHI's pickle format): after a 6-byte header, the root's
block, then depth first the block of every member's children. A block is its member count
(a 4-byte vertex handle) followed by each member's vertex handle and filtration value (4 + 8
bytes); a member without children has a block of count 0. One pass with a stack of the open
blocks writes every triangle and tetrahedron, vertices ascending (the tree's order).

Importing this module compiles nothing; the first call compiles and caches the machine code on
disk. The kernel is kept in its own file (numba checks only the defining file's timestamp
before reusing cached code) and uses no compiled helper from another module.
"""

from __future__ import annotations

import numpy as np
from numba import njit

HEADER = 6
"""Bytes before the root's block."""
RECORD = 12
"""Bytes of one member: vertex handle (4) and filtration value (8)."""
MAX_DEPTH = 4
"""Blocks nest at most this deep in a complex of dimension 3."""


@njit(inline="always")
def _word(data, pos):
    """The little-endian 4-byte integer at byte ``pos`` (the data is read unaligned)."""
    return (
        np.int64(data[pos])
        | (np.int64(data[pos + 1]) << 8)
        | (np.int64(data[pos + 2]) << 16)
        | (np.int64(data[pos + 3]) << 24)
    )


@njit(inline="always")
def _write_block(data, path, block, depth, children, out, found):
    """The simplices a block at ``depth`` closes (the open path's vertices, then each member's)
    into ``out`` from row ``found``, or only counted when ``out`` has no rows; returns the new
    count, −1 when ``out`` is too short."""
    if out.shape[0] == 0:
        return found + children
    if found + children > out.shape[0]:
        return -1
    for j in range(children):
        for k in range(depth):
            out[found, k] = path[k]
        out[found, depth] = _word(data, block + RECORD * j)
        found += 1
    return found


@njit(cache=True, nogil=True)
def read_tree(data, triangles, tetrahedra):
    """Fill ``triangles`` (m, 3) and ``tetrahedra`` (k, 4) from the serialized tree ``data``
    (uint8); returns the number of each found and the bytes read (−1, −1, position where the
    layout is not the one expected: the caller then falls back to GUDHI's iterator). An array
    with no rows is not filled (its simplices are only counted)."""
    size = data.shape[0]
    path = np.zeros(MAX_DEPTH, np.int64)
    start = np.zeros(MAX_DEPTH, np.int64)
    count = np.zeros(MAX_DEPTH, np.int64)
    done = np.zeros(MAX_DEPTH, np.int64)
    if size < HEADER + 4:
        return -1, -1, 0
    pos = HEADER
    count[0] = _word(data, pos)
    start[0] = pos + 4
    pos += 4 + RECORD * count[0]
    found_tri = 0
    found_tet = 0
    depth = 0
    while depth >= 0:
        if done[depth] == count[depth]:
            depth -= 1
            continue
        member = done[depth]
        done[depth] = member + 1
        path[depth] = _word(data, start[depth] + RECORD * member)
        if pos + 4 > size:
            return -1, -1, pos
        children = _word(data, pos)
        if children == 0:
            pos += 4
            continue
        depth += 1
        if depth >= MAX_DEPTH or pos + 4 + RECORD * children > size:
            return -1, -1, pos
        start[depth] = pos + 4
        count[depth] = children
        done[depth] = 0
        pos += 4 + RECORD * children
        if depth == 2:
            found_tri = _write_block(data, path, start[2], 2, children, triangles, found_tri)
            if found_tri < 0:
                return -1, -1, pos
        elif depth == 3:
            found_tet = _write_block(data, path, start[3], 3, children, tetrahedra, found_tet)
            if found_tet < 0:
                return -1, -1, pos
    return found_tri, found_tet, pos
