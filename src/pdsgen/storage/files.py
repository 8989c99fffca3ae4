"""Small whole files (batch markers, logs, summaries) and file facts, wherever they live.

Batch keeps its done-markers beside the products; with an s3:// OUTDIR they are objects
too, written whole (a PUT is atomic, as the local rename is), so a worker that shares no
disk with the client can record and check them. Each function takes a local path or an
internal /vsis3/ path and does the same for both.
"""

from __future__ import annotations

import os
from pathlib import Path

from . import objects
from .locations import S3Location, is_s3
from .staging import staged_file


def read_text(path: str | os.PathLike[str]) -> str | None:
    """The file's text, or None if it is not there."""
    if is_s3(path):
        data = objects.read_if_there(S3Location.parse(path))
        return None if data is None else data.decode("utf-8")
    try:
        return Path(path).read_text(encoding="utf-8")
    except FileNotFoundError:
        return None


def write_text_whole(path: str | os.PathLike[str], text: str) -> None:
    """Write the file so a reader sees the old one or the new one, never a part."""
    if is_s3(path):
        objects.put_bytes(S3Location.parse(path), text.encode("utf-8"))
        return
    local = Path(path)
    local.parent.mkdir(parents=True, exist_ok=True)
    with staged_file(local) as temporary:
        temporary.write_text(text, encoding="utf-8")


def remove(path: str | os.PathLike[str]) -> None:
    """Remove the file if it is there."""
    if is_s3(path):
        objects.delete(S3Location.parse(path))
    else:
        Path(path).unlink(missing_ok=True)


def is_file(path: str | os.PathLike[str]) -> bool:
    if is_s3(path):
        return objects.stat(S3Location.parse(path)) is not None
    return Path(path).is_file()


def stats(path: str | os.PathLike[str]) -> dict[str, list[int] | None]:
    """path -> [size, modification time in ns], None if missing; a directory (or an s3://
    prefix) expanded to its files. Objects are named by their internal /vsis3/ paths."""
    if is_s3(path):
        location = S3Location.parse(path)
        info = objects.stat(location) if location.key and not location.key.endswith("/") else None
        if info is not None:
            return {os.fspath(path): [info.size, info.mtime_ns]}
        found: dict[str, list[int] | None] = {str(item.location.path): [item.size, item.mtime_ns]
                                              for item in objects.list_objects(location)}
        return found or {os.fspath(path): None}
    local = Path(path)
    files = sorted(p for p in local.rglob("*") if p.is_file()) if local.is_dir() else [local]
    result: dict[str, list[int] | None] = {}
    for file in files:
        try:
            st = file.stat()
        except OSError:
            result[str(file)] = None
        else:
            result[str(file)] = [st.st_size, st.st_mtime_ns]
    return result
