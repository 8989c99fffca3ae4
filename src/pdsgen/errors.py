"""The one exception type that means "the user gave us something we cannot use".

The CLI turns it into a single line on stderr and exit code 2; anything else that
escapes is a bug in pdsgen and keeps its traceback.
"""

from __future__ import annotations

import os


class PdsgenError(Exception):
    """A user-facing problem with one file (input, output or parameters)."""

    def __init__(self, path: str | os.PathLike[str] | None, problem: str) -> None:
        self.path = os.fspath(path) if path is not None else None
        self.problem = problem
        super().__init__(str(self))

    def __str__(self) -> str:
        if self.path is None:
            return self.problem
        return f"{self.path}: {self.problem}"


def param(name: str, value: object = None) -> str:
    """A library parameter as a message names it, in Python's words: `product_id`, or
    with the value to give, `kind='dtm'` / `overwrite=True`.

    Messages are read by Python callers and by command-line users alike; the command
    line turns each such reference into its own option (--product-id, --kind dtm,
    --overwrite) with the one table in pdsgen.cli._messages, so neither interface
    speaks the other's words.
    """
    return f"`{name}`" if value is None else f"`{name}={value!r}`"


class InputError(PdsgenError, ValueError):
    """An input file cannot be used (missing, unreadable, wrong content)."""


class OutputError(PdsgenError, OSError):
    """An output cannot be written (exists without --overwrite, unwritable directory)."""

    def __init__(self, path: str | os.PathLike[str] | None, problem: str) -> None:
        PdsgenError.__init__(self, path, problem)


class ParamsError(PdsgenError, ValueError):
    """An option or parameter value is unusable (unknown keyword, bad version, unused option)."""


__all__ = ["InputError", "OutputError", "ParamsError", "PdsgenError", "param"]
