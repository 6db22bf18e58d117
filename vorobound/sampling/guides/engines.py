"""The engines that find guide triangles, by name (numpy-free: the command line derives its
``--engine`` choices from :class:`Engine` without loading the engines)."""

from __future__ import annotations

from enum import Enum


class Engine(str, Enum):
    """Where candidate triples come from."""

    auto = "auto"
    geogram = "geogram"
    gudhi = "gudhi"
    hull = "hull"
    brute = "brute"
