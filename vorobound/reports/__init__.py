"""Reports built on the bounds: figure data, the paper-reproduction table, sweeps, advice."""
