"""Products: orchestration of readers, geometry, mission names and writers.

`write_dtm` and `write_ortho` (in `pdsgen.dtm` and `pdsgen.ortho`) pick the
mission's writer by profile through `dispatch`; every writer returns a result
that satisfies `ProductResult` (product id, files written, geometry).
"""
