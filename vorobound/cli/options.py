"""Options shared by the commands, and parsing of the values users type.

Every message that names a command-line flag lives in ``cli/``; the library below speaks of
parameters by name only.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated

import typer

from ..api.result import FigureFormat, TableFormat
from ..bounds.params import Mode, Target, TightMethod
from ..checks import parse_values  # noqa: F401  (the CLI parses with it)
from ..constants import PAPER_DELTA_RATIO, PAPER_RHO_F, PAPER_SIGMA
from ..errors import InputError
from ..sampling.guides.engines import Engine

# The choices are the library's own enums (numpy-free modules: `vorobound --help` loads them);
# the old names stay for code that imports them.
ModeChoice = Mode
MethodChoice = TightMethod
TargetChoice = Target
EngineChoice = Engine
TableChoice = TableFormat


TARGET_HELP = (
    "ratio: R ≤ ρ_f·R̂, eq. (54), the form of VoroCrust's Lemma 9; additive: R − R̂ ≤ "
    "(ρ_f − 1)·δ·L_i, the paper's target, which gives (55) R ≤ ρ_f·δ·L_i but not (54)."
)
TargetOpt = Annotated[TargetChoice, typer.Option("--target", help=TARGET_HELP)]
TargetsOpt = Annotated[
    str,
    typer.Option("--target", help="Comma list of targets: additive, ratio. " + TARGET_HELP),
]


def parse_targets(text: str) -> list[str]:
    """``--target`` as a comma list of additive, ratio (duplicates dropped, order kept)."""
    from ..bounds.params import checked_targets

    try:
        return [t.value for t in checked_targets(text)]
    except InputError:
        raise InputError(f"--target: expected additive or ratio, got {text!r}") from None


ModesOpt = Annotated[
    str,
    typer.Option("--mode", metavar="MODES", help="Comma list of modes: paper, rigorous, tight."),
]

TightMethodOpt = Annotated[
    MethodChoice,
    typer.Option(
        "--method",
        help="Tight mode: auto (the closed form where docs/tight.md proves it, else the "
        "optimizer) or optimize (always the numerical optimizer, the independent check).",
    ),
]

MODE_HELP = (
    "tight: the supremum over the constraint set (proven in closed form where docs/tight.md "
    "says so, else numerical); rigorous: the corrected chain, proven; paper: the printed chain "
    "(33)–(53), invalid (docs/errata.md E4), kept to reproduce the paper."
)

Eps = Annotated[float, typer.Option("--eps", metavar="EPS", help="Sampling density ε, 0 < ε < 1.")]
Sigma = Annotated[
    float, typer.Option("--sigma", metavar="SIGMA", help=f"Sparsity σ (paper: {PAPER_SIGMA:g}).")
]
DeltaRatio = Annotated[
    float,
    typer.Option(
        "--delta-ratio",
        metavar="RATIO",
        help=f"Ball radius over ε, δ/ε (paper: {PAPER_DELTA_RATIO:g}, δ = 2ε).",
    ),
]
Lfs = Annotated[
    float, typer.Option("--lfs", metavar="L", help="Local feature size L_i (paper: 1).")
]
RhoF = Annotated[
    float,
    typer.Option(
        "--rho-f",
        metavar="RHO_F",
        help=f"Quality constant ρ_f > 1 in R ≤ ρ_f δ L_i (paper: {PAPER_RHO_F:g}).",
    ),
]
ModeOpt = Annotated[ModeChoice, typer.Option("--mode", metavar="MODES", help=MODE_HELP)]
LAMBDA_HELP = "λ, the Lipschitz constant of L (|L(x) − L(y)| ≤ λ|x − y|): "
"""The start of every --lipschitz help: one λ, whatever the command does with it."""
Lipschitz = Annotated[
    float | None,
    typer.Option(
        "--lipschitz",
        metavar="LAMBDA",
        help=LAMBDA_HELP + "tight mode only, added to the constraint set between the "
        "vertices of every guide triangle (λ = 1: a local feature size; sizing fields often use "
        "0.1–0.3).",
    ),
]
SphereOpt = Annotated[
    float | None, typer.Option("--sphere", metavar="R", help="Sphere of radius R (L = R).")
]
TorusOpt = Annotated[
    str | None,
    typer.Option(
        "--torus",
        metavar="R,r[,AXIS]",
        help="Ring torus, radii R > r (L = min(r, ρ)), about the z axis or AXIS (x, y or z; "
        "measuring only: sampling is about z). Any other placement: --mesh.",
    ),
]
MeshOpt = Annotated[
    Path | None,
    typer.Option(
        "--mesh",
        metavar="FILE",
        help="Triangle mesh (any format meshio reads); L from --lfs, --sizing, or else "
        "estimated from the mesh as by `vorobound lfs` (sharp features sampled first).",
    ),
]
MeshLfsOpt = Annotated[
    float | None,
    typer.Option("--lfs", metavar="L", help="Constant local feature size L of the mesh."),
]
SizingOpt = Annotated[
    Path | None,
    typer.Option(
        "--sizing", metavar="FILE", help="CSV with the local feature size L per mesh vertex."
    ),
]


Out = Annotated[
    Path,
    typer.Option(
        "--out",
        metavar="DIR",
        help="Folder to write the figures into (default: ./vorobound-figures, created).",
    ),
]
NoTight = Annotated[
    bool,
    typer.Option(
        "--no-tight", metavar="", help="Skip the tight mode (its optimizations take time)."
    ),
]


@dataclass(frozen=True)
class SurfaceOptions:
    """The surface as the command line gives it (one of sphere, torus, mesh; L for a mesh):
    declared once here, a command takes it as one parameter (:func:`~vorobound.cli.command.
    grouped` spells out its options) and :func:`surface_args` turns it into the API's."""

    sphere: SphereOpt = None
    torus: TorusOpt = None
    mesh: MeshOpt = None
    lfs: MeshLfsOpt = None
    sizing: SizingOpt = None


