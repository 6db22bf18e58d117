"""Surfaces: analytic shapes with a known local feature size, triangle meshes as surfaces, and the
demo and CAD-like test meshes.
"""
