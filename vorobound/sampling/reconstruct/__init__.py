"""VoroCrust's surface M̂ rebuilt from the seeds: labelled seeds, the Voronoi facets between an
inside and an outside seed, the polygon surface they form, its topology and its distance to
the surface that was sampled.
"""
