"""The tile engine: a guide-triangle check cut into tiles with halos, run on any executor.

- :mod:`~vorobound.tiling.plan`: where tiles lie and how wide their halos must be;
- :mod:`~vorobound.tiling.engine`: read a ball file into a spill, route the balls to their
  tiles, run the tiles on a ``concurrent.futures`` executor, merge what they send back;
- :mod:`~vorobound.tiling.job`: one tile's check, as a worker computes it;
- :mod:`~vorobound.tiling.tally`: the mergeable counts and maxima a tile sends back (a whole
  check's summary is built from the same tally);
- :mod:`~vorobound.tiling.rows`: the per-triangle columns, VTU cells and row files.

The check's reports (:mod:`vorobound.reports.check`, :mod:`vorobound.reports.check_tiled`)
sit on top of it.
"""
