"""The one clock of every date pdsgen writes into a product, a delivery or a page.

Products must be byte-reproducible: the same input makes the same bytes on any day. The
reproducible-builds convention for that is SOURCE_DATE_EPOCH, a whole number of seconds
since 1970-01-01T00:00:00Z: when it is set, it *is* the time of making, and nothing pdsgen
writes depends on the wall clock (https://reproducible-builds.org/specs/source-date-epoch/).
When it is not set, the time of making is now, in UTC.

Every date written goes through `now()` (or `today()`, `timestamp()`): the iMars ProcessingDate
and its footprint shapefile's .dbf header, a delivery's publication dates and citation years, a
migrated volume's documents, the review page's time of making. `tests/test_reproducible.py`
keeps it so: no other module reads the wall clock for a date.

A malformed SOURCE_DATE_EPOCH is refused (the convention asks a tool to fail rather than guess),
in one line naming the variable.
"""

from __future__ import annotations

import datetime as _dt
import os
import time

from .errors import ParamsError

VARIABLE = "SOURCE_DATE_EPOCH"
# The largest epoch a four-digit year can show (9999-12-31T23:59:59Z): beyond it no date field
# of PDS3, PDS4 or a .dbf header can hold the time.
_LAST_SECOND = 253402300799


def source_date_epoch() -> int | None:
    """SOURCE_DATE_EPOCH as seconds, None when unset or empty; a value that is not a whole
    number of seconds within the four-digit years is a ParamsError."""
    text = os.environ.get(VARIABLE, "").strip()
    if not text:
        return None
    if not text.isascii() or not text.isdigit() or len(text) > 12 or int(text) > _LAST_SECOND:
        raise ParamsError(None, f"{VARIABLE}={text[:40]!r} is not a whole number of seconds since "
                                "1970-01-01 (the reproducible-builds convention); unset it or give one")
    return int(text)


def now() -> _dt.datetime:
    """The time of making, UTC, to the second: SOURCE_DATE_EPOCH when set, else the wall clock."""
    epoch = source_date_epoch()
    seconds = int(time.time()) if epoch is None else epoch
    return _dt.datetime.fromtimestamp(seconds, _dt.timezone.utc)


def today() -> str:
    """The day of making, YYYY-MM-DD (UTC)."""
    return now().date().isoformat()


def timestamp() -> str:
    """The time of making as YYYY-MM-DDThh:mm:ssZ (UTC)."""
    return now().strftime("%Y-%m-%dT%H:%M:%SZ")


def no_later_than_epoch(seconds: float) -> _dt.datetime:
    """A file's own time (a label's modification time, say), clamped to SOURCE_DATE_EPOCH when
    that is set: a reproducible build states no time later than its own (the convention's
    'clamping'), so a file touched after the epoch reads as made at the epoch."""
    epoch = source_date_epoch()
    whole = int(seconds)
    return _dt.datetime.fromtimestamp(whole if epoch is None else min(whole, epoch), _dt.timezone.utc)


def wall_time() -> str:
    """The wall clock, for what is about a run and never part of a product (a batch job's log
    header): local time, YYYY-MM-DD hh:mm:ss."""
    return time.strftime("%Y-%m-%d %H:%M:%S", time.localtime(time.time()))
