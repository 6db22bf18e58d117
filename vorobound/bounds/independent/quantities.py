"""The constraint set and the target's enclosures, re-derived from the paper for the second
checker (python-flint ``arb`` balls; nothing from the prover's modules).

A box is six closed intervals in the certificate's coordinates

    (ε, β = b/(εL_i), γ = c/(εL_i), cos θ, ℓ_j = (L_j/L_i − 1)/ε, ℓ_k = (L_k/L_i − 1)/ε)

with L_i = 1, r = δ/ε, so δ = rε. Derived (law of cosines, no cancellation):
α = a/(εL_i) = sqrt((β − γ)² + 2βγ(1 − cos θ)) and sin θ = sqrt((1 − cos θ)(1 + cos θ)).

Constraints, each ``small ≤ large`` (a box is infeasible for one when ``large < small`` at all
of its points):

* (33) L_i ≤ L_j ≤ (1+ε)/(1−ε)·L_i  ⇔  0 ≤ ℓ_j ≤ 2/(1−ε)  (and the same for k);
* (34), (35) σεL_i ≤ c, b ≤ 2ε/(1−ε)·L_i  ⇔  σ ≤ γ, β ≤ 2/(1−ε);
* (36) σε·min(L_j, L_k) ≤ a ≤ 2ε(1+ε)/(1−ε)²·L_i  ⇔  σ(1 + ε·min(ℓ_j, ℓ_k)) ≤ α ≤
  2(1+ε)/(1−ε)²;
* H3 R = a/(2 sin θ) ≤ ε/(1−ε)·L_i  ⇔  α ≤ 2 sin θ/(1−ε);
* Lipschitz (with λ) L_j − L_i ≤ λc, L_k − L_i ≤ λb, |L_j − L_k| ≤ λa  ⇔  ℓ_j ≤ λγ,
  ℓ_k ≤ λβ, |ℓ_j − ℓ_k| ≤ λα.

The target's fraction, ≤ 1 exactly where the target holds: (R − R̂)/((ρ_f − 1)δL_i)
(additive) or ((R − R̂)/R)/(1 − 1/ρ_f) (ratio, R ≤ ρ_f·R̂, eq. (54)). With the shifted weights
w_B = δ²(L_j² − L_i²) = δ²ε·g_j, g = ℓ(2 + εℓ) (eq. (37)), n_B = g_j/γ², n_C = g_k/β² and
d = (w_C/b)e_b − (w_B/c)e_c (the shift of the chord BC, Theorem 1 as a chord):

* |d|² = δ⁴·S, S = n_B n_C α² + (n_B − n_C)(g_j − g_k) (expand |m_C P − m_B Q|² with
  2P·Q = b² + c² − a²);
* a⃗·d = δ²ε·(g_j + g_k − (β g_j/γ + γ g_k/β) cos θ);
* (R − R̂)/R = (a − â)/a, a − â = (2a⃗·d − |d|²)/(a + â) (Theorem 1);
* ``circumradius`` (additive): R − R̂ ≤ R (R̂ ≥ 0), fraction ≤ (R/(εL_i))/((ρ_f − 1)r);
* ``chord``: a − â ≤ |d|, so (R − R̂)/R ≤ r²ε·sqrt(S/α²);
* ``exact``: (R − R̂)/R = r²ε·(2a⃗·d/(δ²ε) − r²ε·S)·α/(α + â/(εL_i))/α².

R/(εL_i) ≤ min(1/(1−ε), α/(2 sin θ)) (H3). Before the enclosures, each box is narrowed to what
its feasible points allow: ℓ_j ≤ 2/(1−ε) and ℓ_j ≤ λγ (same for k), α ≥ σ, and with λ
n_B ≤ λ(2 + εℓ_j)/γ (from ℓ_j ≤ λγ).

References
----------
Theorem 1 (eq. (16), (25)–(29)), eq. (33)–(37), (54)–(55), property H3; docs/tight.md.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

from flint import arb, fmpq

COORDINATES = ("eps", "edge_b", "edge_c", "cos_theta", "excess_j", "excess_k")
"""The certificate's box coordinates, in the order its split indices refer to."""
TARGET_ENCLOSURES = {"additive": ("circumradius", "chord", "exact"), "ratio": ("chord", "exact")}
"""The enclosure names a leaf may cite, by target (R − R̂ ≤ R says nothing about the ratio)."""


