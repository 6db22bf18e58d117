"""Reading a run of Sandia's VoroCrust mesher (``vc_mesh -vc vc.in``) and writing its input deck.

The deck ``vc.in`` is read as ``vc_mesh`` reads it (``MeshingVoroCrust::execute`` in
github.com/sandialabs/vorocrust-meshing, commit b5e0859): each line is split at whitespace,
the first token is the key, the *third* the value (so ``KEY = VALUE`` needs the spaces around
``=``; ``KEY=VALUE`` is one token, a key the tool does not know, and is ignored). Keys the
tool reads, with its defaults:

========================== ======================================================
``INPUT_MESH_FILE``        an OBJ surface (may repeat: the tool merges them)
``SIZING_FILE``            CSV ``x, y, z, size`` after a header line: the radius cap at the
                           nearest of its points
``R_MIN``                  0 (0: a "clean" input; > 0 also welds features closer than it)
``R_MAX``                  no cap (DBL_MAX)
``LIP_CONST``              0.1: r_new ≤ r_old + LIP_CONST·|p_new − p_old| for overlapping balls
``VC_ANGLE``               20 degrees: dihedral angle that makes an edge sharp
``NUM_THREADS``            1
``SEEDS_FILE``             with ``GENERATE_MESH_FROM_SEEDS``: mesh given seeds
flag keys                  ``GENERATE_VCG_FILE``, ``GENERATE_EXODUS_FILE``,
                           ``GENERATE_MONITORING_POINTS``, ``IMPOSE_MONITORING_POINTS``,
                           ``GENERATE_MESH_FROM_SEEDS``: set by their presence, whatever the value
========================== ======================================================

Every other key is ignored by the tool, among them ``NUM_LOOP_REF`` and ``REF_ANGLE``, which its
own test decks set (the code declares the variables but never reads them). A value that is not
a number reads as 0 there; here it is refused.

A run writes, in the folder it was started from: ``corner_spheres.csv``, ``edges_spheres.csv``
and ``surface_spheres.csv`` (header ``x1coord, x2coord, x3coord, x4coord, n1, n2, n3, attrib1,
attrib2``: centre, radius, a zero normal, the attribute count and the corner, edge or face
index), ``seeds.csv`` (x, y, z, sizing, region; the header names only the first four) and,
when it makes them, ``interior_spheres.csv`` (x, y, z, radius). A stratum with no balls writes
no file.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...errors import InputError, ReadError
from ..balls import Balls, checked_rows

DECK = "vc.in"
"""The deck's usual name (``vc_mesh -vc FILE`` takes any)."""
NUMERIC_KEYS = {
    "R_MIN": 0.0,
    "R_MAX": math.inf,
    "LIP_CONST": 0.1,
    "VC_ANGLE": 20.0,
    "NUM_THREADS": 1.0,
}
"""Numeric keys vc_mesh reads, with its defaults (R_MAX: DBL_MAX, no cap)."""
PATH_KEYS = ("INPUT_MESH_FILE", "SIZING_FILE", "SEEDS_FILE")
FLAG_KEYS = (
    "GENERATE_VCG_FILE",
    "GENERATE_EXODUS_FILE",
    "GENERATE_MONITORING_POINTS",
    "IMPOSE_MONITORING_POINTS",
    "GENERATE_MESH_FROM_SEEDS",
)
STRATA_FILES = {
    "corner": "corner_spheres.csv",
    "edge": "edges_spheres.csv",
    "surface": "surface_spheres.csv",
    "interior": "interior_spheres.csv",
}
"""The ball files of a run, by stratum (file names as vc_mesh writes them)."""
SEEDS_FILE = "seeds.csv"


