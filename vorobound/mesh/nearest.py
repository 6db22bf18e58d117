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
    pairs: int | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Distance to and index of the nearest point of ``tree`` (a scipy k-d tree) that
    ``allowed`` accepts, for each of ``queries`` (m, 3).

    ``allowed(rows, index)`` gets the query rows still searching (r,) and the indices of
    their k nearest points (r, k), nearest first, and says which of those points each query
    accepts (r, k) bool. The k nearest are tried for each k of ``neighbours`` in turn, the
    next k only for the queries that found none; the search ends early once k covers every
    point. Distance inf and index −1 where no point was accepted.

    ``pairs`` bounds the memory: the queries of one k are then searched in chunks of at most
    ``pairs // k`` (each query's answer is its own, so chunks change no result).
    """
    count = int(tree.n)
    distance = np.full(len(queries), np.inf)
    found_index = np.full(len(queries), -1, dtype=np.int64)
    todo = np.arange(len(queries))
    for k in neighbours:
        if not len(todo) or count == 0:
            break
        k_eff = min(k, count)
        step = len(todo) if pairs is None else max(1, pairs // k_eff)
        left = []
        for start in range(0, len(todo), step):
            rows = todo[start : start + step]
            dist, index = tree.query(queries[rows], k=k_eff, workers=thread_count())
            dist, index = dist.reshape(len(rows), -1), index.reshape(len(rows), -1)
            ok = allowed(rows, index)
            found = ok.any(axis=1)
            first = ok.argmax(axis=1)
            distance[rows[found]] = dist[found, first[found]]
            found_index[rows[found]] = index[found, first[found]]
            left.append(rows[~found])
        todo = np.concatenate(left) if left else todo
        if k_eff == count:
            break
    return distance, found_index
