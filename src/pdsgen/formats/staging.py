"""Write a product's files under temporary names and rename them only when complete.

A product is several files (an .IMG, or a .JP2 with its .LBL); either all of them
appear or none does, so an interrupted or failed run never leaves a half-written
product that a later delivery step might pick up.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterable
from pathlib import Path
from types import TracebackType

from ..errors import PdsgenError


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
    ) -> None:
        """`shared` paths are files several products update (a scene's footprint):
        they are replaced without --overwrite, but still only when everything succeeds."""
        self.shared = [Path(p) for p in shared]
        self.final_paths = [Path(p) for p in final_paths] + self.shared
        self.overwrite = overwrite
        self._temps: dict[Path, Path] = {}

    def __enter__(self) -> StagedOutputs:
        for final in self.final_paths:
            if final.is_dir():
                raise PdsgenError(final, "output path is a directory")
            if final.exists() and not self.overwrite and final not in self.shared:
                raise PdsgenError(final, "output exists; use --overwrite to replace it")
        for final in self.final_paths:
            try:
                fd, tmp = tempfile.mkstemp(prefix=f".{final.name}.", suffix=".part", dir=final.parent)
            except OSError as exc:
                self._discard()
                raise PdsgenError(final.parent, f"cannot write output ({exc.strerror})") from None
            os.close(fd)
            self._temps[final] = Path(tmp)
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
            return
        for final, tmp in self._temps.items():
            os.chmod(tmp, 0o644 & ~_umask())
            os.replace(tmp, final)
        self._temps.clear()

    def _discard(self) -> None:
        for tmp in self._temps.values():
            try:
                tmp.unlink()
            except FileNotFoundError:
                pass
        self._temps.clear()


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