@dataclass(frozen=True)
class Deck:
    """A ``vc.in`` as vc_mesh reads it."""

    path: Path
    values: dict[str, float]
    """Every numeric key, given or defaulted (:data:`NUMERIC_KEYS`)."""
    given: tuple[str, ...]
    """The numeric keys the deck sets."""
    input_meshes: tuple[str, ...]
    sizing_file: str | None
    flags: tuple[str, ...]
    ignored: tuple[str, ...]
    """Keys in the deck that vc_mesh ignores (in order, once each)."""

    def resolve(self, name: str) -> Path:
        """A file the deck names, relative to the deck's folder (vc_mesh opens it relative to
        the folder it runs in, which for a run directory is the deck's)."""
        path = Path(name)
        return path if path.is_absolute() else self.path.parent / path


def read_deck(path: str | os.PathLike) -> Deck:
    """Parse a VoroCrust deck as vc_mesh does (module docstring).

    Raises
    ------
    ReadError
        Missing or unreadable file, a known key without a value (vc_mesh reads past the end of
        the line), a numeric key whose value is not a number, no INPUT_MESH_FILE.
    """
    path = Path(path)
    if not path.is_file():
        reason = "no such file" if not path.exists() else "not a regular file"
        raise ReadError(f"cannot read VoroCrust deck {path}: {reason}")
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise ReadError(f"cannot read VoroCrust deck {path}: {exc}") from None
    values, given, meshes, flags, ignored = dict(NUMERIC_KEYS), [], [], [], []
    sizing = None
    for number, line in enumerate(text.splitlines(), start=1):
        tokens = line.split()
        if not tokens:
            continue
        key = tokens[0]
        known = key in NUMERIC_KEYS or key in PATH_KEYS
        if key in FLAG_KEYS:
            flags.append(key)
            continue
        if not known:
            if key not in ignored:
                ignored.append(key)
            continue
        if len(tokens) < 3:
            raise ReadError(
                f"VoroCrust deck {path}, line {number}: {key} needs 'KEY = VALUE' (vc_mesh "
                "reads the third word)"
            )
        value = tokens[2]
        if key == "INPUT_MESH_FILE":
            meshes.append(value)
        elif key == "SIZING_FILE":
            sizing = value
        elif key in NUMERIC_KEYS:
            try:
                number_value = float(value)
            except ValueError:
                raise ReadError(
                    f"VoroCrust deck {path}, line {number}: {key} = {value!r} is not a number "
                    "(vc_mesh would read 0)"
                ) from None
            if not math.isfinite(number_value):
                raise ReadError(f"VoroCrust deck {path}, line {number}: {key} is not finite")
            values[key] = number_value
            given.append(key)
    if not meshes and "GENERATE_MESH_FROM_SEEDS" not in flags:
        raise ReadError(f"VoroCrust deck {path} names no INPUT_MESH_FILE")
    return Deck(path, values, tuple(given), tuple(meshes), sizing, tuple(flags), tuple(ignored))


def deck_text(
    *,
    input_mesh: str,
    sizing_file: str | None,
    r_max: float,
    lip_const: float,
    vc_angle: float,
    num_threads: int = 1,
    comments: tuple[str, ...] = (),
) -> str:
    """A deck vc_mesh reads: ``KEY = VALUE`` lines (``comments`` as ``#`` lines, which it
    ignores). File names must be one word each (vc_mesh reads one token)."""
    for name in (sizing_file, input_mesh):
        if name is not None and len(name.split()) != 1:
            raise InputError(f"vc_mesh reads one word per value: {name!r} has spaces")
    lines = [f"# {c}" for c in comments]
    lines.append(f"INPUT_MESH_FILE = {input_mesh}")
    if sizing_file is not None:
        lines.append(f"SIZING_FILE = {sizing_file}")
    lines += [
        f"R_MAX = {r_max!r}",
        f"LIP_CONST = {lip_const!r}",
        f"VC_ANGLE = {vc_angle!r}",
        f"NUM_THREADS = {int(num_threads)}",
    ]
    return "\n".join(lines) + "\n"


def obj_writer(points: np.ndarray, triangles: np.ndarray):
    """A writer of a triangle mesh as OBJ (the only input vc_mesh reads)."""

    def write(temp: Path) -> None:
        with open(temp, "w", encoding="utf-8") as handle:
            np.savetxt(handle, points, fmt="v %.17g %.17g %.17g")
            np.savetxt(handle, np.asarray(triangles) + 1, fmt="f %d %d %d")

    return write


