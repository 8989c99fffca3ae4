"""The one bounded reader of structured input, and the one check of a count against bytes.

Every structured file a user hands pdsgen - TOML (params, --config, pdsgen.toml, delivery
text, batch manifests), JSON (baselines, footprints, iMars sidecars), PVL (params) - is read
here and nowhere else, within bounds that hold whatever the file says:

- regular files only: a FIFO, a device (/dev/zero) or a directory is refused in one line
  without being waited on or read (the file is opened non-blocking and asked what it is);
- a size cap (MAX_BYTES unless the caller names a smaller one), checked while reading, so a
  file that grows or lies about its size is never read past it;
- a nesting cap (MAX_DEPTH tables, arrays, objects or groups) and an integer-length cap
  (MAX_INT_DIGITS digits), checked by one walk of what the parser returned; a parser that
  recurses past Python's limit or refuses an integer of thousands of digits on its own is
  turned into the same one line;
- linear time: the parsers used (tomllib, json, pvl on a size-capped text) do not backtrack.

Every refusal is an InputError naming the file: the command line prints it as one line and
exits 2. `checked_count` is the other half of "bounded whatever a file declares": a count or
size read from a file (a tag's value count, ROW_BYTES, a box length) is compared with the
bytes really there before anything of that size is allocated.

A top-level module (the ground under every floor): params.py reads TOML here, and so does
every folder.
"""

from __future__ import annotations

import errno
import math
import os
import stat
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any, BinaryIO

from .errors import InputError

MAX_BYTES = 16 * 1024 * 1024
MAX_DEPTH = 32
MAX_INT_DIGITS = 100
MAX_LINE = 64 * 1024  # characters of one line text_lines yields
_INT_BITS = math.ceil(MAX_INT_DIGITS * math.log2(10))
_INT_BOUND = 10 ** MAX_INT_DIGITS


def read_bytes(path: str | os.PathLike[str], limit: int = MAX_BYTES, what: str = "file") -> bytes:
    """The bytes of PATH, a regular file of at most LIMIT bytes, else InputError (one line).

    Opened with O_NONBLOCK so a FIFO is refused rather than waited on; fstat of the open file
    decides (no window between a check and the open)."""
    chunks, size = [], 0
    with _open_input(path, what) as stream:
        try:
            while size <= limit:
                chunk = stream.read(min(1 << 20, limit + 1 - size))
                if not chunk:
                    break
                chunks.append(chunk)
                size += len(chunk)
        except OSError as exc:
            raise InputError(path, f"cannot be read ({exc.strerror or exc})") from None
    if size > limit:
        raise InputError(path, f"is larger than {limit} bytes, more than a {what} of this kind holds")
    return b"".join(chunks)


def text_lines(path: str | os.PathLike[str], what: str = "file", encoding: str = "latin-1",
               line_limit: int = MAX_LINE) -> Iterator[str]:
    """The lines of PATH, a regular file, streamed without their line ends: memory holds one line
    whatever the file's size (a line longer than LINE_LIMIT characters is cut there and its rest
    skipped), time is linear. For line-oriented text a delivery carries (manifests, inventories,
    README.TXT, JP2INFO.TXT) that may be larger than MAX_BYTES yet must never be waited on (a
    FIFO) or held whole. Not a regular file, or unreadable: InputError naming it, raised by this
    call (before any line is asked for)."""
    return _lines(_open_input(path, what), encoding, line_limit)


def _lines(stream: BinaryIO, encoding: str, line_limit: int) -> Iterator[str]:
    with stream:
        while line := stream.readline(line_limit + 1):
            if len(line) > line_limit and not line.endswith(b"\n"):
                while (rest := stream.readline(1 << 20)) and not rest.endswith(b"\n"):
                    pass  # the rest of an over-long line, read past in bounded pieces
            yield line[:line_limit].rstrip(b"\r\n").decode(encoding, errors="replace")


class NotRegularFile(OSError):
    """What open_regular raises for a path that is there but no regular file: `kind` says what
    it is ("a directory", "a FIFO", "a device", "not a regular file")."""

    def __init__(self, path: str | os.PathLike[str], kind: str) -> None:
        told = f"is {kind}, not a regular file" if kind != "not a regular file" else "is not a regular file"
        super().__init__(errno.EISDIR if kind == "a directory" else errno.EINVAL, told, os.fspath(path))
        self.kind = kind


