"""How a batch tells people where it is: a bar on a terminal, plain lines otherwise.

On a terminal one line is redrawn (jobs done, failed, running, throughput); in CI,
where a redrawn line is noise in the log, each finished job is one plain line.
Failures are always printed in full, on their own line.
"""

from __future__ import annotations

import sys
import time
from typing import Any, TextIO

from ..progress import bar_text


class Progress:
    def __init__(self, total: int, stream: TextIO | None = None, bar: bool | None = None) -> None:
        self.stream = stream or sys.stderr
        self.bar = self.stream.isatty() if bar is None else bar
        self.total = total
        self.counts = {"done": 0, "skipped": 0, "failed": 0, "blocked": 0}
        self.running = 0
        self.start = time.monotonic()

    def started(self) -> None:
        self.running += 1
        self._draw()

    def finished(self, outcome: dict[str, Any], kind: str, was_running: bool = True) -> None:
        self.running -= was_running
        status = outcome["status"]
        self.counts[status] += 1
        if status in ("failed", "blocked"):
            self._line(f"{status.upper():<8}{kind:<9}{outcome['id']}: {outcome['error']}")
        elif not self.bar:
            self._line(f"{status:<8}{kind:<9}{outcome['id']}  {outcome['seconds']:.1f} s")
        self._draw()

    def note(self, text: str) -> None:
        self._line(text)

    def close(self) -> None:
        if self.bar:
            self.stream.write("\r\033[K")
            self.stream.flush()

    def _finished_count(self) -> int:
        return sum(self.counts.values())

    def _line(self, text: str) -> None:
        if self.bar:
            self.stream.write("\r\033[K")
        self.stream.write(text + "\n")
        self.stream.flush()

    def _draw(self) -> None:
        if not self.bar:
            return
        finished = self._finished_count()
        elapsed = time.monotonic() - self.start
        rate = (self.counts["done"] / elapsed * 60) if elapsed > 0 else 0.0
        self.stream.write(
            f"\r\033[K{bar_text(finished, self.total)} {finished}/{self.total}  "
            f"done {self.counts['done'] + self.counts['skipped']}  failed {self.counts['failed']}  "
            f"running {self.running}  {rate:.1f} jobs/min")
        self.stream.flush()
