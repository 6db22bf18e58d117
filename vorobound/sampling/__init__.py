"""Surfaces and point sets: analytic surfaces with a known local feature size, mesh and sizing
files, and (built on them) VoroCrust samples."""
