"""Parameter sweeps: ε* tables over σ, ρ_f, δ/ε, λ, mode and target, or bound curves over ε.

Rows stream out in a fixed nested-loop order (mode, target, λ, σ, ρ_f, δ/ε[, ε]) and are
computed in
chunks, so memory stays bounded whatever the grid size: the chain modes evaluate
``CHUNK_ROWS`` rows at a time (each row costs about ``BYTES_PER_CHAIN_ROW`` while its chunk is
being solved), and the tight rows run one at a time per worker process. A grid is sized by
arithmetic on its axes before anything is built.

A row has an empty result only when its parameters admit no ε* (:class:`NoAdmissibleEps`);
the row's ``note`` says why. Any other error stops the sweep.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

from ..bounds.chain import chain_arrays
from ..bounds.claims import CHAIN_CLAIM
from ..bounds.eps_star import STATUS_OK, STATUS_REASONS, solve_eps_star_batch
from ..bounds.params import Mode, QualityParams, Target
from ..bounds.tight.method import checked_method
from ..checks import (
    DELTA_RATIO_RANGE,
    EPS_RANGE,
    RHO_F_MAX,
    SIGMA_RANGE,
    checked_lipschitz,
    checked_number,
)
from ..errors import EmptyConstraintSet, InputError, NoAdmissibleEps, VoroboundError
from ..progress import Counter, Progress
from ..rounding import DOWN, UP

MAX_GRID_ROWS = 100_000_000
"""Largest grid a sweep accepts (rows stream out, so this limits time, not memory)."""
CHUNK_ROWS = 2048
"""Chain-mode rows solved together; memory ≈ CHUNK_ROWS × BYTES_PER_CHAIN_ROW."""
BYTES_PER_CHAIN_ROW = 40 * 200 * 8
"""About 40 arrays of the 200-point ε scan of :func:`solve_eps_star_batch`, per row."""
TIGHT_SECONDS_PER_ROW = {"eps_star": 4.0, "bound": 1.0}
"""Measured upper estimates of one optimizer row (ε* and one supremum) on one core; rows the
closed form answers take well under a millisecond."""
ESTIMATE_SAMPLE = 200
"""Tight rows examined (evenly spread) to estimate the share that needs the optimizer."""
MAX_TIGHT_SECONDS = 600.0
"""Tight grids estimated to take longer are refused unless the caller allows them."""


@dataclass(frozen=True)
class SweepRow:
    """One row of a sweep (``eps``/``bound``/``limit`` for bound curves, else ``eps_star``)."""

    mode: str
    target: str
    """additive (R − R̂ ≤ (ρ_f − 1)δL_i) or ratio (R ≤ ρ_f·R̂, eq. (54))."""
    lipschitz: float | None
    sigma: float
    rho_f: float
    delta_ratio: float
    eps: float | None = None
    bound: float | None = None
    """Bound curves: the bound on R − R̂ (additive) or on R/R̂ (ratio; empty where none)."""
    limit: float | None = None
    """Bound curves: (ρ_f − 1)δL_i, or ρ_f."""
    eps_star: float | None = None
    claim: str = ""
    """proven, numerical or invalid (:mod:`vorobound.bounds.claims`)."""
    note: str = ""
    """Why a result cell is empty (no admissible ε); empty otherwise."""


HEAD_COLUMNS = ("mode", "target", "lipschitz", "sigma", "rho_f", "delta_ratio")
EPS_STAR_COLUMNS = (*HEAD_COLUMNS, "eps_star")
CURVE_COLUMNS = (*HEAD_COLUMNS, "eps", "bound", "limit")
TRAILING_COLUMNS = ("claim", "note")
COLUMN_ROUNDING = {"eps_star": DOWN, "bound": UP}
"""How a table for people rounds each result column (:mod:`vorobound.rounding`): ε* down,
bounds up; the CSV and JSON rows keep every digit."""


AXIS_RANGES = {
    "sigma": (*SIGMA_RANGE, False),
    "rho_f": (1.0, RHO_F_MAX, True),
    "delta_ratio": (*DELTA_RATIO_RANGE, False),
}
"""The supported range of each swept parameter (those of :class:`QualityParams`)."""


def _unique(values) -> tuple:
    return tuple(dict.fromkeys(values))


@dataclass(frozen=True)
class SweepSpec:
    """The axes of a sweep; duplicates are dropped and every value is checked on creation."""

    sigma: tuple[float, ...]
    rho_f: tuple[float, ...]
    delta_ratio: tuple[float, ...]
    lipschitz: tuple[float | None, ...]
    modes: tuple[Mode, ...]
    eps: tuple[float, ...] | None = None
    lfs: float = 1.0
    method: str = "auto"
    """How tight rows are evaluated (:class:`vorobound.bounds.tight.method.TightMethod`)."""
    targets: tuple[Target, ...] = (Target.additive,)

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        set_(self, "modes", _unique(Mode(m) for m in self.modes))
        set_(self, "targets", _unique(Target(t) for t in self.targets))
        for name in ("sigma", "rho_f", "delta_ratio", "lipschitz", "modes", "targets"):
            if not getattr(self, name):
                raise InputError(f"the sweep's {name} axis is empty")
        for name, (low, high, open_low) in AXIS_RANGES.items():
            values = getattr(self, name)
            set_(
                self,
                name,
                _unique(checked_number(v, name, low, high, open_low=open_low) for v in values),
            )
        set_(self, "lipschitz", _unique(checked_lipschitz(lam) for lam in self.lipschitz))
        set_(self, "lfs", QualityParams(lfs=self.lfs).lfs)
        if self.eps is not None:
            if not self.eps:
                raise InputError("the sweep's eps axis is empty")
            set_(self, "eps", _unique(checked_number(e, "eps", *EPS_RANGE) for e in self.eps))
        if Mode.tight not in self.modes and self.lipschitz != (None,):
            raise InputError("a Lipschitz constant applies to the tight mode only")
        set_(self, "method", checked_method(self.method).value)

    @property
    def per_mode(self) -> int:
        """Rows per chain mode: |σ|·|ρ_f|·|δ/ε|·|ε|."""
        return len(self.sigma) * len(self.rho_f) * len(self.delta_ratio) * len(self.eps or (0,))

    @property
    def tight_rows(self) -> int:
        if Mode.tight not in self.modes:
            return 0
        return self.per_mode * len(self.lipschitz) * len(self.targets)

    @property
    def rows(self) -> int:
        """Rows of the whole sweep (arithmetic on the axis lengths; nothing is built)."""
        chains = sum(1 for m in self.modes if m is not Mode.tight)
        return chains * self.per_mode * len(self.targets) + self.tight_rows

    @property
    def columns(self) -> tuple[str, ...]:
        return (CURVE_COLUMNS if self.eps is not None else EPS_STAR_COLUMNS) + TRAILING_COLUMNS

    def estimated_tight_seconds(self, workers: int) -> float:
        """Estimated wall time of the tight rows on ``workers`` processes.

        Only rows the optimizer must answer count: with ``method="auto"``, the share of rows
        whose closed form is not proven exact, measured on up to ``ESTIMATE_SAMPLE`` rows.
        """
        if not self.tight_rows:
            return 0.0
        per_row = TIGHT_SECONDS_PER_ROW["bound" if self.eps is not None else "eps_star"]
        share = 1.0 if self.method == "optimize" else _optimizer_share(self)
        return self.tight_rows * share * per_row / max(workers, 1)


def _optimizer_share(spec: SweepSpec) -> float:
    """Share of a sample of tight rows that the closed form does not answer exactly."""
    import itertools

    from ..bounds.tight.closed_form import closed_form_is_exact, tight_eps_star_closed_form
    from ..bounds.tight.ratio_form import ratio_eps_star_closed_form

    step = max(1, spec.tight_rows // ESTIMATE_SAMPLE)
    tasks = list(itertools.islice(_tight_tasks(spec), 0, None, step))
    slow = 0
    for eps, lam, sigma, rho_f, ratio, _, _, target in tasks:
        try:
            if eps is not None:
                exact = closed_form_is_exact(eps, sigma, ratio, lam)
            elif target is Target.ratio:
                exact = ratio_eps_star_closed_form(sigma, ratio, rho_f, lam).status.name == "exact"
            else:
                exact = tight_eps_star_closed_form(sigma, ratio, rho_f, lam).status.name == "exact"
        except VoroboundError:
            exact = True  # answered at once (an empty cell or an error)
        slow += not exact
    return slow / len(tasks)


def check_size(
    spec: SweepSpec, workers: int, max_rows: int = MAX_GRID_ROWS, allow_long: bool = False
) -> None:
    """Refuse a grid with more than ``max_rows`` rows, or tight rows estimated to take longer
    than ``MAX_TIGHT_SECONDS`` unless ``allow_long``."""
    if spec.rows > max_rows:
        raise InputError(f"the sweep has {spec.rows:,} rows; at most {max_rows:,} are allowed")
    seconds = spec.estimated_tight_seconds(workers)
    if seconds > MAX_TIGHT_SECONDS and not allow_long:
        raise InputError(
            f"the {spec.tight_rows:,} tight rows would take about {_duration(seconds)} on "
            f"{workers} process(es); allow it explicitly or use a smaller grid"
        )


def _duration(seconds: float) -> str:
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


def iter_sweep(
    spec: SweepSpec, jobs: int = 1, progress: Progress | None = None
) -> Iterator[SweepRow]:
    """The sweep's rows in order, computed chunk by chunk (see the module docstring).

    Tight rows run on ``jobs`` worker processes (capped by the rows and the CPUs); ``progress``
    is told of each finished tight row.
    """
    for mode in spec.modes:
        if mode is Mode.tight:
            yield from _tight_rows(spec, jobs, progress)
        else:
            for target in spec.targets:
                yield from _chain_rows(spec, mode, target)


def _chain_rows(spec: SweepSpec, mode: Mode, target: Target) -> Iterator[SweepRow]:
    axes = [np.asarray(spec.sigma), np.asarray(spec.rho_f), np.asarray(spec.delta_ratio)]
    if spec.eps is not None:
        axes.append(np.asarray(spec.eps))
    shape = tuple(len(a) for a in axes)
    total = math.prod(shape)
    claim = CHAIN_CLAIM[mode.value]

    def row(sigma, rho_f, ratio, **found) -> SweepRow:
        """A row of this mode and target (no λ: the chain has none)."""
        values = (float(sigma), float(rho_f), float(ratio))
        return SweepRow(mode.value, target.value, None, *values, claim=claim, **found)

    for start in range(0, total, CHUNK_ROWS):
        index = np.unravel_index(np.arange(start, min(start + CHUNK_ROWS, total)), shape)
        sigma, rho_f, ratio = (axis[i] for axis, i in zip(axes[:3], index[:3], strict=True))
        if spec.eps is None:
            stars, status = solve_eps_star_batch(sigma, ratio, rho_f, mode, target=target)
            for s, q, r, star, code in zip(sigma, rho_f, ratio, stars, status, strict=True):
                ok = code == STATUS_OK
                note = "" if ok else STATUS_REASONS[int(code)]
                yield row(s, q, r, eps_star=float(star) if ok else None, note=note)
        else:
            eps = axes[3][index[3]]
            with np.errstate(invalid="ignore"):
                chain = chain_arrays(eps, sigma, ratio, spec.lfs, rho_f, mode)
            if target is Target.ratio:
                bounds, limits = chain.ratio_bound, np.broadcast_to(rho_f, eps.shape)
            else:
                bounds, limits = chain.bound, chain.gap_allowance
            for s, q, r, e, b, t in zip(sigma, rho_f, ratio, eps, bounds, limits, strict=True):
                defined = bool(np.isfinite(b))
                if defined:
                    note = ""
                elif np.isnan(b):
                    note = "the chain is not defined at this eps"
                else:
                    note = "no finite bound on R/R^: the bound on (R - R^)/R reaches 1"
                bound = float(b) if defined else None
                yield row(s, q, r, eps=float(e), bound=bound, limit=float(t), note=note)


def _tight_tasks(spec: SweepSpec) -> Iterator[tuple]:
    for target in spec.targets:
        for lam in spec.lipschitz:
            for sigma in spec.sigma:
                for rho_f in spec.rho_f:
                    for ratio in spec.delta_ratio:
                        for eps in spec.eps if spec.eps is not None else (None,):
                            yield (eps, lam, sigma, rho_f, ratio, spec.lfs, spec.method, target)


def tight_row(task: tuple) -> SweepRow:
    """One tight row (module level, so worker processes can run it)."""
    from ..bounds.guarantee import bound_at, eps_star

    eps, lam, sigma, rho_f, ratio, lfs, method, target = task
    quality = QualityParams(sigma, ratio, rho_f, lfs, lipschitz=lam, target=target)
    head = ("tight", quality.target.value, lam, sigma, rho_f, ratio)
    if eps is not None:
        params = quality.at(eps)
        try:
            bound = bound_at(params, Mode.tight, method)
        except EmptyConstraintSet as exc:  # every bound is vacuous at this ε
            return SweepRow(*head, eps=eps, limit=params.limit, note=str(exc))
        finite = math.isfinite(bound.value)
        note = "" if finite else "no finite bound on R/R^: R^ can reach 0"
        return SweepRow(
            *head,
            eps=eps,
            bound=bound.value if finite else None,
            limit=params.limit,
            claim=bound.claim,
            note=note,
        )
    try:
        star = eps_star(quality, Mode.tight, method)
    except NoAdmissibleEps as exc:
        return SweepRow(*head, note=str(exc))
    return SweepRow(*head, eps_star=star.eps_star, claim=star.claim)


def _tight_rows(spec: SweepSpec, jobs: int, progress: Progress | None) -> Iterator[SweepRow]:
    from ..parallel import process_pool, usable_workers

    counter = Counter(progress, "tight rows", spec.tight_rows)
    workers = usable_workers(jobs, spec.tight_rows)
    if workers == 1:
        for task in _tight_tasks(spec):
            row = tight_row(task)
            counter.step()
            yield row
        return
    with process_pool(workers) as pool:
        for row in pool.imap(tight_row, _tight_tasks(spec)):
            counter.step()
            yield row
