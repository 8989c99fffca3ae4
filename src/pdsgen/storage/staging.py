"""Write a product's files under temporary names and rename them only when complete.

A product is several files (an .IMG, or a .JP2 with its .LBL); either all of them
appear or none does, so an interrupted or failed run never leaves a half-written
product that a later delivery step might pick up.

The one module that renames files (tests/test_architecture_staging.py): a product's files
(StagedOutputs), any other single file or set of files (staged_file, staged_files: a
report, a baseline, review pages, a schema download) and a whole tree (replace_directory:
a delivery) all appear here, so removing temporaries on failure and holding Ctrl-C back
while names change are written once.
"""

from __future__ import annotations

import errno
import functools
import logging
import os
import shutil
import signal
import tempfile
import threading
from collections.abc import Callable, Iterable, Iterator
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass, field
from pathlib import Path
from types import TracebackType
from typing import ParamSpec, TypeVar

from ..errors import OutputError, PdsgenError, param

log = logging.getLogger(__name__)  # what was written: shown by `pdsgen ... --verbose`

# Failures of writing itself: reported as the output's problem in one line, not a traceback.
_WRITE_ERRNOS = {errno.ENOSPC: "no space left on device", errno.EDQUOT: "disk quota exceeded",
                 errno.EFBIG: "file too large for the file system", errno.EIO: "input/output error",
                 errno.EROFS: "read-only file system", errno.EACCES: "permission denied",
                 errno.EPERM: "operation not permitted"}


def prepare_output_dir(outdir: str | os.PathLike[str]) -> Path:
    """Create OUTDIR if needed and make sure we can write into it."""
    path = Path(outdir)
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise PdsgenError(path, f"cannot create output directory ({exc.strerror})") from None
    if not path.is_dir():
        raise PdsgenError(path, "output path exists and is not a directory")
    if not os.access(path, os.W_OK | os.X_OK):
        raise PdsgenError(path, "output directory is not writable")
    return path


class StagedOutputs:
    """Context manager: hand out temporary paths, publish them all on success.

    On any exception inside the block every temporary file is removed and nothing
    under the final names is touched.
    """

    def __init__(
        self,
        final_paths: Iterable[str | os.PathLike[str]],
        overwrite: bool,
        shared: Iterable[str | os.PathLike[str]] = (),
        restore_on_rollback: bool = True,
    ) -> None:
        """`shared` paths are files several products update (a scene's footprint):
        they are replaced without --overwrite, but still only when everything succeeds.

        `restore_on_rollback=False`: inside `published_together`, a rollback leaves these
        files as they are rather than putting back what they replaced - for a file other
        runs may have updated since (a directory's README.TXT), which the writer repairs
        itself with `on_rollback`."""
        self.shared = [Path(p) for p in shared]
        self.final_paths = [Path(p) for p in final_paths] + self.shared
        self.overwrite = overwrite
        self.restore_on_rollback = restore_on_rollback
        self._temps: dict[Path, Path] = {}

    def __enter__(self) -> StagedOutputs:
        for final in self.final_paths:
            if final.is_dir():
                raise PdsgenError(final, "output path is a directory")
            if final.exists() and not self.overwrite and final not in self.shared:
                raise PdsgenError(final, f"output exists; use {param('overwrite', True)} to replace it")
        try:
            for final in self.final_paths:
                with _interruption_deferred():
                    self._temps[final] = _make_temp(final)
        except BaseException:  # an interruption here too must leave no temporary file behind
            self._discard()
            raise
        return self

    def path(self, final: str | os.PathLike[str]) -> Path:
        """The temporary path to write in place of `final`."""
        return self._temps[Path(final)]

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        if exc_type is not None:
            self._discard()
            if isinstance(exc, OSError) and not isinstance(exc, PdsgenError) and exc.errno in _WRITE_ERRNOS:
                where = self.final_paths[0].parent if self.final_paths else None
                raise OutputError(where, f"cannot write the product: {_WRITE_ERRNOS[exc.errno]}") from None
            return
        with _interruption_deferred():
            group = _GROUP.get()
            self._publish(group.undo if group is not None and self.restore_on_rollback else None)

    def _publish(self, undo: list[tuple[Path, Path | None]] | None = None) -> None:
        """Rename the temporaries into place; inside `published_together`, record in
        `undo` each final name and the backup of the file it replaced (if any)."""
        for final, tmp in self._temps.items():
            os.chmod(tmp, 0o644 & ~_umask())
            if undo is not None:
                backup = _make_temp(final) if final.exists() else None
                if backup is not None:
                    os.replace(final, backup)
                undo.append((final, backup))
            os.replace(tmp, final)
            log.info("wrote %s (%d bytes)", final, final.stat().st_size)
        self._temps.clear()

    def _discard(self) -> None:
        for tmp in self._temps.values():
            _remove_quietly(tmp)
        self._temps.clear()


