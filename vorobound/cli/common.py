"""Options shared by the bound commands, and the parameter object they build."""

from __future__ import annotations

from enum import Enum
from typing import Annotated

import typer

from ..bounds.params import SamplingParams


class ModeChoice(str, Enum):
    paper = "paper"
    rigorous = "rigorous"
    tight = "tight"


Eps = Annotated[float, typer.Option("--eps", help="Sampling density ε, 0 < ε < 1.")]
Sigma = Annotated[float, typer.Option("--sigma", help="Sparsity σ (paper: 0.75).")]
DeltaRatio = Annotated[
    float, typer.Option("--delta-ratio", help="Ball radius over ε, δ/ε (paper: 2, δ = 2ε).")
]
Lfs = Annotated[float, typer.Option("--lfs", help="Local feature size L_i (paper: 1).")]
RhoF = Annotated[
    float, typer.Option("--rho-f", help="Quality constant ρ_f > 1 in R ≤ ρ_f δ L_i (paper: 1.38).")
]
ModeOpt = Annotated[
    ModeChoice,
    typer.Option(
        "--mode",
        help="paper: the printed chain (33)–(53); rigorous: the corrected chain; "
        "tight: the exact supremum over feasible guide triangles.",
    ),
]
Lipschitz = Annotated[
    float | None,
    typer.Option(
        "--lipschitz",
        help="Tight mode only: add |L_x − L_y| ≤ λ|p_x − p_y| for each pair (λ = 1: local "
        "feature size; sizing fields often use 0.1–0.3).",
    ),
]
Json = Annotated[bool, typer.Option("--json", help="Print one JSON object.")]


def make_params(eps: float, sigma: float, delta_ratio: float, lfs: float, rho_f: float):
    return SamplingParams(eps, sigma, delta_ratio, lfs, rho_f)


def params_dict(params: SamplingParams) -> dict:
    return {
        "eps": params.eps,
        "sigma": params.sigma,
        "delta_ratio": params.delta_ratio,
        "lfs": params.lfs,
        "rho_f": params.rho_f,
    }
