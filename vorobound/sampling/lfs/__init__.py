"""Local feature size of a triangle mesh: patches and features, face sites, poles, fitted
midpoints, thickness, tangent balls, the Lipschitz envelope.
"""