def open_regular(path: str | os.PathLike[str]) -> BinaryIO:
    """PATH opened for reading in binary when it is a regular file; OSError otherwise
    (NotRegularFile for a directory, FIFO or device, as the open file's fstat tells: no window
    between a check and the open). Opened without blocking, so a FIFO under any name is refused
    rather than waited on, then read as usual. The one such open: every reader of a file a tree
    or a label names goes through it (the bounded readers below, label heads, sniffing)."""
    descriptor = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    try:
        mode = os.fstat(descriptor).st_mode
        if not stat.S_ISREG(mode):
            raise NotRegularFile(path, "a directory" if stat.S_ISDIR(mode) else "a FIFO" if stat.S_ISFIFO(mode)
                                 else "a device" if stat.S_ISCHR(mode) or stat.S_ISBLK(mode)
                                 else "not a regular file")
        os.set_blocking(descriptor, True)
        return os.fdopen(descriptor, "rb")
    except BaseException:
        os.close(descriptor)
        raise


def _open_input(path: str | os.PathLike[str], what: str) -> BinaryIO:
    """open_regular, its refusals as the one-line InputError naming PATH and WHAT it should be."""
    try:
        return open_regular(path)
    except FileNotFoundError:
        raise InputError(path, f"no such {what}") from None
    except NotRegularFile as exc:
        raise InputError(path, f"is {exc.kind}, not a regular {what}") from None
    except OSError as exc:
        raise InputError(path, f"cannot be read ({exc.strerror or exc})") from None


def read_text(path: str | os.PathLike[str], limit: int = MAX_BYTES, what: str = "file",
              encoding: str = "utf-8") -> str:
    """The text of PATH (bounded as `read_bytes`), refused in one line when not ENCODING."""
    data = read_bytes(path, limit, what)
    try:
        return data.decode(encoding)
    except UnicodeDecodeError as exc:
        raise InputError(path, f"is not {encoding.upper()} text (byte {exc.start})") from None


def load_toml(path: str | os.PathLike[str], limit: int = MAX_BYTES, what: str = "TOML file") -> dict[str, Any]:
    """A TOML file's table, bounded; InputError for anything else, naming the file."""
    return parse_toml(path, read_text(path, limit, what))


def parse_toml(source: str | os.PathLike[str], text: str) -> dict[str, Any]:
    """TEXT (read from SOURCE within the size cap) as TOML, within the nesting and integer caps."""
    from ._compat import tomllib  # the parser is start-up time: only where a TOML file is read

    return _parsed(source, "TOML", lambda: tomllib.loads(text), (tomllib.TOMLDecodeError, ValueError))


def load_json(path: str | os.PathLike[str], limit: int = MAX_BYTES, what: str = "JSON file") -> Any:
    """A JSON file's value, bounded (NaN and Infinity, not JSON, are refused too)."""
    return parse_json(path, read_text(path, limit, what))


def parse_json(source: str | os.PathLike[str], text: str) -> Any:
    """TEXT (read from SOURCE within the size cap) as JSON, within the nesting and integer caps."""
    import json

    def refuse_constant(name: str) -> Any:
        raise ValueError(f"{name} is not a JSON value")

    return _parsed(source, "JSON", lambda: json.loads(text, parse_constant=refuse_constant), (ValueError,))


def load_pvl(path: str | os.PathLike[str], limit: int = MAX_BYTES, what: str = "PVL file") -> Any:
    """A PVL file's module (pvl's mapping), bounded; nesting is checked on the text first,
    since pvl's parser recurses per group and per set."""
    return parse_pvl(path, read_text(path, limit, what, encoding="latin-1"))


def parse_pvl(source: str | os.PathLike[str], text: str) -> Any:
    """TEXT (read from SOURCE within the size cap) as PVL, within the nesting and integer caps."""
    import pvl  # most runs read no PVL: it is imported where one is

    _check_pvl_nesting(source, text)
    errors = (pvl.exceptions.ParseError, pvl.exceptions.LexerError, ValueError, TypeError, KeyError)
    return _parsed(source, "PVL", lambda: pvl.loads(text), errors)


