"""What `pdsgen extras` made, as every command's result says it (`CommandResult`).

`make_extras` returns the paths it wrote (a list, what its callers iterate); the command
line and `pdsgen batch` take them as an `ExtrasResult`, told one path per line.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

from ..results import CommandResult
from .readme_txt import README_NAME


@dataclass(frozen=True)
class ExtrasResult(CommandResult):
    """The Extras written, in the order `make_extras` returns them; Extras keep no warnings."""

    written: tuple[Path, ...]
    warnings: tuple[str, ...] = ()

    @classmethod
    def of(cls, written: Iterable[Path]) -> ExtrasResult:
        return cls(tuple(written))

    @property
    def files(self) -> tuple[Path, ...]:
        return self.written

    @property
    def summary_lines(self) -> tuple[str, ...]:
        return tuple(str(path) for path in self.written)

    @property
    def directory_files(self) -> tuple[Path, ...]:
        """The files describing the whole directory (README.TXT), which later calls rewrite."""
        return tuple(path for path in self.written if path.name == README_NAME)


__all__ = ["ExtrasResult"]