def ball(value: Fraction) -> arb:
    """A ball containing the rational ``value`` exactly."""
    return arb(fmpq(value.numerator, value.denominator))


def interval(lo: Fraction, hi: Fraction) -> arb:
    """A ball containing every number of [lo, hi]."""
    return arb.union(ball(lo), ball(hi))


def _at_least_zero(x: arb) -> arb:
    return x.nonnegative_part()


def _square_of_positive(x: arb) -> arb:
    """x² over the ball from its two ends (the product x·x would double the spread)."""
    lo, hi = x.lower(), x.upper()
    if lo < 0:
        return x * x
    return arb.union((lo * lo).lower(), (hi * hi).upper())


def _lowered_top(x: arb, *caps: arb) -> arb:
    """``x`` with its top end moved down to the lowest top end of ``caps`` (each cap is an upper
    bound of the quantity at every feasible point); unchanged if that would empty it."""
    top = x.upper()
    for cap in caps:
        top = arb.min(top, cap.upper())
    return x if top < x.lower() else arb.union(x.lower(), top)


def _raised_bottom(x: arb, floor: arb) -> arb:
    """``x`` with its bottom end moved up to the bottom of ``floor``; unchanged if emptied."""
    bottom = arb.max(x.lower(), floor.lower())
    return x if bottom > x.upper() else arb.union(bottom, x.upper())


@dataclass(frozen=True)
class Parameters:
    """σ, r = δ/ε, ρ_f, λ (or None) and the target, as balls holding the exact values."""

    sigma: arb
    ratio: arb
    rho_f: arb
    lipschitz: arb | None
    target: str

    def allowance(self) -> arb:
        """The target in the fraction's units: ρ_f − 1 (additive) or 1 − 1/ρ_f (ratio)."""
        return 1 - 1 / self.rho_f if self.target == "ratio" else self.rho_f - 1


@dataclass(frozen=True)
class Triangle:
    """The balls of one box: its six coordinates and α = a/(εL_i), sin θ."""

    eps: arb
    beta: arb
    gamma: arb
    cos_theta: arb
    ell_j: arb
    ell_k: arb
    alpha: arb
    sin_theta: arb

    @classmethod
    def of(cls, box) -> Triangle:
        """From a box given as six (lo, hi) pairs of Fractions."""
        eps, beta, gamma, cos_theta, ell_j, ell_k = (interval(lo, hi) for lo, hi in box)
        below = _at_least_zero(1 - cos_theta)
        above = _at_least_zero(1 + cos_theta)
        gap = beta - gamma
        alpha_sq = _at_least_zero(gap * gap) + 2 * beta * gamma * below
        return cls(
            eps,
            beta,
            gamma,
            cos_theta,
            ell_j,
            ell_k,
            alpha=_at_least_zero(alpha_sq).sqrt(),
            sin_theta=_at_least_zero(below * above).sqrt(),
        )


