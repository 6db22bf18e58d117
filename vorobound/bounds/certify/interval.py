"""Outward-rounded enclosures of R − R̂ over boxes of guide triangles (python-flint ``arb``).

A box is a product of closed intervals with exact rational ends (``fmpq``) in the coordinates

    (ε, b/(εL_i), c/(εL_i), cos θ, (L_j/L_i − 1)/ε, (L_k/L_i − 1)/ε),

the units of :class:`vorobound.bounds.constraints.ScaledConfiguration`, in which no quantity
divides by ε, so ε is a box coordinate down to 0. Every interval operation is ``arb`` ball
arithmetic, rounded outward, so an enclosure contains the exact value at every point of the box.

The quantity bounded is the target's fraction: (R − R̂)/((ρ_f − 1)δL_i) for the additive
target (eq. (55)), or ((R − R̂)/R)/(1 − 1/ρ_f) for the ratio target R ≤ ρ_f·R̂ (eq. (54)); either
is ≤ 1 exactly where its target holds. The enclosures, each a valid upper bound at every
feasible point of a box (docs/tight.md, "Certificates"):

* ``circumradius`` (additive only): R − R̂ ≤ R ≤ ε/(1−ε)·L_i (R̂ ≥ 0 and H3);
* ``chord``: (R − R̂)/R = (a − â)/a ≤ |d|/a with d the shift of the chord BC (Theorem 1 via
  E2), times R for the additive target;
* ``exact``: Theorem 1 itself, a − â = (2 a⃗·d − |d|²)/(a + â), free of cancellation.

References
----------
Theorem 1 (eq. (16), (25)–(29)), eq. (33)–(37), (55), property H3.
"""

from __future__ import annotations

import contextlib
from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction

from flint import arb, ctx, fmpq

from .. import constraints
from ..params import Target

PRECISION_BITS = 64
"""Working precision of the ball arithmetic (recorded in certificates)."""
DIMENSIONS = ("eps", "edge_b", "edge_c", "cos_theta", "excess_j", "excess_k")
"""Box coordinates, in this order (see the module docstring)."""
EPS, EDGE_B, EDGE_C, COS_THETA, EXCESS_J, EXCESS_K = range(6)
ENCLOSURES = ("circumradius", "chord", "exact")
"""Names of the upper enclosures of the additive target's fraction, in the order tried."""
RATIO_ENCLOSURES = ("chord", "exact")
"""Names of the enclosures of the ratio target's fraction (R − R̂ ≤ R says nothing there)."""
TARGETS = tuple(target.value for target in Target)
"""The targets a certificate can be about (:mod:`vorobound.bounds.targets`)."""


def enclosure_names(target: str) -> tuple[str, ...]:
    """The enclosures that are valid for ``target``."""
    return RATIO_ENCLOSURES if target == "ratio" else ENCLOSURES


Box = tuple[tuple[fmpq, fmpq], ...]
"""Closed intervals [lo, hi] with exact rational ends, one per coordinate of DIMENSIONS."""


class ArbBackend:
    """The ``xp`` of :mod:`vorobound.bounds.constraints` for ``arb`` balls."""

    @staticmethod
    def minimum(x, y):
        return arb.min(_ball(x), _ball(y))

    @staticmethod
    def absolute(x):
        return abs(_ball(x))


def _ball(x) -> arb:
    return x if isinstance(x, arb) else arb(x)


def exact_rational(value: float | int | Fraction) -> fmpq:
    """A float (exactly, every float is a dyadic rational) or a Fraction as ``fmpq``."""
    frac = Fraction(value)
    return fmpq(frac.numerator, frac.denominator)


def nearest_float(value: fmpq) -> float:
    """The float nearest to a rational (``float(fmpq)`` is missing from older python-flint)."""
    return float(Fraction(int(value.p), int(value.q)))


