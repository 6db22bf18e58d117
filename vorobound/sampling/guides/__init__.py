"""Guide triangles of a set of balls: seeds, the engines that find them, and their measurement
against the bounds.
"""