def sizing_writer(points: np.ndarray, sizes: np.ndarray):
    """A writer (taking the temporary path) of a vc_mesh sizing file: a header line and
    ``x, y, z, size`` rows at full precision (vc_mesh caps a ball's radius by the size of the
    nearest row)."""

    def write(temp: Path) -> None:
        with open(temp, "w", encoding="utf-8") as handle:
            handle.write("x, y, z, size\n")
            np.savetxt(handle, np.column_stack([points, sizes]), fmt="%.17g", delimiter=", ")

    return write


@dataclass(frozen=True)
class Run:
    """A VoroCrust run directory: its deck, the balls of each stratum and the seeds file."""

    folder: Path
    deck: Deck
    strata: dict[str, Balls | None]
    """Balls per stratum (corner, edge, surface, interior); None where the run wrote none."""
    stratum_index: dict[str, np.ndarray] = field(default_factory=dict)
    """Per stratum, vc_mesh's attribute column (corner, edge or face index), where present."""
    seeds: Path | None = None
    """seeds.csv, if the run wrote it."""

    @property
    def mesh(self) -> Path:
        """The input mesh (one: several are refused by :func:`read_run`)."""
        return self.deck.resolve(self.deck.input_meshes[0])

    def counts(self) -> dict[str, int]:
        """Balls per stratum (0 where none), and the seeds."""
        return {name: 0 if b is None else len(b) for name, b in self.strata.items()}


def read_run(folder: str | os.PathLike, deck: str = DECK) -> Run:
    """Read a VoroCrust run: ``folder/vc.in``, the balls of each stratum and seeds.csv.

    Raises
    ------
    ReadError
        No deck, a deck naming several input meshes (merge them into one file first), no ball
        file at all, or an unreadable ball file.
    """
    folder = Path(folder)
    if not folder.is_dir():
        reason = "no such folder" if not folder.exists() else "not a folder"
        raise ReadError(f"cannot read VoroCrust run {folder}: {reason}")
    parsed = read_deck(folder / deck)
    if len(parsed.input_meshes) > 1:
        raise ReadError(
            f"VoroCrust deck {parsed.path} names {len(parsed.input_meshes)} input meshes: vc_mesh "
            "merges them (model_combined.obj in the run folder); give that one to --mesh"
        )
    strata: dict[str, Balls | None] = {}
    index: dict[str, np.ndarray] = {}
    for name, file in STRATA_FILES.items():
        path = folder / file
        if not path.is_file():
            if path.exists():
                raise ReadError(f"VoroCrust run {folder}: {file} is not a regular file")
            strata[name] = None
            continue
        centers, radii, attrib = read_sphere_file(path)
        centers, radii = checked_rows(centers, radii, f"{name} balls {file}")
        strata[name] = Balls(centers, radii)
        if attrib is not None:
            index[name] = attrib
    if all(b is None for b in strata.values()):
        raise ReadError(
            f"VoroCrust run {folder}: no ball file ({', '.join(STRATA_FILES.values())}); "
            "vc_mesh writes them into the folder it runs in"
        )
    seeds = folder / SEEDS_FILE
    return Run(folder, parsed, strata, index, seeds if seeds.is_file() else None)


def read_sphere_file(path: str | os.PathLike):
    """Centres (n, 3), radii (n,) and the attribute column (n,) or None of a vc_mesh sphere
    file (``corner_spheres.csv`` etc.; ``interior_spheres.csv`` has x, y, z, radius)."""
    from .tables import read_number_table

    table = read_number_table(path, "VoroCrust spheres")
    values = table.values
    if values.ndim != 2 or values.shape[1] < 4:
        raise ReadError(f"VoroCrust spheres {path}: need x, y, z and r in the first 4 columns")
    attrib = values[:, 8] if values.shape[1] >= 9 else None
    return values[:, :3], values[:, 3], attrib
