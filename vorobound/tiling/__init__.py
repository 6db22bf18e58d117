"""The check's pipeline and its tile engine: a guide-triangle check cut into tiles with halos,
run on any executor, or a whole sample as one tile in process.

- :mod:`~vorobound.tiling.job`: the pipeline, :func:`~vorobound.tiling.job.check_part`, from
  a part's balls to its guide rows and tallies (a tile on a worker; a whole check as one
  tile, :mod:`vorobound.reports.check`);
- :mod:`~vorobound.tiling.plan`: where tiles lie and how wide their halos must be;
- :mod:`~vorobound.tiling.engine`: read a ball file into a spill, route the balls to their
  tiles, run the tiles on a ``concurrent.futures`` executor, merge what they send back;
- :mod:`~vorobound.tiling.tally`: the mergeable counts and maxima a part sends back (a whole
  check's summary is built from the same tally);
- :mod:`~vorobound.tiling.rows`: the per-triangle columns, VTU cells, and the two sinks of the
  rows (part files, memory).

The check's reports (:mod:`vorobound.reports.check`, :mod:`vorobound.reports.check_tiled`)
sit on top of it.
"""