@contextmanager
def _interruption_deferred() -> Iterator[None]:
    """Hold Ctrl-C back for a few file operations that must not be cut in half (a
    temporary file created but not yet recorded; a finished set not yet handed over).

    The handler is swapped rather than the signal masked: with GDAL's or the
    encoder's threads running, the kernel may deliver SIGINT to any of them.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    received: list[int] = []
    previous = signal.signal(signal.SIGINT, lambda signum, frame: received.append(signum))
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
    if received and callable(previous):
        previous(signal.SIGINT, None)


class InterruptSafeExecutor(ThreadPoolExecutor):
    """A ThreadPoolExecutor whose shutdown(wait=True) waits for every thread it started, even
    when Ctrl-C arrives while one is starting.

    ThreadPoolExecutor starts a worker thread in submit() and records it only after
    Thread.start() has returned; start() waits for the thread to run, and that wait is where a
    SIGINT becomes a KeyboardInterrupt. The thread then runs its task unrecorded, shutdown does
    not wait for it, and it reads a GDAL dataset the interrupted command has already closed (a
    crash at exit, seen as `pdsgen dtm` killed by SIGSEGV after "interrupted"). Starting the
    thread with Ctrl-C held back (and raised right after) keeps the record whole.
    """

    def _adjust_thread_count(self) -> None:
        with _interruption_deferred():
            super()._adjust_thread_count()


@contextmanager
def staged_file(final: str | os.PathLike[str], temporary: str | os.PathLike[str] | None = None) -> Iterator[Path]:
    """Write one file under a temporary name beside FINAL and rename it into place when the
    block completes, so a reader sees the old file or the new one, never a part.

    Yields the temporary path (TEMPORARY if given - callers whose temporaries others look
    for keep their own names - else `.NAME.PID.part`); the caller creates and writes it.
    If the block raises (Ctrl-C included) the temporary is removed and FINAL is untouched.
    """
    with staged_files() as stage:
        yield stage(final, temporary)


@contextmanager
def staged_files() -> Iterator[Callable[[str | os.PathLike[str], str | os.PathLike[str] | None], Path]]:
    """Several files written under temporary names, renamed into place together at the end.

    Yields `stage(final, temporary=None)`, which records a pair and returns the temporary
    path to write (see `staged_file` for its name). When the block completes, each is renamed
    onto its final name in the order staged, with Ctrl-C held back until all are; if the
    block or a rename fails, the temporaries still there are removed.
    """
    staged: list[tuple[Path, Path]] = []

    def stage(final: str | os.PathLike[str], temporary: str | os.PathLike[str] | None = None) -> Path:
        final_path = Path(final)
        temporary_path = Path(temporary) if temporary is not None else _temporary_name(final_path)
        staged.append((temporary_path, final_path))
        return temporary_path

    try:
        yield stage
        with _interruption_deferred():
            for temporary, final in staged:
                os.replace(temporary, final)
    except BaseException as exc:
        for temporary, _ in staged:
            _remove_quietly(temporary)
        if isinstance(exc, OSError) and not isinstance(exc, PdsgenError):
            for temporary, final in staged:
                if exc.filename in (str(temporary), os.fspath(temporary)):  # the user never named the temporary
                    reason = _WRITE_ERRNOS.get(exc.errno or 0, (exc.strerror or str(exc)).lower())
                    raise OutputError(final, f"cannot write: {reason}") from None
        raise


def _remove_quietly(temporary: Path) -> None:
    """Remove a temporary on the way out of a failure. It may never have been made, or the file
    system may refuse (read-only, gone): the failure being reported is the real one, so this
    one is not raised over it."""
    try:
        temporary.unlink(missing_ok=True)
    except OSError:
        log.debug("could not remove %s", temporary)


def _temporary_name(final: Path) -> Path:
    """`.NAME.PID.part` beside FINAL: hidden, unique to this process, and recognised by the
    clean-up of killed runs (their PID no longer runs)."""
    return final.with_name(f".{final.name}.{os.getpid()}.part")


def replace_directory(work: str | os.PathLike[str], target: str | os.PathLike[str]) -> None:
    """The finished tree WORK takes TARGET's place; the previous tree is moved aside to
    `.NAME.old-PID`, removed after, and put back if WORK cannot take its place. Ctrl-C is
    held back while the names change, so TARGET is never left missing."""
    work, target = Path(work), Path(target)
    refuse_link(target)
    with _interruption_deferred():
        if not target.exists():
            os.rename(work, target)
            return
        old = target.parent / f".{target.name}.old-{os.getpid()}"
        os.rename(target, old)
        try:
            os.rename(work, target)
        except OSError:
            os.rename(old, target)
            raise
    shutil.rmtree(old)


def refuse_link(target: str | os.PathLike[str]) -> None:
    """A tree a command replaces whole must not be a symbolic link: replacing the link would
    leave the directory it leads to as it was while saying the output was written (and a
    link's own rename is not the tree's). Refused in one line before anything is done."""
    if os.path.islink(target):
        raise OutputError(target, f"is a symbolic link (to {os.readlink(target)}); pdsgen does not replace a link: "
                                  "give the directory it leads to, or remove the link")


def _make_temp(final: Path) -> Path:
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{final.name}.", suffix=".part", dir=final.parent)
    except OSError as exc:
        raise PdsgenError(final.parent, f"cannot write output ({exc.strerror})") from None
    os.close(fd)
    return Path(tmp)


@dataclass
class _Rollback:
    """What a rollback of `published_together` does: put back each published file (final
    name, backup of what it replaced), then run the writers' own repairs."""

    undo: list[tuple[Path, Path | None]] = field(default_factory=list)
    repairs: list[Callable[[], None]] = field(default_factory=list)


