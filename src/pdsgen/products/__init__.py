"""Products: orchestration of readers, geometry, mission names and writers.

`write_dtm` and `write_ortho` (in `dtm.py` and `ortho.py`; also `pdsgen.write_dtm`)
pick the mission's writer by profile through `dispatch`; every writer returns a
`ProductResult` (result.py: product ID, files written, geometry, warnings, and the
line that says what was written).
"""
