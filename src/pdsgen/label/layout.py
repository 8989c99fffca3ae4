"""Lay out label statements as archive users expect to read them.

The templates emit one statement per line (``KEY = VALUE``, ``OBJECT = X``,
comments, blank lines) with no concern for indentation or width. This module
indents by nesting, aligns the ``=`` signs of each block, wraps long quoted
strings and sequences onto continuation lines, and enforces the hard rules:
7-bit ASCII, no tabs, at most 78 characters before the CR LF.
"""

from __future__ import annotations

import re

from ..errors import ParamsError
from .grammar import MAX_LINE_CHARS

MAX_CONTENT = MAX_LINE_CHARS  # characters per line before CR LF (80 bytes in all)
INDENT = "  "

_STATEMENT_RE = re.compile(r"^(?P<key>\^?[A-Za-z][A-Za-z0-9_:]*)\s*=\s*(?P<value>.*)$")
_OPENERS = ("OBJECT", "GROUP")
_CLOSERS = ("END_OBJECT", "END_GROUP")


class LabelLayoutError(ParamsError):
    """The statements cannot be laid out within the PDS line rules (e.g. a params value
    with a word longer than a line): one line for the user, not a traceback."""

    def __init__(self, problem: str) -> None:
        super().__init__(None, problem)


def layout_label(text: str) -> str:
    """Turn template output into final label text with CR LF line ends."""
    lines = [line.strip() for line in text.replace("\r\n", "\n").split("\n")]
    while lines and not lines[-1]:
        lines.pop()
    out = _indent_and_align(lines)
    for line in out:
        _check_line(line)
    return "\r\n".join(out) + "\r\n"


def _indent_and_align(lines: list[str]) -> list[str]:
    """Indent by depth and align '=' within each run of same-depth statements.

    Comments sit inside a run without breaking its alignment (as in released
    HiRISE labels); blank lines, OBJECT/GROUP lines and END end a run.
    """
    out: list[str] = []
    depth = 0
    block: list[tuple[int, str | None, str]] = []  # (depth, key or None for a comment, value)

    def flush() -> None:
        if not block:
            return
        width = max((len(key) for _, key, _ in block if key is not None), default=0)
        for level, key, value in block:
            if key is None:
                out.append(INDENT * level + value)
            else:
                out.extend(_statement_lines(level, key.ljust(width), value))
        block.clear()

    for line in lines:
        match = _STATEMENT_RE.match(line)
        if line.startswith("/*"):
            block.append((depth, None, line))
            continue
        if not line or match is None:
            flush()
            if line == "END":
                if depth != 0:
                    raise LabelLayoutError("END reached inside an open OBJECT or GROUP")
                out.append("END")
            else:
                out.append(line)
            continue
        key, value = match.group("key"), match.group("value").strip()
        if key in _OPENERS:
            flush()
            out.append(f"{INDENT * depth}{key} = {value}")
            depth += 1
        elif key in _CLOSERS:
            flush()
            depth -= 1
            if depth < 0:
                raise LabelLayoutError(f"{key} without a matching opener")
            out.append(f"{INDENT * depth}{key} = {value}")
        else:
            block.append((depth, key, value))
    flush()
    if depth != 0:
        raise LabelLayoutError("unbalanced OBJECT/GROUP in label")
    return out


def _statement_lines(level: int, padded_key: str, value: str) -> list[str]:
    head = f"{INDENT * level}{padded_key} = "
    if len(head) + len(value) <= MAX_CONTENT:
        return [head + value]
    column = len(head) if len(head) <= MAX_CONTENT // 2 else len(INDENT * (level + 1))
    if value.startswith('"'):
        pieces = _wrap_words(value, len(head), column)
    elif value.startswith("("):
        pieces = _wrap_sequence(value, len(head), column)
    else:
        raise LabelLayoutError(f"value of {padded_key.strip()} is too long for one line: {value}")
    return [head + pieces[0]] + [" " * column + piece for piece in pieces[1:]]


def _wrap_words(value: str, first_column: int, column: int) -> list[str]:
    """Break a quoted string at spaces; the reader joins continuation lines."""
    return _greedy(value.split(" "), " ", first_column, column)


def _wrap_sequence(value: str, first_column: int, column: int) -> list[str]:
    """Break a sequence after its commas, never inside an element."""
    items = value.split(", ")
    return _greedy(items, ", ", first_column, column, keep_separator=True)


def _greedy(
    words: list[str], sep: str, first_column: int, column: int, keep_separator: bool = False
) -> list[str]:
    pieces: list[str] = []
    current = ""
    width = MAX_CONTENT - first_column
    for index, word in enumerate(words):
        token = word + (sep.rstrip() if keep_separator and index < len(words) - 1 else "")
        candidate = f"{current}{' ' if current else ''}{token}" if current else token
        if len(candidate) <= width or not current:
            current = candidate
        else:
            pieces.append(current)
            current = token
            width = MAX_CONTENT - column
    pieces.append(current)
    for piece in pieces:
        if len(piece) > MAX_CONTENT - column and piece is not pieces[0]:
            raise LabelLayoutError(f"cannot wrap label value within {MAX_CONTENT} characters")
    return pieces


def _check_line(line: str) -> None:
    if len(line) > MAX_CONTENT:
        raise LabelLayoutError(f"label line longer than {MAX_CONTENT} characters: {line}")
    if not line.isascii() or "\t" in line:
        raise LabelLayoutError(f"label line is not 7-bit ASCII without tabs: {line!r}")