@dataclass(frozen=True)
class Setting:
    """What a certificate is about: the parameters and the largest ε, all exact rationals."""

    sigma: fmpq
    delta_ratio: fmpq
    rho_f: fmpq
    lipschitz: fmpq | None
    eps_max: fmpq
    target: str = "additive"
    """``"additive"`` (R − R̂ ≤ (ρ_f − 1)δL_i) or ``"ratio"`` (R ≤ ρ_f·R̂, eq. (54))."""

    @classmethod
    def of(cls, quality, eps_max: float) -> Setting:
        """From validated parameters (:class:`~vorobound.bounds.params.QualityParams`) and a
        float ε_max, each converted exactly."""
        lam = None if quality.lipschitz is None else exact_rational(quality.lipschitz)
        sigma, delta_ratio, rho_f = (
            exact_rational(v) for v in (quality.sigma, quality.delta_ratio, quality.rho_f)
        )
        return cls(sigma, delta_ratio, rho_f, lam, exact_rational(eps_max), quality.target.value)

    def scale(self) -> arb:
        """The target in the enclosures' units: ρ_f − 1, or 1 − 1/ρ_f for the ratio target."""
        rho_f = arb(self.rho_f)
        return 1 - 1 / rho_f if self.target == "ratio" else rho_f - 1

    def root_box(self) -> Box:
        """A box holding every feasible configuration at every ε in (0, ε_max].

        b/(εL_i), c/(εL_i) ∈ [σ, 2/(1−ε)] by (34)–(35); cos θ ∈ [−1, 1]; the excesses lie in
        [0, 2/(1−ε)] by (33) and, with λ, below λ·2/(1−ε) (L_j − L_i ≤ λc). 2/(1−ε) grows with
        ε, so its value at ε_max bounds it on the whole range.
        """
        edge_max = 2 / (1 - self.eps_max)
        excess_max = (
            edge_max if self.lipschitz is None else min(edge_max, self.lipschitz * edge_max)
        )
        zero, one = fmpq(0), fmpq(1)
        return (
            (zero, self.eps_max),
            (self.sigma, edge_max),
            (self.sigma, edge_max),
            (-one, one),
            (zero, excess_max),
            (zero, excess_max),
        )


def balls(box: Box) -> list[arb]:
    """One ``arb`` ball per coordinate, containing the exact interval [lo, hi]."""
    return [arb.union(arb(lo), arb(hi)) for lo, hi in box]


def split(box: Box, dim: int) -> tuple[Box, Box]:
    """The two halves of ``box`` at the exact midpoint of coordinate ``dim``."""
    lo, hi = box[dim]
    mid = (lo + hi) / 2
    left = box[:dim] + ((lo, mid),) + box[dim + 1 :]
    right = box[:dim] + ((mid, hi),) + box[dim + 1 :]
    return left, right


@dataclass(frozen=True)
class Scaled:
    """A box's coordinates as balls, with the derived a/(εL_i) and sin θ."""

    eps: arb
    edge_b: arb
    edge_c: arb
    cos_theta: arb
    excess_j: arb
    excess_k: arb
    edge_a: arb
    """a/(εL_i) = sqrt((b − c)² + 2bc(1 − cos θ)) over εL_i (law of cosines, no cancellation)."""
    sin_theta: arb
    """sqrt((1 − cos θ)(1 + cos θ))."""

    def configuration(self) -> constraints.ScaledConfiguration:
        return constraints.ScaledConfiguration(
            edge_b=self.edge_b,
            edge_c=self.edge_c,
            edge_a=self.edge_a,
            sin_theta=self.sin_theta,
            excess_j=self.excess_j,
            excess_k=self.excess_k,
        )


def scaled(values: Sequence[arb]) -> Scaled:
    """The derived quantities of a box (or point) given as balls in DIMENSIONS order."""
    eps, edge_b, edge_c, cos_theta, excess_j, excess_k = values
    # 1 ± cos θ and the sums of squares are ≥ 0 exactly; clamp the rounding below 0 away.
    one_minus = (1 - cos_theta).nonnegative_part()
    one_plus = (1 + cos_theta).nonnegative_part()
    diff = edge_b - edge_c
    a_sq = (diff * diff).nonnegative_part() + 2 * edge_b * edge_c * one_minus
    return Scaled(
        eps,
        edge_b,
        edge_c,
        cos_theta,
        excess_j,
        excess_k,
        edge_a=a_sq.nonnegative_part().sqrt(),
        sin_theta=(one_minus * one_plus).nonnegative_part().sqrt(),
    )


def violated_constraint(point: Scaled, setting: Setting) -> str | None:
    """Name of the first constraint that fails at every point of the box, or None.

    A constraint ``small ≤ large`` fails everywhere when the enclosure of ``large`` lies
    entirely below that of ``small``.
    """
    params, cfg = _params(point, setting), point.configuration()
    for constraint in constraints.active_constraints(params):
        small, large = _sides(constraint, cfg, params)
        if large < small:
            return constraint.name
    return None


def constraint_fails(name: str, point: Scaled, setting: Setting) -> bool:
    """True if the constraint ``name`` fails at every point of the box."""
    params = _params(point, setting)
    constraint = constraints.BY_NAME[name]
    if constraint not in constraints.active_constraints(params):
        return False
    small, large = _sides(constraint, point.configuration(), params)
    return bool(large < small)


def constraints_hold(point: Scaled, setting: Setting) -> bool:
    """True if every constraint holds at every point of the (point) box."""
    params, cfg = _params(point, setting), point.configuration()
    for constraint in constraints.active_constraints(params):
        small, large = _sides(constraint, cfg, params)
        if not small <= large:
            return False
    return True


