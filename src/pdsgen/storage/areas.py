"""A command's boundary with object storage: inputs in, complete products out.

An object store has no rename, so a product cannot appear there "all at once" the way
storage/staging.py makes it appear on disk. Instead the writer works in a local staging
directory exactly as it would in a real OUTDIR, and only when it has finished without an
error are its files uploaded; if anything fails before or during the upload, the objects
already uploaded are deleted again and nothing else is left in the bucket.

Commands call three things here, each a no-op for local paths:
- `output_area(outdir, overwrite)`: where to write, and the upload when done;
- `raster_input(path)`: the path to give GDAL (read in place, with range requests);
- `local_inputs(paths)`: local copies for readers that are not GDAL (labels, text).
"""

from __future__ import annotations

import logging
import os
import shutil
import tempfile
from collections.abc import Callable, Iterable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..errors import InputError, OutputError, PdsgenError, param
from . import objects
from .containment import checked_name, inside
from .locations import S3Location, display, internal, is_s3

log = logging.getLogger(__name__)
# Temporaries of storage/staging.py (".NAME.PID.part") and other hidden work files never leave the staging area.
_HIDDEN = "."


@dataclass
class OutputArea:
    """Where a command writes: `directory` (local), and for an S3 OUTDIR its `location`.

    Paths the writer returns under `directory` are named in the bucket by `remote()`.
    `shared` names files a product updates for its whole directory (README.TXT,
    JP2INFO.TXT): they are fetched before writing and may be replaced on upload.
    """

    directory: Path
    location: S3Location | None = None
    shared: tuple[str, ...] = ()
    uploaded: list[S3Location] = field(default_factory=list)

    def remote(self, path: str | os.PathLike[str]) -> str:
        """PATH (a file the writer wrote in `directory`) where it ends up: its internal
        /vsis3/ form for an S3 OUTDIR, the path itself for a local one."""
        if self.location is None:
            return os.fspath(path)
        relative = Path(path).resolve().relative_to(self.directory.resolve()).as_posix()
        return str(self.location.child(relative).path)

    def shown(self, value: Any) -> Any:
        """VALUE (a summary line, a --json summary) with the staging directory's paths
        replaced by the URLs the files were uploaded to."""
        if self.location is None:
            return value
        if isinstance(value, str):
            base = str(self.directory)
            return value.replace(base, display(self.location.path)) if base in value else value
        if isinstance(value, dict):
            return {key: self.shown(item) for key, item in value.items()}
        if isinstance(value, list | tuple):
            return type(value)(self.shown(item) for item in value)
        if isinstance(value, Path):
            return self.shown(str(value))
        return value


@contextmanager
def output_area(outdir: str | os.PathLike[str], overwrite: bool = False,
                shared: Sequence[str] = ()) -> Iterator[OutputArea]:
    """The directory a command writes its products into.

    Local OUTDIR: itself. S3 OUTDIR (s3://bucket/prefix or /vsis3/...): a fresh local
    staging directory. On a clean exit every file written or changed there is uploaded
    under the prefix; a failed upload deletes what it had uploaded. Local staging is
    removed in every case.

    A product that updates `shared` directory files (JP2INFO.TXT, README.TXT) sees the
    prefix as a directory: its objects as empty placeholder files (so the writer finds
    which products exist, and refuses to replace one unless told to overwrite, as on
    disk) and the shared files whole. Without `shared` nothing is listed (a listing
    grows with the prefix): each file written is checked with one request instead, and
    an existing one refused unless `overwrite`.
    """
    if not is_s3(outdir):
        yield OutputArea(Path(outdir), shared=tuple(shared))
        return
    location = S3Location.parse(outdir)
    objects.check_bucket(location, reading=False)
    staging = _staging_directory()
    try:
        area = OutputArea(staging, location, tuple(shared))
        untouched = _mirror(area) if shared else None
        with _renamed_in_errors(area.shown):
            yield area
            _publish(area, untouched, overwrite)
    finally:
        shutil.rmtree(staging, ignore_errors=True)


_STAGING_PREFIX = "pdsgen-s3-"


def _staging_directory() -> Path:
    """A new local staging directory, named for this process; those of processes that are
    gone (a killed batch job) are removed first."""
    for leftover in Path(tempfile.gettempdir()).glob(f"{_STAGING_PREFIX}*-*"):
        pid = leftover.name[len(_STAGING_PREFIX):].split("-", 1)[0]
        if pid.isdigit() and not _alive(int(pid)):
            shutil.rmtree(leftover, ignore_errors=True)
    return Path(tempfile.mkdtemp(prefix=f"{_STAGING_PREFIX}{os.getpid()}-"))


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


@contextmanager
def _renamed_in_errors(rename: Callable[[str], str]) -> Iterator[None]:
    """A one-line error from inside names the URL, not the local copy it was about."""
    try:
        yield
    except PdsgenError as exc:
        exc.path = rename(exc.path) if exc.path is not None else None
        exc.problem = rename(exc.problem)
        exc.args = (str(exc),)
        raise


