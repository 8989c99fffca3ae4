"""Done-markers: what lets a re-run skip the jobs that are finished and still current.

After a job's outputs are published (renamed into place, see staging.py) the worker
writes `<outdir>/.pdsgen-batch/jobs/<id>.json` holding a hash of the job's options
and pdsgen's version, the size and modification time of each input, and the same
of each output. A re-run skips the job only if all of these still match; a changed
option, input or pdsgen version, or an output deleted or touched, makes it run again.
Files that describe a whole directory (an Extras README.TXT), which later jobs in
the same directory rewrite, need only still exist.

Before a job starts, the marker says "started". A run killed part way leaves that
state behind. A job whose marker shows it published its outputs before (done, or
started and killed) may replace them when it runs again; a job that never did gets
no marker when it fails, so an "output exists" refusal is never turned into an
overwrite of somebody else's file.
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

from ..formats.checksum import bytes_sha256
from ..storage import files

STATE_DIR = ".pdsgen-batch"
MARKER_FORMAT = "pdsgen batch marker 1"


def options_hash(kind: str, params: Mapping[str, Any], version: str) -> str:
    """Hash of what a job is asked to make: its kind, parameters and pdsgen's version."""
    text = json.dumps({"kind": kind, "params": params, "version": version}, sort_keys=True, default=str)
    return bytes_sha256(text.encode("utf-8"))


def marker_path(outdir: Path, job_id: str) -> Path:
    return outdir / STATE_DIR / "jobs" / f"{job_id}.json"


def file_stats(paths: Iterable[str]) -> dict[str, list[int] | None]:
    """path -> [size, mtime in ns] (None if missing), directories (and s3:// prefixes) expanded
    to their files."""
    found: dict[str, list[int] | None] = {}
    for name in paths:
        found.update(files.stats(name))
    return found


def read_marker(path: Path) -> dict[str, Any] | None:
    try:
        text = files.read_text(path)
        data = json.loads(text) if text is not None else None
    except (OSError, ValueError):
        return None
    return data if isinstance(data, dict) and data.get("format") == MARKER_FORMAT else None


def write_marker(path: Path, **fields: Any) -> None:
    """Write the marker whole (a temporary name renamed into place; an object PUT whole)."""
    files.write_text_whole(path, json.dumps({"format": MARKER_FORMAT, **fields}, indent=1, sort_keys=True))


def remove_marker(path: Path) -> None:
    files.remove(path)


def is_done(marker: Mapping[str, Any] | None, digest: str, inputs: Iterable[str]) -> bool:
    """Whether MARKER records this very job as finished, with its inputs and outputs unchanged."""
    if not marker or marker.get("state") != "done" or marker.get("options") != digest:
        return False
    if marker.get("inputs") != file_stats(inputs):
        return False
    outputs = marker.get("outputs", {})
    if not (isinstance(outputs, dict) and outputs == file_stats(outputs)):
        return False
    # directory-wide files (README.TXT) are rewritten by later jobs: they need only exist
    return all(files.is_file(shared) for shared in marker.get("shared", []))


def may_replace(marker: Mapping[str, Any] | None) -> bool:
    """Whether this job's earlier runs published (or may have published) its outputs.

    Then the job may replace them: it was finished and has changed, or was killed part
    way, or failed after such a run. A job with no marker never replaces a file.
    """
    if marker is None:
        return False
    return marker.get("state") in ("done", "started") or bool(marker.get("owner"))


def _stale_marker_temporaries(marker: Path) -> list[Path]:
    """A marker's own temporaries (write_marker) whose writer process is gone: a batch
    killed between writing a marker and renaming it leaves one behind."""
    removed = []
    for leftover in marker.parent.glob(f".{marker.name}.*.part"):
        pid = leftover.name[len(marker.name) + 2:-len(".part")]
        try:
            written = leftover.stat().st_mtime
        except FileNotFoundError:
            continue
        if pid.isdigit() and not _writer_alive(int(pid), written):
            leftover.unlink(missing_ok=True)
            removed.append(leftover)
    return removed


def _writer_alive(pid: int, written: float) -> bool:
    """Whether the process that wrote a file at time `written` may still be running: a process
    `pid` exists and (where the system says when it started) started before the file was
    written. Process ids are reused (after 32768 of them on many Linux systems), so a new
    process holding a killed batch's id must not keep its leftover alive forever."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # alive, another user's
        pass
    if _is_zombie(pid):  # killed, not yet reaped (a killed batch's worker): it writes nothing more
        return False
    started = _process_start_time(pid)
    return started is None or started <= written + 1.0  # 1 s: clock ticks and file-time granularity


def _is_zombie(pid: int) -> bool:
    """Whether process `pid` has exited and waits to be reaped (state Z in /proc on Linux; False
    where the system does not say)."""
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0] == "Z"
    except (OSError, IndexError):
        return False


def _process_start_time(pid: int) -> float | None:
    """When process `pid` started (seconds since the epoch), from /proc on Linux; None elsewhere."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
        boot = next(line for line in Path("/proc/stat").read_text().splitlines() if line.startswith("btime "))
        ticks = int(stat.rsplit(")", 1)[1].split()[19])  # field 22, starttime, after "(comm)"
        return int(boot.split()[1]) + ticks / os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError, IndexError, StopIteration):
        return None


def remove_interrupted_leftovers(markers: Iterable[Path]) -> list[Path]:
    """Delete the temporary files (`.NAME.*.part`, see staging.py) that jobs killed part way left.

    Called before any job of a run starts, for the outdirs of jobs whose marker says
    "started", so no temporary file of a running job can be among them.
    """
    removed = []
    markers = list(markers)
    for marker in markers:
        removed += _stale_marker_temporaries(marker)
        data = read_marker(marker)
        if not data or data.get("state") != "started" or not isinstance(data.get("outdir"), str):
            continue
        for leftover in Path(data["outdir"]).glob(".*.part"):
            try:
                leftover.unlink()
            except OSError:
                continue
            removed.append(leftover)
    return removed