def _sides(
    constraint: constraints.Constraint,
    cfg: constraints.ScaledConfiguration,
    params: constraints.ConstraintParams,
) -> tuple[arb, arb]:
    """Enclosures of the constraint's two sides ``small ≤ large``."""
    # constraints.Sides declares a module (numpy) as xp; ArbBackend has what the sides call
    small, large = constraint.sides(cfg, params, ArbBackend)  # type: ignore[arg-type]
    return _ball(small), _ball(large)


def _params(point: Scaled, setting: Setting) -> constraints.ConstraintParams:
    lam = None if setting.lipschitz is None else arb(setting.lipschitz)
    # ConstraintParams declares float fields; its constraints take any scalar of the backend
    return constraints.ConstraintParams(point.eps, arb(setting.sigma), lam)


def _cap(value: arb, *limits: arb) -> arb:
    """``value`` with its upper end lowered to the smallest upper end of ``limits``."""
    upper = value.upper()
    for limit in limits:
        upper = arb.min(upper, limit.upper())
    if upper < value.lower():
        return value  # cannot happen once no constraint fails everywhere; keep the box as is
    return arb.union(value.lower(), upper)


def _square(value: arb) -> arb:
    """x² of a ball of non-negative numbers from its ends (tighter than the ball product)."""
    lower, upper = value.lower(), value.upper()
    if lower < 0:
        return value * value
    return arb.union((lower * lower).lower(), (upper * upper).upper())


def _floor(value: arb, limit: arb) -> arb:
    """``value`` with its lower end raised to the lower end of ``limit``."""
    lower = arb.max(value.lower(), limit.lower())
    if lower > value.upper():
        return value
    return arb.union(lower, value.upper())


@dataclass(frozen=True)
class Weights:
    """The shifted weights of a box in scaled form (shared by the enclosures)."""

    excess_j: arb
    excess_k: arb
    edge_a: arb
    radius: arb
    """An enclosure of R/(εL_i) on the feasible part of the box (upper end from H3)."""
    g_j: arb
    """ℓ_j(2 + εℓ_j) = (L_j² − L_i²)/(εL_i²): w_B = δ²L_i²·ε·g_j, eq. (37)."""
    g_k: arb
    n_b: arb
    """g_j/(c/εL_i)²: w_B/c² over δ²/ε."""
    n_c: arb
    """g_k/(b/εL_i)²."""
    shift_sq: arb
    """|d|²/(δ²ε)², d = (w_C/b)e_b − (w_B/c)e_c: n_B n_C a² + (n_B − n_C)(g_j − g_k) (scaled)."""


def weights(point: Scaled, setting: Setting) -> Weights:
    """Contract the box with the constraints that bound it directly, then form the weights.

    The excesses are capped by (33) and the Lipschitz conditions to p_i, a is at least σ by
    (36), and R/(εL_i) is at most 1/(1−ε) by H3: every feasible point of the box keeps these.
    """
    eps, lam = point.eps, setting.lipschitz
    lfs_cap = 2 / (1 - eps)
    excess_j = _cap(point.excess_j, lfs_cap, *([] if lam is None else [arb(lam) * point.edge_c]))
    excess_k = _cap(point.excess_k, lfs_cap, *([] if lam is None else [arb(lam) * point.edge_b]))
    edge_a = _floor(point.edge_a, arb(setting.sigma))
    radius = 1 / (1 - eps)
    if point.sin_theta > 0:
        radius = arb.min(radius, edge_a / (2 * point.sin_theta))
    radius = arb.union(arb(0), radius.upper())
    g_j = excess_j * (2 + eps * excess_j)
    g_k = excess_k * (2 + eps * excess_k)
    n_b = g_j / _square(point.edge_c)
    n_c = g_k / _square(point.edge_b)
    if lam is not None:
        # ℓ_j ≤ λ·c/(εL_i) gives g_j/c² ≤ λ(2 + εℓ_j)/c without the spread of c between the
        # numerator and the denominator (the extreme configurations have ℓ_j = λc/(εL_i)).
        n_b = _cap(n_b, arb(lam) * (2 + eps * excess_j) / point.edge_c)
        n_c = _cap(n_c, arb(lam) * (2 + eps * excess_k) / point.edge_b)
    shift_sq = n_b * n_c * _square(edge_a) + (n_b - n_c) * (g_j - g_k)
    return Weights(
        excess_j, excess_k, edge_a, radius, g_j, g_k, n_b, n_c, shift_sq.nonnegative_part()
    )


