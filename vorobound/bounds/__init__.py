"""Bounds on R − R̂ for VoroCrust guide triangles: parameters, the constraint set, the chain
(33)–(53), its audit, the ε* solvers and the tight supremum."""
