"""The result every command's library call returns, and the one JSON shape `--json` prints of it.

A `CommandResult` says the files it wrote (`files`), the lines the command prints for
people (`summary_lines`), the warnings it tells on stderr (`warnings`), the refusals it
went on after (`refused`, which sets `exit_code`), and its own facts for scripts
(`details`). The CLI and `pdsgen batch` read only these, so a command's output needs no
code of its own there, and one JSON shape serves every command:

    {"command": "dtm", "files": [{"path": ..., "bytes": ...}], "warnings": [...], <details>}

(`files`: every file written, the shared ones - an orthoimage's JP2INFO.TXT - too.)

This module imports nothing of pdsgen: deliver, review, migrate and extras derive their
results from it without loading the product writers.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

# The members of every command's --json document; a command's own facts go beside them.
COMMON_MEMBERS = ("command", "files", "warnings")


class CommandResult(ABC):
    """What a command made. Results are dataclasses deriving from it, with fields of their own."""

    if TYPE_CHECKING:  # a field of most results, a property of some: the contract names it only
        @property
        def warnings(self) -> tuple[str, ...]:
            """What the command tells on stderr as `warning: ...` (the run goes on)."""

    @property
    @abstractmethod
    def files(self) -> tuple[Path, ...]:
        """Every file the command wrote, the main one first."""

    @property
    def shared_files(self) -> tuple[Path, ...]:
        """Files the command wrote that every product of a directory shares (an orthoimage's
        JP2INFO.TXT): named in its summary and in --json `files` as every file written is, but
        not its own (a later product rewrites them; a batch's resume leaves them out)."""
        return ()

    @property
    def written_files(self) -> tuple[Path, ...]:
        """Every file the command wrote: its own, then the shared ones."""
        return (*self.files, *self.shared_files)

    @property
    @abstractmethod
    def summary_lines(self) -> tuple[str, ...]:
        """What the command prints on stdout, line by line (nothing under --quiet or --json)."""

    @property
    def refused(self) -> tuple[str, ...]:
        """Refusals the command went on after (one product of several): told on stderr, exit status 2."""
        return ()

    @property
    def exit_code(self) -> int:
        """The command's exit status: 2 when something was refused, else 0."""
        return 2 if self.refused else 0

    def details(self) -> dict[str, Any]:
        """The command's own facts for scripts (product ID, counts ...), JSON-ready, beside the
        common members of `as_json` and never named as one of them."""
        return {}

    def as_json(self, command: str) -> dict[str, Any]:
        """The --json document of this result: `COMMON_MEMBERS` first, then `details()`.

        Each file is {"path", "bytes"} (what a script needs to pick it up), so this is called
        while the files are still where `files` says (an s3:// output's staging directory)."""
        facts = self.details()
        taken = sorted(set(facts) & set(COMMON_MEMBERS))
        if taken:
            raise ValueError(f"{type(self).__name__}.details() names common member(s) {', '.join(taken)}")
        return {"command": command, "files": files_json(self.written_files), "warnings": list(self.warnings), **facts}


def written_line(files: Sequence[Path], facts: Iterable[str]) -> str:
    """The one summary form of the commands that make products (dtm, ortho, mosaic, migrate):
    the main file's path, the name of every other file written (its path when it is elsewhere),
    then what was made - `delivery/X.JP2  X.LBL: 400 x 300 (lines x samples), 8-bit ...`."""
    main, *others = files
    named = [path.name if path.parent == main.parent else str(path) for path in others]
    return "  ".join([str(main), *named]) + ": " + ", ".join(facts)


def finding_counts(errors: int, warnings: int, info: int) -> dict[str, int]:
    """A run's findings counted by severity, as every --json document names them: keyed by the
    validator's severities, so `warnings` stays the command's list of warnings everywhere."""
    return {"error": errors, "warning": warnings, "info": info}


def files_json(paths: Iterable[Path]) -> list[dict[str, Any]]:
    """Each file as {"path", "bytes"}."""
    return [{"path": str(path), "bytes": path.stat().st_size} for path in paths]


__all__ = ["CommandResult", "files_json", "finding_counts", "written_line"]
