"""The numbers the paper and the original VoroCrust analysis fix, defined once.

References
----------
Section 4.1 of "Analytic formula for the difference of the circumradius and orthoradius of a
weighted triangle" (σ = 3/4, δ = 2ε, ρ_f < 1.38, ε ≤ 0.0047 against ε = 1/500).
"""

PAPER_SIGMA = 0.75
"""Sparsity σ of the ε-sample, Section 4.1."""
PAPER_DELTA_RATIO = 2.0
"""Ball radius factor over ε, δ/ε (the paper's δ = 2ε)."""
PAPER_RHO_F = 1.38
"""Quality constant ρ_f of R ≤ ρ_f δ L_i, eq. (54)–(55)."""
PAPER_EPS = 0.0047
"""The sampling density the paper reports as admissible (Section 4.1, Figure 3)."""
BASELINE_EPS = 1 / 500
"""The sampling density of the original VoroCrust analysis."""
