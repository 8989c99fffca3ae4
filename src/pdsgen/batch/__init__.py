"""Archive-scale production: many product commands from one manifest, on Dask.

`load_manifest` reads and checks a TOML manifest of dtm/ortho/extras/validate jobs
(keys and checks taken from the CLI commands themselves); `run` runs it on a Dask
cluster - each job's body in its own child process, done jobs skipped on a re-run
thanks to markers written after publication - and `plan` prints what a run would do.
"""

from __future__ import annotations

from .manifest import Job, Manifest, ManifestError, load_manifest
from .run import Settings, Summary, plan, run

__all__ = ["Job", "Manifest", "ManifestError", "Settings", "Summary", "load_manifest", "plan", "run"]