def constraint_sides(name: str, t: Triangle, p: Parameters) -> tuple[arb, arb] | None:
    """(small, large) of the constraint ``name`` on the box, or None for a name that is not a
    constraint at these parameters (a Lipschitz one without λ, or an unknown name)."""
    top = 2 / (1 - t.eps)
    lam = p.lipschitz
    sides = {
        "lfs_j_min": lambda: (arb(0), t.ell_j),
        "lfs_j_max": lambda: (t.ell_j, top),
        "lfs_k_min": lambda: (arb(0), t.ell_k),
        "lfs_k_max": lambda: (t.ell_k, top),
        "c_min": lambda: (p.sigma, t.gamma),
        "c_max": lambda: (t.gamma, top),
        "b_min": lambda: (p.sigma, t.beta),
        "b_max": lambda: (t.beta, top),
        "a_min": lambda: (p.sigma * (1 + t.eps * arb.min(t.ell_j, t.ell_k)), t.alpha),
        "a_max": lambda: (t.alpha, 2 * (1 + t.eps) / (1 - t.eps) ** 2),
        "circumradius_max": lambda: (t.alpha, 2 * t.sin_theta / (1 - t.eps)),
    }
    if lam is not None:
        sides |= {
            "lipschitz_ij": lambda: (t.ell_j, lam * t.gamma),
            "lipschitz_ik": lambda: (t.ell_k, lam * t.beta),
            "lipschitz_jk": lambda: (abs(t.ell_j - t.ell_k), lam * t.alpha),
        }
    make = sides.get(name)
    return None if make is None else make()


def fails_everywhere(name: str, t: Triangle, p: Parameters) -> bool:
    """True if the constraint ``name`` is violated at every point of the box."""
    sides = constraint_sides(name, t, p)
    if sides is None:
        return False
    small, large = sides
    return bool(large < small)


def fraction_enclosure(name: str, t: Triangle, p: Parameters) -> arb:
    """A ball whose top end bounds the target's fraction at every feasible point of the box,
    by the enclosure ``name`` (module docstring). KeyError for a name not valid for the target.
    """
    if name not in TARGET_ENCLOSURES[p.target]:
        raise KeyError(name)
    eps, lam = t.eps, p.lipschitz
    top = 2 / (1 - eps)
    ell_j = _lowered_top(t.ell_j, top, *(() if lam is None else (lam * t.gamma,)))
    ell_k = _lowered_top(t.ell_k, top, *(() if lam is None else (lam * t.beta,)))
    alpha = _raised_bottom(t.alpha, p.sigma)
    radius = 1 / (1 - eps)  # R/(εL_i), by H3
    if t.sin_theta > 0:
        radius = arb.min(radius, alpha / (2 * t.sin_theta))
    radius = arb.union(arb(0), radius.upper())
    g_j = ell_j * (2 + eps * ell_j)
    g_k = ell_k * (2 + eps * ell_k)
    n_b = g_j / _square_of_positive(t.gamma)
    n_c = g_k / _square_of_positive(t.beta)
    if lam is not None:
        n_b = _lowered_top(n_b, lam * (2 + eps * ell_j) / t.gamma)
        n_c = _lowered_top(n_c, lam * (2 + eps * ell_k) / t.beta)
    r, allowance = p.ratio, p.allowance()
    # (R − R̂)/R ≤ r²ε·q; the additive fraction is that times R/(εL_i)·ε/((ρ_f − 1)rε), the
    # ratio one over 1 − 1/ρ_f: both are rε·q·factor/allowance.
    factor = radius if p.target == "additive" else r
    if name == "circumradius":
        return radius / (allowance * r)
    alpha_sq = _square_of_positive(alpha)
    if name == "chord":
        share_sq = n_b * n_c + (n_b - n_c) * (g_j - g_k) / alpha_sq
        return r * eps * _at_least_zero(share_sq).sqrt() * factor / allowance
    shift_sq = _at_least_zero(n_b * n_c * alpha_sq + (n_b - n_c) * (g_j - g_k))
    beta, gamma, cos_theta = t.beta, t.gamma, t.cos_theta
    dot = g_j + g_k - (beta * g_j / gamma + gamma * g_k / beta) * cos_theta
    weight = r * r * eps
    beta_hat = beta - weight * g_k / beta
    gamma_hat = gamma - weight * g_j / gamma
    gap = beta_hat - gamma_hat
    below = _at_least_zero(1 - cos_theta)
    alpha_hat = _at_least_zero(_at_least_zero(gap * gap) + 2 * beta_hat * gamma_hat * below)
    numerator = (2 * dot - weight * shift_sq) * alpha / (alpha + alpha_hat.sqrt())
    return r * eps * numerator * factor / (allowance * alpha_sq)
