"""The nearest point of an allowed label: k-d tree queries for the k nearest points, k grown
until each query has found one that its own label allows."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from ..geometry.threads import thread_count


def nearest_allowed(
    tree: Any,
    queries: np.ndarray,
    allowed: Callable[[np.ndarray, np.ndarray], np.ndarray],
    neighbours: Sequence[int],
) -> tuple[np.ndarray, np.ndarray]:
    """Distance to and index of the nearest point of ``tree`` (a scipy k-d tree) that
    ``allowed`` accepts, for each of ``queries`` (m, 3).

    ``allowed(rows, index)`` gets the query rows still searching (r,) and the indices of
    their k nearest points (r, k), nearest first, and says which of those points each query
    accepts (r, k) bool. The k nearest are tried for each k of ``neighbours`` in turn, the
    next k only for the queries that found none; the search ends early once k covers every
    point. Distance inf and index −1 where no point was accepted.
    """
    count = int(tree.n)
    distance = np.full(len(queries), np.inf)
    found_index = np.full(len(queries), -1, dtype=np.int64)
    todo = np.arange(len(queries))
    for k in neighbours:
        if not len(todo) or count == 0:
            break
        k_eff = min(k, count)
        dist, index = tree.query(queries[todo], k=k_eff, workers=thread_count())
        dist, index = dist.reshape(len(todo), -1), index.reshape(len(todo), -1)
        ok = allowed(todo, index)
        found = ok.any(axis=1)
        first = ok.argmax(axis=1)
        distance[todo[found]] = dist[found, first[found]]
        found_index[todo[found]] = index[found, first[found]]
        todo = todo[~found]
        if k_eff == count:
            break
    return distance, found_index
