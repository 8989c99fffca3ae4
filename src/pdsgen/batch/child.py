"""The process a batch job's body runs in: `python -m pdsgen.batch.child TASK RESULT`.

Each job runs in a child process of the Dask worker, so a job that crashes - even a
segfault or abort inside GDAL or OpenJPEG - ends only this process; the worker
sees the exit status and goes on with its other jobs. The child reads its task
(JSON) from TASK, makes the one library call of its kind, and writes what it wrote
(or the one-line reason it failed) to RESULT. Its stdout and stderr are the job's log.
"""

from __future__ import annotations

import json
import os
import sys
import traceback
from pathlib import Path
from typing import Any

# Variables that size the thread pools of the native libraries a job uses; set
# from the job's thread count before those libraries load (see thread_environment).
THREAD_VARIABLES = ("GDAL_NUM_THREADS", "OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")


def thread_environment(threads: int) -> dict[str, str]:
    """Environment for a child limited to THREADS threads: GDAL, OpenMP and BLAS pools."""
    return {name: str(threads) for name in THREAD_VARIABLES}


def run(task: dict[str, Any]) -> dict[str, Any]:
    """Make the job's library call; the result is JSON: outputs, or a one-line error."""
    import glymur

    from ..errors import PdsgenError
    from .calls import RUNNERS, ProblemsFound

    glymur.set_option("lib.num_threads", task["threads"])  # OpenJPEG's pool, for decoding and encoding
    params = task["params"]
    try:
        written = RUNNERS[task["kind"]](params, bool(params.get("overwrite")) or task["resume"], task["threads"])
    except (PdsgenError, ProblemsFound) as exc:
        return {"ok": False, "error": str(exc), "retry": False}
    except Exception as exc:  # a bug or an environment failure: keep the traceback in the log
        traceback.print_exc()
        return {"ok": False, "error": f"{type(exc).__name__}: {exc}".splitlines()[0], "retry": True}
    return {"ok": True, **written}


def main(argv: list[str]) -> int:
    task_path, result_path = Path(argv[0]), Path(argv[1])
    result = run(json.loads(task_path.read_text(encoding="utf-8")))
    tmp = result_path.with_name(result_path.name + ".part")
    tmp.write_text(json.dumps(result), encoding="utf-8")
    os.replace(tmp, result_path)
    sys.stdout.flush()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