AreaLfsOpt = Annotated[
    float | None,
    typer.Option("--lfs", metavar="L", help="Constant local feature size L (of --area or --mesh)."),
]


@dataclass(frozen=True)
class CountedSurfaceOptions(SurfaceOptions):
    """The surface whose samples the advisor counts: as :class:`SurfaceOptions`, and ``lfs``
    also goes with ``--area``."""

    lfs: AreaLfsOpt = None


@dataclass(frozen=True)
class QualityOptions:
    """σ, δ/ε, L_i and ρ_f with the paper's defaults (the ε-free quality parameters)."""

    sigma: Sigma = PAPER_SIGMA
    delta_ratio: DeltaRatio = PAPER_DELTA_RATIO
    lfs: Lfs = 1.0
    rho_f: RhoF = PAPER_RHO_F


@dataclass(frozen=True)
class BoundOptions(QualityOptions):
    """The quality parameters and the question asked of a bound: mode, target, λ, method."""

    mode: ModeOpt = Mode.tight
    target: TargetOpt = Target.ratio
    lipschitz: Lipschitz = None
    method: TightMethodOpt = TightMethod.auto


SURFACE_OPTIONS = "--sphere R, --torus R,r or --mesh FILE"
"""The ways to give a surface, as every message that asks for one names them."""


def surface_args(
    sphere=None, torus=None, mesh=None, lfs=None, sizing=None, *, instead: dict | None = None
) -> dict:
    """The surface options as the API's keyword arguments (``--torus R,r`` parsed).

    ``instead`` maps the options that may replace a surface (``{"--balls FILE": value}``) to
    their values: when neither a surface nor any of them is given, the one-line error names
    every alternative.
    """
    if instead is not None and all(v is None for v in (sphere, torus, mesh, *instead.values())):
        raise InputError(f"give a surface ({SURFACE_OPTIONS}) or " + " or ".join(instead))
    return {
        "sphere": sphere,
        "torus": None if torus is None else parse_torus(torus),
        "mesh": mesh,
        "lfs": lfs,
        "sizing": sizing,
    }


EngineOpt = Annotated[
    EngineChoice,
    typer.Option(
        "--engine",
        help="Candidate triples: geogram (regular triangulation, geogram's, compiled with "
        "vorobound, exact), gudhi (regular triangulation, CGAL), hull (equal radii on a "
        "sphere), brute (all overlapping triples; small inputs), auto (hull for a sphere, else "
        "geogram if built, else gudhi if installed, else brute).",
    ),
]


FigureFormatOpt = Annotated[
    FigureFormat, typer.Option("--figure-format", help="File format of the figures.")
]


Json = Annotated[
    bool, typer.Option("--json", metavar="", help="Print one JSON object (for programs).")
]
Seed = Annotated[
    int, typer.Option("--seed", metavar="SEED", help="Random seed, 0 ≤ seed < 2⁶³ (deterministic).")
]


def parse_modes(text: str) -> list[str]:
    """``--mode`` as a comma list of paper, rigorous, tight (duplicates dropped, order kept)."""
    from ..bounds.params import checked_modes

    try:
        return [m.value for m in checked_modes(text)]
    except InputError:
        raise InputError(f"--mode: expected paper, rigorous or tight, got {text!r}") from None


def parse_torus(text: str) -> list:
    """``R,r`` or ``R,r,AXIS`` (AXIS x, y or z: the torus's axis; default z)."""
    parts = [p.strip() for p in text.split(",")]
    if len(parts) == 3 and parts[2].lower() in ("x", "y", "z"):
        return [*parse_numbers(",".join(parts[:2]), "--torus", 2), parts[2].lower()]
    if len(parts) != 2:
        raise InputError(
            "--torus needs 2 comma-separated numbers R,r or R,r,AXIS (AXIS x, y or z), "
            f"got {text!r}"
        )
    return parse_numbers(text, "--torus", 2)


def parse_numbers(text: str, what: str, count: int | Sequence[int]) -> list[float]:
    """Parse ``"x,y[,z]"`` into finite floats, checking how many there are."""
    parts = [p.strip() for p in text.split(",")]
    allowed = (count,) if isinstance(count, int) else tuple(count)
    if len(parts) not in allowed:
        want = " or ".join(str(c) for c in allowed)
        raise InputError(f"{what} needs {want} comma-separated numbers, got {text!r}")
    values = []
    for part in parts:
        try:
            value = float(part)
        except ValueError:
            raise InputError(f"{what}: {part!r} is not a number") from None
        if not math.isfinite(value):
            raise InputError(f"{what}: {part!r} is not a finite number")
        values.append(value)
    return values