def enclosures(
    point: Scaled, setting: Setting, names: Sequence[str] | None = None
) -> dict[str, arb]:
    """Upper enclosures of the target's fraction on the feasible part of the box.

    Parameters
    ----------
    point : Scaled
        The box.
    setting : Setting
        σ, δ/ε, ρ_f, λ and the target.
    names : sequence of {"circumradius", "chord", "exact"}, optional
        Which valid bounds to evaluate (module docstring); default: all valid for the target.

    Returns
    -------
    dict
        Name ↦ ball whose upper end bounds the fraction at every feasible point of the box.

    Raises
    ------
    KeyError
        For a name that is not an enclosure of the setting's target.

    References
    ----------
    Eq. (16)–(17), (25)–(29), (54)–(55), property H3.
    """
    valid = enclosure_names(setting.target)
    names = valid if names is None else names
    w = weights(point, setting)
    ratio = arb(setting.delta_ratio)
    scale = setting.scale()
    # In scaled units (a − â)/a = (δ/ε)²ε·q with q = shift or numerator/a²; the additive
    # fraction is that times R/(εL_i) over (ρ_f − 1)·δ/ε, the ratio one over 1 − 1/ρ_f.
    size = ratio * point.eps
    factor = w.radius if setting.target == "additive" else ratio
    out = {}
    for name in names:
        if name not in valid:
            raise KeyError(name)
        if name == "circumradius":
            out[name] = w.radius / (scale * ratio)
        elif name == "chord":
            # |d|²/a² = n_B n_C + (n_B − n_C)(g_j − g_k)/a² (step 3's identity over a²): a
            # enters once, so a wide range of θ (and hence of a) costs little.
            share_sq = w.n_b * w.n_c + (w.n_b - w.n_c) * (w.g_j - w.g_k) / _square(w.edge_a)
            shift = share_sq.nonnegative_part().sqrt()
            out[name] = size * shift * factor / scale
        else:
            numerator = _gap_numerator(point, w, ratio)
            out[name] = size * numerator * factor / (scale * _square(w.edge_a))
    return out


def _gap_numerator(point: Scaled, w: Weights, ratio: arb) -> arb:
    """(a − â)·a/(δ²ε·εL_i): (2 a⃗·d − |d|²)·a/(a + â) in scaled units, Theorem 1 via E2.

    With a⃗ = b e_b − c e_c and â⃗ = a⃗ − d (the chord B̂Ĉ of the orthocircle), a − â =
    (2 a⃗·d − |d|²)/(a + â); nothing cancels.
    """
    eps, edge_b, edge_c, cos_theta = point.eps, point.edge_b, point.edge_c, point.cos_theta
    chord_dot_shift = (
        w.g_j + w.g_k - (edge_b * w.g_j / edge_c + edge_c * w.g_k / edge_b) * cos_theta
    )
    weight = ratio * ratio * eps
    b_hat = edge_b - weight * w.g_k / edge_b
    c_hat = edge_c - weight * w.g_j / edge_c
    diff = b_hat - c_hat
    one_minus = (1 - cos_theta).nonnegative_part()
    a_hat = ((diff * diff).nonnegative_part() + 2 * b_hat * c_hat * one_minus).nonnegative_part()
    return (2 * chord_dot_shift - weight * w.shift_sq) * w.edge_a / (w.edge_a + a_hat.sqrt())


def best_enclosure(point: Scaled, setting: Setting) -> tuple[str, arb]:
    """The enclosure with the smallest upper end, as (name, ball)."""
    names = enclosure_names(setting.target)
    values = enclosures(point, setting)
    finite = [name for name in names if values[name].is_finite()]
    if not finite:
        return names[0], values[names[0]]
    name = min(finite, key=lambda n: values[n].upper())
    return name, values[name]


def exact_ratio_at(values: Sequence[arb], setting: Setting) -> arb:
    """Enclosure of the exact fraction of the target at one configuration (for
    counterexamples).

    Uses the true R = a/(2 sin θ) (no H3 bound), so its lower end is a valid lower bound.
    """
    point = scaled(values)
    ratio = arb(setting.delta_ratio)
    g_j = point.excess_j * (2 + point.eps * point.excess_j)
    g_k = point.excess_k * (2 + point.eps * point.excess_k)
    n_b = g_j / (point.edge_c * point.edge_c)
    n_c = g_k / (point.edge_b * point.edge_b)
    shift_sq = n_b * n_c * point.edge_a * point.edge_a + (n_b - n_c) * (g_j - g_k)
    w = Weights(
        point.excess_j,
        point.excess_k,
        point.edge_a,
        point.edge_a / (2 * point.sin_theta),
        g_j,
        g_k,
        n_b,
        n_c,
        shift_sq,
    )
    numerator = _gap_numerator(point, w, ratio)
    factor = w.radius if setting.target == "additive" else ratio
    return ratio * point.eps * numerator * factor / (setting.scale() * w.edge_a * w.edge_a)


@contextlib.contextmanager
def working_precision(bits: int = PRECISION_BITS):
    """Set the ball arithmetic's precision to ``bits`` for a block, then restore it."""
    saved = ctx.prec
    ctx.prec = bits
    try:
        yield
    finally:
        ctx.prec = saved
