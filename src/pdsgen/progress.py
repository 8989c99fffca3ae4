"""Progress on long work: a bar for a person at a terminal, silence everywhere else.

The rule lives here and nowhere else (`wanted`): progress is shown only when stderr is
a terminal and the command was not asked for --quiet or --json; and a bar is drawn
only for large work (`LARGE_WORK_PIXELS`), where it would not merely flicker. Piped or
redirected, commands print no carriage-return noise into logs and CI output.

Library loops (the DTM strip writer, the JP2 tile encoder) call `advance(done, total)`.
That does nothing unless a command installed a reporter with `reporting(...)`, so
`write_dtm` and `write_ortho` called from Python never write to stderr on their own,
and the cost of a call is one context-variable look-up per strip or tile.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from typing import Protocol, TextIO

LARGE_WORK_PIXELS = 4_000_000  # a 2000 x 2000 raster: below it a conversion takes about a second
REDRAW_SECONDS = 0.1
BAR_WIDTH = 30


class Reporter(Protocol):
    def __call__(self, done: int, total: int, unit: str) -> None: ...


_REPORTER: ContextVar[Reporter | None] = ContextVar("pdsgen_progress", default=None)


def wanted(quiet: bool = False, as_json: bool = False, stream: TextIO | None = None) -> bool:
    """Whether a command shows progress: stderr is a terminal, and neither --quiet nor --json."""
    stream = stream if stream is not None else sys.stderr
    return not quiet and not as_json and stream.isatty()


def is_large(pixels: int, items: int = 1) -> bool:
    """Work worth a bar: rasters of LARGE_WORK_PIXELS or more, or several products at once."""
    return pixels >= LARGE_WORK_PIXELS or items > 1


@contextmanager
def reporting(reporter: Reporter | None) -> Iterator[None]:
    """Send the progress of library loops inside this block to `reporter` (None: nowhere)."""
    token = _REPORTER.set(reporter)
    try:
        yield
    finally:
        _REPORTER.reset(token)


def advance(done: int, total: int, unit: str) -> None:
    """Tell the installed reporter, if any, that `done` of `total` units are finished."""
    reporter = _REPORTER.get()
    if reporter is not None:
        reporter(done, total, unit)


def bar_text(done: int, total: int) -> str:
    """`[#####.....]`: the share of `total` that is `done`, the one bar every command draws."""
    filled = BAR_WIDTH * min(done, total) // max(1, total)
    return f"[{'#' * filled}{'.' * (BAR_WIDTH - filled)}]"


class TerminalBar:
    """One line on stderr, redrawn at most ten times a second, cleared when the work ends.

    A total of 0 means it is not known yet (files found while they are checked): the
    line is then a count.
    """

    def __init__(self, stream: TextIO | None = None) -> None:
        self.stream = stream if stream is not None else sys.stderr
        self.drawn_at = 0.0
        self.visible = False

    def __call__(self, done: int, total: int, unit: str) -> None:
        now = time.monotonic()
        finished = 0 < total <= done
        if not finished and now - self.drawn_at < REDRAW_SECONDS:
            return
        self.drawn_at = now
        if total > 0:
            self.stream.write(f"\r\033[K{bar_text(done, total)} {100 * done // total:3d}%  {done}/{total} {unit}")
        else:
            self.stream.write(f"\r\033[K{done} {unit}")
        self.visible = not finished
        if finished:
            self.stream.write("\r\033[K")  # leave the line to the result
        self.stream.flush()

    def close(self) -> None:
        """Clear a bar left drawn by work that stopped early (an error, Ctrl-C)."""
        if self.visible:
            self.stream.write("\r\033[K")
            self.stream.flush()
            self.visible = False


@contextmanager
def terminal_bar(show: bool) -> Iterator[None]:
    """Library progress inside this block drawn on stderr when `show` (see `wanted`)."""
    bar = TerminalBar() if show else None
    try:
        with reporting(bar):
            yield
    finally:
        if bar is not None:
            bar.close()