def _signature(path: Path) -> tuple[int, int, int]:
    st = path.stat()
    return (st.st_ino, st.st_size, st.st_mtime_ns)


def _mirror(area: OutputArea) -> dict[str, tuple[int, int, int]]:
    """Lay out the objects directly under the prefix in the staging directory (placeholders;
    the shared directory files whole); what each file looked like, to tell later which were
    written. Writers write into OUTDIR itself, so deeper "directories" are not listed (a
    batch's markers and logs there would make every job's listing grow with the run)."""
    assert area.location is not None
    untouched = {}
    for item, name in staged_names(objects.list_objects(area.location, recursive=False), area.location):
        if any(part.startswith(_HIDDEN) for part in name.split("/")):
            continue
        target = inside(area.directory, name, item.location.url)
        if name in area.shared:
            objects.download(item.location, target)
        else:
            target.parent.mkdir(parents=True, exist_ok=True)
            target.touch()
        untouched[name] = _signature(target)
    return untouched


def _publish(area: OutputArea, untouched: dict[str, tuple[int, int, int]] | None, overwrite: bool) -> None:
    """Upload the files the command wrote or changed: products first, directory files last,
    so a reader never finds a directory file naming a product not there yet."""
    assert area.location is not None
    files = sorted(p for p in area.directory.rglob("*") if p.is_file()
                   and not any(part.startswith(_HIDDEN) for part in p.relative_to(area.directory).parts))
    relative = {p: p.relative_to(area.directory).as_posix() for p in files}
    if untouched is None:  # not mirrored: ask about each file
        untouched = {}
        for path in files:
            target = area.location.child(relative[path])
            if not overwrite and objects.stat(target) is not None:
                raise OutputError(target.url, f"output exists; use {param('overwrite', True)} to replace it")
    written = [p for p in files if untouched.get(relative[p]) != _signature(p)]
    ordered = [p for p in written if relative[p] not in area.shared] + \
              [p for p in written if relative[p] in area.shared]
    try:
        for path in ordered:
            target = area.location.child(relative[path])
            objects.upload(path, target)
            area.uploaded.append(target)
            log.info("uploaded %s (%d bytes)", target.url, path.stat().st_size)
    except BaseException:
        for target in area.uploaded:  # all or nothing, as on disk
            if relative_name(target, area.location) not in untouched:
                try:
                    objects.delete(target)
                except OutputError:
                    pass
        raise


@contextmanager
def tree_area(outdir: str | os.PathLike[str], order: Callable[[str], int] | None = None) -> Iterator[OutputArea]:
    """For a command that rewrites a whole tree (a delivery): the directory to rewrite.

    Local OUTDIR: itself. S3 OUTDIR: a local copy of every object under the prefix. An
    object store has no rename to swap a tree in, so on a clean exit the files that
    changed are uploaded in `order` (lowest first: the files that index the others - a
    checksum manifest - last), and only then the objects no longer in the tree deleted:
    a reader going by the index never finds it naming a file that is not there yet. If
    an upload fails, the objects it added are deleted and those it changed put back.
    """
    if not is_s3(outdir):
        yield OutputArea(Path(outdir))
        return
    location = S3Location.parse(outdir)
    objects.check_bucket(location, reading=False)
    staging = _staging_directory()
    try:
        # the copy has the prefix's own name: what the tree says of itself (a review page's
        # title) is what it says on disk
        name = location.prefix.rstrip("/").rpartition("/")[2] or location.bucket
        area = OutputArea(staging / "tree" / name, location)
        previous = staging / "previous"
        for item, name in staged_names(objects.list_objects(location), location):
            objects.download(item.location, inside(previous, name, item.location.url))
        if previous.is_dir():
            shutil.copytree(previous, area.directory)
        with _renamed_in_errors(area.shown):
            yield area
            _publish_tree(area, previous, order or (lambda name: 0))
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def _tree_files(root: Path) -> dict[str, bytes]:
    return {p.relative_to(root).as_posix(): p.read_bytes() for p in sorted(root.rglob("*")) if p.is_file()} \
        if root.is_dir() else {}


def _publish_tree(area: OutputArea, previous: Path, order: Callable[[str], int]) -> None:
    assert area.location is not None
    before, now = _tree_files(previous), _tree_files(area.directory)
    changed = sorted((name for name in now if before.get(name) != now[name]), key=lambda name: (order(name), name))
    done: list[str] = []
    try:
        for name in changed:
            objects.upload(area.directory / name, area.location.child(name))
            done.append(name)
        log.info("uploaded %d changed file(s) of %s", len(done), area.location.url)
    except BaseException:
        for name in reversed(done):  # as it was: added objects deleted, changed ones put back
            try:
                if name in before:
                    objects.upload(previous / name, area.location.child(name))
                else:
                    objects.delete(area.location.child(name))
            except PdsgenError:
                pass
        raise
    for name in sorted(set(before) - set(now)):
        objects.delete(area.location.child(name))


def relative_name(target: S3Location, base: S3Location) -> str:
    return target.key[len(base.prefix):]