_GROUP: ContextVar[_Rollback | None] = ContextVar("pdsgen_staged_group", default=None)


def on_rollback(repair: Callable[[], None]) -> None:
    """Inside `published_together`: run `repair` if the set is taken back (after its files are)."""
    group = _GROUP.get()
    if group is not None:
        group.repairs.append(repair)


@contextmanager
def published_together() -> Iterator[None]:
    """Make every StagedOutputs completed inside the block one set: all kept, or none.

    A call that writes several sets of files (Extras of several products, then the
    README that lists them) publishes each as it completes - later steps may look
    for the files - but, interrupted or failing part-way, takes them all back and
    restores the files they replaced: a half set would block the re-run (files
    exist, no --overwrite).
    """
    group = _Rollback()
    token = _GROUP.set(group)
    try:
        yield
    except BaseException:
        with _interruption_deferred():
            for final, backup in reversed(group.undo):
                final.unlink(missing_ok=True)
                if backup is not None:
                    os.replace(backup, final)
            for repair in reversed(group.repairs):
                repair()
        raise
    finally:
        _GROUP.reset(token)
    for _, backup in group.undo:
        if backup is not None:
            backup.unlink(missing_ok=True)


P = ParamSpec("P")
R = TypeVar("R")


def publishes_together(function: Callable[P, R]) -> Callable[P, R]:
    """Decorator form of `published_together` for a writer function."""

    @functools.wraps(function)
    def wrapper(*args: P.args, **kwargs: P.kwargs) -> R:
        with published_together():
            return function(*args, **kwargs)

    return wrapper


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
