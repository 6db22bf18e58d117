"""The tight bound: the supremum of R − R̂ over every guide triangle of the constraint set.

``problem`` states it in normalized coordinates, ``search`` optimizes it, ``scan`` finds the
supremum at one ε and the tight ε*.
"""

from .scan import TightResult, solve_tight, tight_supremum

__all__ = ["TightResult", "solve_tight", "tight_supremum"]