def staged_names(found: Iterable[objects.ObjectInfo], base: S3Location) -> list[tuple[objects.ObjectInfo, str]]:
    """Each object under BASE with the name its local copy takes, every name checked by the
    containment rule (a key holding `../`, `//abs`, an empty or over-long segment is refused,
    naming its URL). A key ending in '/' is a "folder" marker some tools write, not a file. A
    key that is both an object and the prefix of others (`a` and `a/b`) is refused: a local
    copy cannot hold a file and a directory of the same name."""
    named = []
    for item in found:
        name = relative_name(item.location, base)
        if not name or name.endswith("/") and item.size == 0:
            continue
        checked_name(name, item.location.url)
        named.append((item, name))
    names = {name for _, name in named}
    for item, name in named:
        parent = name.rpartition("/")[0]
        while parent:
            if parent in names:
                raise InputError(base.child(parent).url, "is both an object and a prefix of other objects "
                                                         f"({item.location.url}); a local copy cannot hold both")
            parent = parent.rpartition("/")[0]
    return named


def raster_input(path: str | os.PathLike[str]) -> str:
    """What to give GDAL for an input: a local path unchanged, an object as /vsis3/, a web
    URL as /vsicurl/ (read inside `gdal_environment`, which formats.raster.open_raster enters)."""
    return internal(path)


def explain_unreadable(path: str | os.PathLike[str]) -> None:
    """After GDAL failed to open an object: raise the one line saying why, if the store
    can tell (no such bucket or object, access denied, endpoint unreachable). Asked only
    on failure, so a successful open costs no extra request. Without boto3, nothing."""
    if not is_s3(path):
        return
    try:
        objects.require_object(S3Location.parse(path))
    except PdsgenError as exc:
        if objects.MISSING_CLIENT not in str(exc):
            raise


@dataclass
class LocalInputs:
    """Local paths for a command's inputs; `shown` names the copies by their URLs again."""

    paths: list[str]
    origins: dict[str, str] = field(default_factory=dict)  # local copy's directory -> URL of the same level

    def shown(self, text: str) -> str:
        for local in sorted(self.origins, key=len, reverse=True):  # .../10 before .../1
            text = text.replace(local, self.origins[local])
        return text


@contextmanager
def local_inputs(paths: Iterable[str | os.PathLike[str]]) -> Iterator[LocalInputs]:
    """Local files for inputs read by Python rather than GDAL (PDS3 labels, the files they
    point to, their directory's other products for the validator's set rules).

    Local paths come back unchanged. An object comes back inside a local copy of its
    "directory": the objects beside it whole, those in subdirectories (Extras) as empty
    files of their size, so a reader finds what it would find on disk. A prefix
    (s3://bucket/dir/) comes back as a local copy of its whole tree.
    """
    given = [os.fspath(p) for p in paths]
    if not any(is_s3(p) for p in given):
        yield LocalInputs(given)
        return
    staging = _staging_directory()
    try:
        inputs = LocalInputs([])
        copies: dict[str, Path] = {}  # URL of a directory -> its local copy (several inputs may share one)
        for path in given:
            inputs.paths.append(_fetch_input(internal(path), staging, copies) if is_s3(path) else path)
        inputs.origins = {str(local): url.rstrip("/") for url, local in copies.items()}
        with _renamed_in_errors(inputs.shown):
            yield inputs
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def _fetch_input(path: str, staging: Path, copies: dict[str, Path]) -> str:
    """The local copy of PATH (an object or a prefix), made inside a copy of its directory
    under STAGING unless COPIES has that directory already."""
    location = S3Location.parse(path)
    info = objects.stat(location) if location.key and not location.key.endswith("/") else None
    if info is None:  # a prefix: the whole "directory"
        directory = S3Location(location.bucket, location.prefix)
        if directory.url not in copies:
            copies[directory.url] = _copy_tree(directory, staging / str(len(copies)), whole=True)
        return str(copies[directory.url])
    directory = S3Location(location.bucket, location.key.rpartition("/")[0])
    directory = S3Location(directory.bucket, directory.prefix)
    if directory.url not in copies:
        copies[directory.url] = _copy_tree(directory, staging / str(len(copies)), whole=False)
    return str(inside(copies[directory.url], location.key.rpartition("/")[2], location.url))


def _copy_tree(directory: S3Location, target: Path, whole: bool) -> Path:
    """Download the objects under DIRECTORY into TARGET. Unless `whole`, only the objects
    directly in it: those in subdirectories (Extras) become empty files of their size,
    enough for rules that ask whether a file is there."""
    found = list(objects.list_objects(directory))
    if not found:
        objects.check_bucket(directory)
        raise InputError(directory.url, "no such object or prefix")
    target.mkdir(parents=True)
    for item, name in staged_names(found, directory):
        local = inside(target, name, item.location.url)
        if whole or "/" not in name:
            objects.download(item.location, local)
        else:
            local.parent.mkdir(parents=True, exist_ok=True)
            with open(local, "wb") as placeholder:
                placeholder.truncate(item.size)
    return target


__all__ = ["LocalInputs", "OutputArea", "explain_unreadable", "local_inputs", "output_area", "raster_input",
           "tree_area"]
