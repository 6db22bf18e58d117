"""The sampler: candidate lattices (surfaces of revolution, meshes), the maximal sparse subset, and
what a sample achieves.
"""