def _parsed(path: str | os.PathLike[str], kind: str, parse: Callable[[], Any],
            errors: tuple[type[BaseException], ...]) -> Any:
    try:
        value = parse()
    except RecursionError:
        raise InputError(path, f"is nested deeper than {MAX_DEPTH} levels") from None
    except errors as exc:
        if "integer string conversion" in str(exc):  # Python's own cap on int(text), met first
            raise InputError(path, f"holds an integer longer than {MAX_INT_DIGITS} digits") from None
        # the parser's error stays the cause: a validator finding takes its line number
        raise InputError(path, f"not valid {kind} ({first_line(exc)})") from exc
    check_structure(path, value)
    return value


def first_line(exc: BaseException) -> str:
    """An exception's message as one line (its type when it says nothing)."""
    text = str(exc).strip()
    return text.splitlines()[0] if text else type(exc).__name__


def check_structure(path: str | os.PathLike[str], value: Any) -> None:
    """Refuse VALUE (what a parser read from PATH) nested deeper than MAX_DEPTH or holding an
    integer longer than MAX_INT_DIGITS digits; one walk, without recursion."""
    stack: list[tuple[Any, int]] = [(value, 0)]
    while stack:
        item, depth = stack.pop()
        if isinstance(item, bool):
            continue
        if isinstance(item, int):
            if item.bit_length() > _INT_BITS or abs(item) >= _INT_BOUND:
                raise InputError(path, f"holds an integer longer than {MAX_INT_DIGITS} digits")
        elif isinstance(item, dict) or hasattr(item, "items") and not isinstance(item, (str, bytes)):
            if depth >= MAX_DEPTH:
                raise InputError(path, f"is nested deeper than {MAX_DEPTH} levels")
            stack.extend((part, depth + 1) for pair in item.items() for part in pair)
        elif isinstance(item, (list, tuple, set, frozenset)):
            if depth >= MAX_DEPTH:
                raise InputError(path, f"is nested deeper than {MAX_DEPTH} levels")
            stack.extend((part, depth + 1) for part in item)


_PVL_OPEN = ("BEGIN_OBJECT", "BEGIN_GROUP", "OBJECT", "GROUP")


def _check_pvl_nesting(path: str | os.PathLike[str], text: str) -> None:
    """Refuse PVL nesting OBJECT/GROUP blocks, or sets and sequences, deeper than MAX_DEPTH:
    one pass over the text, quoted strings and comments skipped."""
    depth = block = 0
    i, n = 0, len(text)
    word_start = -1
    while i < n:
        c = text[i]
        if c in "\"'":
            end = text.find(c, i + 1)
            i = n if end < 0 else end + 1
            continue
        if c == "/" and text.startswith("/*", i):
            end = text.find("*/", i + 2)
            i = n if end < 0 else end + 2
            continue
        if c in "({":
            depth += 1
        elif c in ")}":
            depth = max(depth - 1, 0)
        elif c == "=" and word_start >= 0:
            word = text[word_start:i].strip().upper()
            if word in _PVL_OPEN:
                block += 1
            elif word.startswith("END_"):
                block = max(block - 1, 0)
        if c == "\n":
            word_start = i + 1
        elif c == "=":
            word_start = -1
        if depth > MAX_DEPTH or block > MAX_DEPTH:
            raise InputError(path, f"is nested deeper than {MAX_DEPTH} levels")
        i += 1


def checked_count(source: str | os.PathLike[str], what: str, count: int, item_bytes: int, available: int) -> int:
    """COUNT items of ITEM_BYTES each, as a file at SOURCE declares them, refused (InputError,
    one line) when they need more than the AVAILABLE bytes really there - before anything of
    that size is allocated or read. Negative counts are refused too."""
    if count < 0 or item_bytes < 0:
        raise InputError(source, f"{what} declares a negative size ({count} x {item_bytes} bytes)")
    needed = count * item_bytes
    if needed > max(available, 0):
        raise InputError(source, f"{what} declares {count} x {item_bytes} bytes ({needed} bytes), "
                                 f"but only {max(available, 0)} bytes are there")
    return count


def file_size(path: str | os.PathLike[str]) -> int:
    """The size of a file a count is checked against (0 when it cannot be asked)."""
    try:
        return Path(path).stat().st_size
    except OSError:
        return 0


__all__ = ["MAX_BYTES", "MAX_DEPTH", "MAX_INT_DIGITS", "check_structure", "checked_count", "file_size",
           "first_line", "load_json", "load_pvl", "load_toml", "parse_json", "parse_pvl", "parse_toml", "read_bytes",
           "read_text"]
