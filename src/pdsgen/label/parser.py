"""The PDS3 (ODL) label reader: text -> `Label` tree, with line numbers and reading problems.

pvl is both too lenient (it accepts an unquoted value with spaces) and too strict (one
error stops it, with no line to show) for a validator, so labels are read here with a
small hand-written reader, the one every part of pdsgen that reads a PDS3 label uses
(pvl stays for iMars PVL). It tolerates what real archives do (LF-only lines,
`Object`/`End_Object`, unquoted `MEX-M-HRSC-3-RDR-V2.0`, `2575.0<KM>`, `0015`,
`1737400.`, unnamed END_OBJECT, inline comments) and records each real problem as an
`Issue` tagged with its SYNTAX/FILE rule id, then carries on with the next line, so
one bad statement never hides the rest of the label.

Three parts: the scanner (the tokens of label text and its physical lines), the parser
(tokens -> `Label` tree, tree.py), and the one END rule on bytes with the reading of a
file's label head that stops at it - what every reader of a label file uses, so all agree
on where a label ends. (One module: writing a product loads the reader, and each module
is start-up time, see tests/test_cli_startup.py.)
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass, replace
from functools import cached_property
from itertools import accumulate, repeat
from pathlib import Path
from typing import BinaryIO

from ..bounded import open_regular
from .grammar import IDENTIFIER_PATTERN
from .tree import (
    Block,
    Issue,
    Label,
    Line,
    Pointer,
    Statement,
    Value,
    first_statement,
    first_text,
    image_object,
    label_pointers,
    projection_object,
)

# -- the scanner ----------------------------------------------------------------------

NEWLINE = re.compile(r"\r\n|\n|\r")
_WORD = re.compile(r"(?:[^\s=(){},;\"'<>/]|/(?!\*))+")
_UNIT = re.compile(r"<[^<>\r\n]*>")
_SYMBOL = re.compile(r"'[^'\r\n]*'")
NOT_TEXT = re.compile(r"[^\x20-\x7e\t]")
class Token:
    __slots__ = ("kind", "text", "line", "end_line", "start", "end", "issues")

    def __init__(self, kind: str, text: str, line: int, end_line: int, start: int, end: int,
                 issues: list[Issue] | None = None) -> None:
        self.kind = kind  # word, string, symbol, unit, punct, eof, bad
        self.text = text
        self.line = line
        self.end_line = end_line  # the line (and `end` the offset) where reading goes on after it
        self.start = start
        self.end = end
        self.issues = issues  # what scanning it found, reported each time the parser reads it


_SKIP = re.compile(r"(?:[ \t\f\v\x00]+|\r\n|\n|\r|/\*.*?\*/)+", re.S)

# One pattern reads the blanks, line ends and comments before a token and the token itself,
# so a token costs one regex call. The alternatives after the skip part cover every
# character (1-5 the tokens, 6 any other character, 7 the end of the text), so a match
# never backtracks into the skip part: it skips exactly what _SKIP skips. Group 6 (an
# unclosed quote, comment, symbol or unit, a character no token takes) goes to the
# character-by-character path, which reports it.
_TOKEN = re.compile(
    r"(?:[ \t\f\v\x00\r\n]+|/\*.*?\*/)*"
    r"(?:(\"[^\"]*\")"  # 1 string
    r"|([=(){},;])"  # 2 punct
    r"|('[^'\r\n]*')"  # 3 symbol
    r"|(<[^<>\r\n]*>)"  # 4 unit
    r"|((?:[^\s=(){},;\"'<>/]+|/(?!\*))+)"  # 5 word (as _WORD)
    r"|(.)"  # 6 anything else: the careful path
    r"|())",  # 7 end of text
    re.S,
)
_KINDS = ("", "string", "punct", "symbol", "unit", "word", "", "eof")  # by _TOKEN group
_BLANKS = r"[ \t\f\v\x00]*"
_SPACE = r"[ \t\f\v\x00\r\n]*"
_WORD_CHAR = r"[^\s=(){},;\"'<>/]"
# A word as _WORD reads it, written `A*(/A*)*` so it matches a text one way only, and not
# starting with NUL: NUL is a blank between tokens but part of a word (as _TOKEN reads it).
_WORD_ONCE = r"(?=[^\s=(){},;\"'<>/\x00]|/(?!\*))" + _WORD_CHAR + r"*(?:/(?!\*)" + _WORD_CHAR + "*)*"
_ITEM = r"(?:\"[^\"]*\"|'[^'\r\n]*'|" + _WORD_ONCE + ")"
# A statement as most labels write nearly all of theirs: `KEYWORD = value [<unit>]` alone on
# its line(s), maybe with closed comments after it, and no `<unit>` or comment starting the
# next line; the value a word, a quoted text or symbol, or a sequence/set of those (no
# comments, units or nesting inside). The parser takes such a statement in one match (see
# _Parser._simple); anything else goes token by token. No part can match a text in two ways
# (a comment cannot contain `*/`), so a failing match costs one pass, never backtracking
# that grows with the text.
_SIMPLE = re.compile(
    _BLANKS  # only blanks before it: line ends and comments are skipped first (simple_statement)
    + r"(?P<keyword>\^?(?:(?P<namespace>[A-Za-z][A-Za-z0-9_]*):)?(?P<name>[A-Za-z][A-Za-z0-9_]*))"
    r"(?!\x00)"  # the whole word
    + _BLANKS + "=" + _BLANKS
    + r"(?:(?P<string>\"[^\"]*\")"
    r"|(?P<symbol>'[^'\r\n]*')"
    r"|(?P<word>" + _WORD_ONCE + ")"
    r"|(?P<items>[({](?:" + _SPACE + _ITEM + _SPACE + ",)*" + _SPACE + _ITEM + _SPACE + "[)}]))"
    + _BLANKS + r"(?:(?P<unit><[^<>\r\n]*>)"
    + _BLANKS + r")?(?:/\*(?:[^*\r\n]|\*(?!/))*\*/" + _BLANKS + r")*"
    r"(?P<eol>\r\n|\n|\r|\Z)(?![ \t\f\v\x00\r\n]*[</])"
)
ITEMS = re.compile(_SPACE + "(" + _ITEM + ")" + _SPACE + "[,)}]")


class Scanner:
    """Produces significant tokens on demand; whitespace, newlines and comments are skipped.

    `pos`/`line` say where reading goes on after the last token read. The last peeked
    token is remembered, so the parser's look-ahead costs one scan.
    """

    def __init__(self, text: str, issues: list[Issue]) -> None:
        self.text = text
        self.pos = 0
        self.line = 1
        self.issues = issues
        self._ahead: Token | None = None  # the token peeked at _ahead_from
        self._ahead_from = -1

    def mark(self) -> tuple[int, int]:
        return self.pos, self.line

    def reset(self, mark: tuple[int, int]) -> None:
        self.pos, self.line = mark

    def next(self) -> Token:
        tok = self._ahead
        if tok is None or self._ahead_from != self.pos:
            tok = self._scan()
        self._ahead = None
        self.pos, self.line = tok.end, tok.end_line
        if tok.issues:
            self.issues.extend(tok.issues)
        return tok

    def peek(self) -> Token:
        if self._ahead is None or self._ahead_from != self.pos:
            self._ahead, self._ahead_from = self._scan(), self.pos
        return self._ahead

    def skip_line(self) -> None:
        """Drop the rest of the current line (error recovery)."""
        self.pos = line_end(self.text, self.pos)
        self._ahead = None

    def simple_statement(self) -> tuple[re.Match[str], int] | None:
        """The match of a simple statement (see _SIMPLE) starting at the next token, with
        the line its keyword is on; nothing is read until `take` is called."""
        text, pos = self.text, self.pos
        m = _SIMPLE.match(text, pos)  # a statement at the start of the line the last one ended
        if m is not None:
            return m, self.line
        skip = _SKIP.match(text, pos)
        if skip is None:
            return None
        m = _SIMPLE.match(text, skip.end())
        if m is None:
            return None
        return m, self.line + count_lines(text, pos, skip.end())

    def take(self, m: re.Match[str], line: int) -> None:
        """Read past a simple statement matched on `line` and its line end."""
        value = m.group("string") or m.group("items")
        if value is not None and ("\n" in value or "\r" in value):  # they may span lines
            line += count_lines(value, 0, len(value))
        if m.group("eol"):
            line += 1
        self.pos, self.line = m.end(), line

    def _scan(self) -> Token:
        """The next token, by the one-pattern path when it applies."""
        text, pos, line = self.text, self.pos, self.line
        m = _TOKEN.match(text, pos)
        if m is None or m.lastindex is None:  # never: some alternative matches anywhere
            return self._scan_by_character(pos, line)
        group = m.lastindex
        start = m.start(group)
        if start > pos:  # blanks, line ends or comments before the token
            newlines = text.count("\n", pos, start)
            returns = text.count("\r", pos, start)
            if returns:
                newlines += returns - text.count("\r\n", pos, start)
            line += newlines
        if group == 6:
            return self._scan_by_character(start, line)
        end = m.end()
        if group == 1:  # a string may span lines
            return Token("string", m[1], line, line + count_lines(text, start, end), start, end)
        return Token(_KINDS[group], m[group], line, line, start, end)

    def _scan_by_character(self, pos: int, line: int) -> Token:
        """What _TOKEN does not take: unclosed quotes and comments, stray characters."""
        text = self.text
        issues: list[Issue] = []
        m = _SKIP.match(text, pos)
        if m:
            end = m.end()
            line += count_lines(text, pos, end)
            pos = end
        if text.startswith("/*", pos):  # a comment that never closes
            issues.append(Issue("SYNTAX-001", line, "comment '/*' is never closed"))
            line += count_lines(text, pos, len(text))
            pos = len(text)
        if pos >= len(text):
            return Token("eof", "", line, line, pos, pos, issues)
        ch = text[pos]
        if ch == '"':
            end = text.find('"', pos + 1)
            if end < 0:
                issues.append(Issue("SYNTAX-001", line, 'quoted text is never closed (missing ")'))
                end = line_end(text, pos)
                return Token("bad", text[pos:end], line, line, pos, end, issues)
            end_line = line + count_lines(text, pos, end)
            return Token("string", text[pos : end + 1], line, end_line, pos, end + 1, issues)
        if ch in "=(){},;":
            return Token("punct", ch, line, line, pos, pos + 1, issues)
        m = None
        if ch == "'":
            m = _SYMBOL.match(text, pos)
            kind = "symbol"
        elif ch == "<":
            m = _UNIT.match(text, pos)
            kind = "unit"
        if m is None:
            m = _WORD.match(text, pos)
            kind = "word"
        if m:
            return Token(kind, m.group(), line, line, pos, m.end(), issues)
        return Token("bad", ch, line, line, pos, pos + 1, issues)


def count_lines(text: str, start: int, end: int) -> int:
    chunk = text[start:end]
    return chunk.count("\n") + chunk.count("\r") - chunk.count("\r\n")


_EOL = re.compile(r"[\r\n]")


def line_end(text: str, pos: int) -> int:
    m = _EOL.search(text, pos)
    return m.start() if m else len(text)


_ENDINGS = {"\r\n": "CRLF", "\n": "LF", "\r": "CR"}


def split_lines(text: str, limit: int) -> list[Line]:
    """Physical lines of text[:limit] with their byte offsets and terminator kind."""
    body = text[:limit]
    newline = "\n" if "\r" not in body else "\r\n" if body.count("\r") == body.count("\r\n") == body.count("\n") else ""
    if not newline:  # mixed line ends: one at a time
        return _split_mixed_lines(text, limit)
    parts = body.split(newline)  # the last part follows the last line end
    step = len(newline)
    starts = list(accumulate((len(part) + step for part in parts), initial=0))
    ends = [start + len(part) for start, part in zip(starts[:-1], parts, strict=True)]
    count = len(parts) - 1
    lines = list(map(Line, range(1, count + 1), starts, ends, repeat(_ENDINGS[newline], count)))
    if parts[-1]:
        lines.append(Line(count + 1, starts[count], limit, ""))
    return lines


def _split_mixed_lines(text: str, limit: int) -> list[Line]:
    lines: list[Line] = []
    append = lines.append
    pos, number = 0, 1
    for m in NEWLINE.finditer(text, 0, limit):
        append(Line(number, pos, m.start(), _ENDINGS[m.group()]))
        pos, number = m.end(), number + 1
    if pos < limit:
        append(Line(number, pos, limit, ""))
    return lines


# -- the parser -----------------------------------------------------------------------

# an integer (group 1) or a real
_NUMBER = re.compile(r"[+-]?(?:(\d+)|(?:\d+\.\d*|\.\d+|\d+)(?:[eE][+-]?\d+)?)")
_BASED = re.compile(r"([+-]?)(\d+)#([^#]*)#")
_KEYWORD = re.compile(rf"\^?(?:({IDENTIFIER_PATTERN}):)?({IDENTIFIER_PATTERN})")
_DATE_START = re.compile(r"\d{1,4}-\d|\d{1,2}:\d")
_DATE = re.compile(
    r"(?P<year>\d{4})(?:-(?P<doy>\d{3})|-(?P<month>\d{2})(?:-(?P<day>\d{2}))?)"
    r"(?:T(?P<time>.*))?"
)
_TIME = re.compile(r"(?P<h>\d{2})(?::(?P<m>\d{2})(?::(?P<s>\d{2})(?:\.(?P<f>\d*))?)?)?(?P<z>Z)?")
# A CCSDS SFDU label (CCSDS 620.0-B-2; PDS Standards Reference chapter 16) is 20 characters:
# control authority (4), version (1), class (1), delimitation (1; a spare '0' in version 1),
# a spare '0', the description data unit id (4), and the length - or, for an SFDU delimited
# by a marker, the marker (8). PDS wraps a label in a CCSD Z-class SFDU followed by the
# label's own (NJPL3IF0PDS2..., or NJPL3KS0PDSX##mark## delimited by a marker).
_SFDU_LABEL = re.compile(r"([A-Z0-9]{4})([1-3])([A-Z0-9])([A-Z0-9])0([A-Z0-9]{4})(\S{8})")
_SFDU_DELIMITATIONS = {"A": "length in ASCII", "B": "binary length", "C": "marker", "S": "marker",
                       "E": "end of file", "F": "end of file"}
_DAYS = (31, 29, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31)
_BASE_DIGITS = {2: "01", 8: "01234567", 16: "0123456789ABCDEFabcdef"}
MAX_KEYWORD_LENGTH = 30
# No reader holds an integer of more digits (a 128-bit one has 39); a longer one is reported
# and kept as text, never converted: Python refuses to convert more than 4,300 digits (its
# int-string limit) and arithmetic on the product of such numbers would be unbounded.
MAX_INTEGER_DIGITS = 100
# ODL sequences have one or two dimensions and sets one; OBJECT/GROUP nesting in real labels
# is a handful deep. Deeper nesting is reported, so that no reader or walker of the tree
# recurses without bound (a RecursionError on a hostile label).
MAX_NESTING = 32


# A keyword whose line ends after its "=" (the next line starts a statement, or the text
# ends): every reader takes the value as empty - NASA's PDS3 tools (MISSING_VALUE, a warning),
# pvl and pdr (an empty value) - so the statement after it is read as itself. A warning;
# a value missing before ")", "," or "=" stays an error: there the reader has no value to take.
_EMPTY_AT_LINE_END = "warning"


class _TooDeep(Exception):
    """A value nested deeper than MAX_NESTING: the statement is dropped (reported once)."""


class _Parser:
    def __init__(self, text: str) -> None:
        self.text = text
        self.issues: list[Issue] = []
        self.scan = Scanner(text, self.issues)
        self.root = Block("ROOT", "", 1)
        self.stack: list[Block] = [self.root]
        self.end_found = False
        self.label_end = len(text)
        self.first_keyword: str | None = None
        self.first_line: int | None = None
        self.sfdu: str | None = None
        self.lowercase: list[tuple[str, int]] = []
        self.segments = 0  # nested SFDU segments open (see _another_segment)
        self.depth = 0  # sequences and sets open in the value being read
        self.too_deep: Block | None = None  # the first OBJECT/GROUP nested too deep

    def issue(self, rule: str, line: int | None, message: str, keyword: str | None = None,
              severity: str | None = None) -> None:
        self.issues.append(Issue(rule, line, message, keyword, severity))

    def _unclosed(self, open_tok: Token, close: str, keyword: str) -> None:
        """A sequence or set whose closing bracket never comes (the next statement began)."""
        self.issue("SYNTAX-001", open_tok.line,
                   f"{open_tok.text} opened at line {open_tok.line} is never closed with {close}", keyword)

    # -- statements -------------------------------------------------------------
    def parse(self) -> None:
        self._sfdu()
        while True:
            simple = self.scan.simple_statement()
            if simple is not None and self._simple(*simple):
                continue
            tok = self.scan.next()
            if tok.kind == "eof":
                break
            if tok.kind != "word":
                self.issue("SYNTAX-001", tok.line, f"expected a keyword, found {tok.text[:20]!r}")
                self.scan.skip_line()
                continue
            tok = self._unglued_end(tok)
            upper = self._keyword_seen(tok.text, tok.line)
            if upper == "END":
                self._end(tok)
                if not self._another_segment():
                    break
                continue
            if upper in ("END_OBJECT", "END_GROUP"):
                self._close(tok, upper[4:])
                continue
            self._statement(tok, upper)
        self._finish()

    def _unglued_end(self, tok: Token) -> Token:
        """END itself when the scanner glued END and the binary data right after it into
        one word (`END\\xf8...`, `EndQ\\x0b...`: ISIS and several pipelines write no line
        end after END). It is END when binary bytes follow its three letters on the same
        line before any '=': no statement looks so. Reading goes on after END."""
        word = tok.text
        if len(word) <= 3 or word[:3].upper() != "END" or word[3] == "_":
            return tok
        after = tok.start + 3
        binary = NOT_TEXT.search(self.text, after, line_end(self.text, after))
        if binary is None or "=" in self.text[after : binary.start()]:
            return tok
        self.scan.reset((after, tok.line))
        return Token("word", word[:3], tok.line, tok.line, tok.start, after)

    def _keyword_seen(self, word: str, line: int) -> str:
        """Note the first keyword and keywords not in upper case; the upper-case form."""
        upper = word.upper()
        if self.first_keyword is None:
            self.first_keyword, self.first_line = upper, line
        if word != upper:
            self.lowercase.append((word, line))
        return upper

    def _simple(self, m: re.Match[str], line: int) -> bool:
        """A statement _SIMPLE matched, read as the token path reads it: the same checks
        and findings in the same order. False (nothing read) for what it must not take."""
        word, scalar, items, unit = m.group("keyword", "word", "items", "unit")
        upper = word.upper()
        if upper in ("END_OBJECT", "END_GROUP"):
            name = scalar or m.group("string")
            if name is None or unit is not None:
                return False  # what _close reports
            self.scan.take(m, line)
            self._keyword_seen(word, line)
            self._closed(word, upper[4:], name.strip('"'), line)
            return True
        if upper == "END":
            return False
        if unit is not None and scalar is None and items is None:
            return False  # a unit after a quoted value: the token path's finding
        if items is not None and (items[0] == "(") != (items[-1] == ")"):
            return False  # `(...}`: the token path's finding
        self.scan.take(m, line)
        self._keyword_seen(word, line)
        if not is_sfdu(upper):  # as _check_keyword, the name already taken apart
            self._check_lengths(word, m.group("namespace"), m.group("name"), line)
        if scalar is not None:
            value = self._scalar(scalar, line, word)
        elif items is not None:
            value = self._items(items, line, word)
        elif m.group("string") is not None:
            value = self._string(m.group("string"), line, word, False)
        else:
            value = Value("symbol", m.group("symbol"), m.group("symbol")[1:-1], line)
        if unit is not None:  # on the line the value ends on
            unit_line = line + count_lines(items, 0, len(items)) if items else line
            self._set_unit(value, unit, unit_line, unit_line, word)
        self._add(word, upper, line, value)
        return True

    def _items(self, text: str, line: int, keyword: str) -> Value:
        """A sequence or set _SIMPLE matched (`text` from its bracket to its closing one,
        opened on `line`): its members read as _value reads them."""
        members: list[Value] = []
        pos, item_line = 1, line
        for m in ITEMS.finditer(text, 1):
            start = m.start(1)
            if "\n" in text[pos:start] or "\r" in text[pos:start]:
                item_line += count_lines(text, pos, start)
            item = m.group(1)
            if item[0] == '"':
                members.append(self._string(item, item_line, keyword, True))
                if "\n" in item or "\r" in item:
                    item_line += count_lines(item, 0, len(item))
            elif item[0] == "'":
                members.append(Value("symbol", item, item[1:-1], item_line))
            else:
                members.append(self._scalar(item, item_line, keyword))
            pos = m.end(1)
        kind = "seq" if text[0] == "(" else "set"
        return Value(kind, text, [member.py for member in members], line, None, members)


    def _another_segment(self) -> bool:
        """True when END closes a nested segment of an SFDU label (Viking EDRs open one with
        `CCSD... = SFDU_LABEL` inside an object and close it with END), so the label goes on."""
        if self.segments == 0:
            return False
        self.segments -= 1
        self.end_found = False
        return True

    def _sfdu(self) -> None:
        tok = self.scan.peek()
        if tok.kind == "word" and tok.text.upper().startswith("CCSD"):
            self.scan.next()
            self.sfdu = tok.text
            problem = sfdu_problem(tok.text)
            if problem:
                self.issue("FILE-006", tok.line, f"malformed SFDU label {tok.text[:60]!r} before "
                           f"PDS_VERSION_ID: {problem}")
            nxt = self.scan.peek()
            if nxt.kind == "punct" and nxt.text == "=" and nxt.line == tok.line:
                self.scan.next()
                self.scan.next()

    def _end(self, tok: Token) -> None:
        self.end_found = True
        rest = self.scan.peek()
        if rest.kind == "punct" and rest.text == ";" and rest.line == tok.line:
            self.scan.next()
        end = line_end(self.text, tok.start)
        after = tok.start + len(tok.text)
        binary = NOT_TEXT.search(self.text, after, end)
        if binary is not None:  # END followed by the data on its line: the label ends at END
            self.label_end = after
            # data right after END (see _unglued_end) are data, even where they start with a
            # letter; after blanks, a ';' or a comment, text before the first binary byte is
            # text the label has after END
            end = binary.start() if self.text[after] in " \t;/\x00" else after
        else:
            m = NEWLINE.match(self.text, end)
            self.label_end = m.end() if m else end
        tail = self.text[after:end].strip(" ;\x00")
        if tail and not tail.startswith("/*"):
            self.issue("SYNTAX-001", tok.line, f"unexpected text {tail[:20]!r} after END")

    def _close(self, tok: Token, kind: str) -> None:
        name = None
        nxt = self.scan.peek()
        if nxt.kind == "punct" and nxt.text == "=" and nxt.line == tok.line:
            self.scan.next()
            val = self.scan.next()
            name = val.text.strip('"') if val.kind in ("word", "string") else None
            if name is None:
                self.issue("SYNTAX-001", tok.line, f"END_{kind} = needs an object name")
        self._end_of_statement(tok.line)
        self._closed(tok.text, kind, name, tok.line)

    def _closed(self, word: str, kind: str, name: str | None, line: int) -> None:
        """END_OBJECT/END_GROUP (`word`, naming `name` or not) read on `line`: close the block."""
        top = self.stack[-1]
        if top.kind == "ROOT":
            self.issue("SYNTAX-005", line, f"END_{kind} without a matching {kind}", word)
            return
        if top.kind != kind:
            self.issue(
                "SYNTAX-005",
                line,
                f"END_{kind} closes {top.kind} {top.name} opened at line {top.line}",
                word,
            )
        elif name is not None and name.upper() != top.name.upper():
            self.issue(
                "SYNTAX-005",
                line,
                f"END_{kind} = {name} closes {kind} {top.name} opened at line {top.line}",
                word,
            )
        elif name is None:
            self.issue("SYNTAX-006", line, f"END_{kind} does not repeat the name {top.name}")
        top.end_line = line
        self.stack.pop()

    def _statement(self, tok: Token, upper: str) -> None:
        line = tok.line
        self._check_keyword(tok.text, line)
        eq = self.scan.peek()
        if not (eq.kind == "punct" and eq.text == "="):
            self.issue("SYNTAX-001", line, f"missing '=' after {tok.text}", tok.text)
            self.scan.skip_line()
            return
        self.scan.next()
        try:
            value = self._value(line, tok.text)
        except _TooDeep:
            self._skip_value()
            return
        if value is None:
            return
        self._end_of_statement(self.scan.line)
        self._add(tok.text, upper, line, value)

    def _skip_value(self) -> None:
        """Read on to the next statement (or the end): what is left of a value too deep."""
        while True:
            tok = self.scan.peek()
            if tok.kind == "eof" or (tok.kind == "word" and self._starts_statement(tok)):
                return
            self.scan.next()

    def _add(self, word: str, upper: str, line: int, value: Value) -> None:
        """A statement read: into the current block, or opening an OBJECT/GROUP."""
        pointer = word.startswith("^")
        keyword = word[1:] if pointer else word
        if value.text.upper() == "SFDU_LABEL" and is_sfdu(keyword):
            self.segments += 1  # a nested SFDU segment (Viking EDRs): closed by its own END
            return
        if upper in ("OBJECT", "GROUP"):
            if value.kind not in ("ident", "string") or not value.text.strip():
                self.issue("SYNTAX-001", line, f"{upper} needs a name, found {value.raw[:20]!r}")
            block = Block(upper, value.text.strip(), line)
            if self._nests_within_bound(block):
                self.stack[-1].items.append(block)
            self.stack.append(block)
            return
        self.stack[-1].items.append(Statement(keyword, value, line, pointer))

    def _nests_within_bound(self, block: Block) -> bool:
        """True when `block` opens at most MAX_NESTING deep. A deeper one is read (its END_
        still closes it) but left out of the tree, reported at the first such block."""
        if len(self.stack) <= MAX_NESTING:
            return True
        if self.too_deep is None:
            self.too_deep = block
            self.issue("SYNTAX-005", block.line, f"{block.kind} = {block.name} nested more than "
                       f"{MAX_NESTING} deep: it and what it holds are not read", block.name)
        return False

    def _end_of_statement(self, line: int) -> None:
        nxt = self.scan.peek()
        if nxt.kind == "eof" or nxt.line != line:
            return
        if nxt.kind == "punct" and nxt.text == ";":
            self.scan.next()
            self.issue("SYNTAX-012", line, "';' statement terminator is PVL, not PDS3")
            return
        self.issue(
            "SYNTAX-001",
            line,
            f"unexpected text {nxt.text[:20]!r} after the value (quote values containing spaces)",
        )
        self.scan.skip_line()

    def _check_keyword(self, word: str, line: int) -> None:
        if is_sfdu(word):
            return  # a nested SFDU marker: see _statement
        m = _KEYWORD.fullmatch(word)
        if not m:
            self.issue("SYNTAX-002", line, f"{word!r} is not a valid keyword name", word)
            return
        self._check_lengths(word, m.group(1), m.group(2), line)

    def _check_lengths(self, word: str, namespace: str | None, name: str, line: int) -> None:
        if len(name) > MAX_KEYWORD_LENGTH and not word.startswith("^"):  # the limit is for keywords
            self.issue(
                "SYNTAX-015",
                line,
                f"keyword {name} has {len(name)} characters (at most {MAX_KEYWORD_LENGTH})",
                word,
            )
        if namespace and len(namespace) > MAX_KEYWORD_LENGTH:
            self.issue(
                "SYNTAX-015",
                line,
                f"namespace {namespace} has {len(namespace)} characters (at most {MAX_KEYWORD_LENGTH})",
                word,
            )

    # -- values ----------------------------------------------------------------
    def _value(self, line: int, keyword: str, nested: bool = False) -> Value | None:
        mark = self.scan.mark()
        tok = self.scan.next()
        if tok.kind == "eof" or (tok.kind == "punct" and tok.text in ")},;="):
            self.issue("SYNTAX-009", line, f"{keyword} has no value", keyword,
                       _EMPTY_AT_LINE_END if tok.kind == "eof" else None)
            self.scan.reset(mark)
            if tok.kind == "punct" and tok.text in ";":
                self.scan.next()
            elif not nested:
                self.scan.skip_line()
            return None
        if tok.kind == "word" and tok.line != line and not nested and self._starts_statement(tok):
            self.issue("SYNTAX-009", line, f"{keyword} has no value", keyword, _EMPTY_AT_LINE_END)
            self.scan.reset(mark)
            return None
        if tok.kind == "punct" and tok.text in "({":
            return self._collection(tok, keyword)
        if tok.kind == "string":
            return self._string(tok.text, tok.line, keyword, nested)
        if tok.kind == "symbol":
            return Value("symbol", tok.text, tok.text[1:-1], tok.line)
        if tok.kind == "word":
            value = self._scalar(tok.text, tok.line, keyword)
            self._unit(value, tok.line, keyword)
            return value
        self.issue("SYNTAX-001", tok.line, f"unexpected {tok.text[:20]!r} where a value belongs", keyword)
        if not nested:
            self.scan.skip_line()
        return None

    def _string(self, text: str, line: int, keyword: str, nested: bool) -> Value:
        content = text[1:-1]
        if not content.strip() and not nested:
            self.issue("SYNTAX-013", line, f'{keyword} = "": an empty text value', keyword)
        return Value("string", text, content, line)

    def _unit(self, value: Value, line: int, keyword: str) -> None:
        """A `<unit>` after the value. pvl reads one that starts the next line (JAXA and MER
        labels wrap long sequences so), and so does this reader, with a warning."""
        unit = self.scan.peek()
        if unit.kind != "unit":
            return
        self.scan.next()
        self._set_unit(value, unit.text, unit.line, line, keyword)

    def _set_unit(self, value: Value, text: str, unit_line: int, line: int, keyword: str) -> None:
        value.unit = text[1:-1].strip()
        if not value.unit:
            self.issue("SYNTAX-011", unit_line, f"empty unit '<>' after {keyword}", keyword)
        elif unit_line != line:
            self.issue("SYNTAX-014", unit_line, f"{keyword}: unit <{value.unit}> starts the line after "
                       "its value (readers such as pvl attach it to the value)", keyword)
        if value.items is not None:
            for item in value.scalars():
                item.unit = item.unit or value.unit

    def _starts_statement(self, tok: Token) -> bool:
        """True when a word on a later line is the next statement (so the value is missing)."""
        if tok.text.upper() in ("END", "END_OBJECT", "END_GROUP"):
            return True
        mark = self.scan.mark()
        nxt = self.scan.next()
        self.scan.reset(mark)
        return nxt.kind == "punct" and nxt.text == "="

    def _collection(self, open_tok: Token, keyword: str) -> Value | None:
        if self.depth >= MAX_NESTING:
            self.issue("SYNTAX-001", open_tok.line, f"{keyword}: a value nested more than {MAX_NESTING} "
                       "deep (sequences have one or two dimensions)", keyword)
            raise _TooDeep
        self.depth += 1
        try:
            return self._members(open_tok, keyword)
        finally:
            self.depth -= 1

    def _members(self, open_tok: Token, keyword: str) -> Value | None:
        """A sequence or set opened by `open_tok`: its members up to the closing bracket."""
        close = ")" if open_tok.text == "(" else "}"
        items: list[Value] = []
        while True:
            nxt = self.scan.peek()
            if nxt.kind == "punct" and nxt.text == close and not items:
                self.scan.next()
                if close == ")":  # an empty set {} is valid ODL; an empty sequence is not
                    self.issue("SYNTAX-013", open_tok.line, f"{keyword} = (): an empty sequence", keyword)
                break
            if nxt.kind == "eof" or (nxt.kind == "word" and self._starts_statement(nxt)):
                self._unclosed(open_tok, close, keyword)
                break
            item = self._value(open_tok.line, keyword, nested=True)
            if item is not None:
                items.append(item)
            ahead = self.scan.peek()
            if ahead.kind == "word" and self._starts_statement(ahead):
                self._unclosed(open_tok, close, keyword)
                break
            sep = self.scan.next()
            if sep.kind == "punct" and sep.text == close:
                break
            if sep.kind == "punct" and sep.text == ",":
                continue
            self.issue(
                "SYNTAX-001",
                sep.line,
                f"expected ',' or '{close}' in {keyword}, found {sep.text[:20]!r}",
                keyword,
            )
            if sep.kind == "eof":
                break
            self.scan.skip_line()
            break
        kind = "seq" if close == ")" else "set"
        raw = self.text[open_tok.start : self.scan.pos]
        value = Value(kind, raw, [item.py for item in items], open_tok.line, None, items)
        self._unit(value, self.scan.line, keyword)
        return value

    def _scalar(self, text: str, line: int, keyword: str) -> Value:
        number = _NUMBER.fullmatch(text)
        if number:
            if number.group(1):
                return self._integer(text, 10, text, line, keyword)
            if "." not in text:  # 1e+30: ODL real numbers have a decimal point
                mantissa, e, exponent = text.partition("e" if "e" in text else "E")
                self.issue("SYNTAX-016", line, f"{keyword} = {text}: a real number without a decimal "
                           f"point is not ODL (write {mantissa}.0{e}{exponent})", keyword)
            return Value("real", text, float(text), line)
        if "#" in text:
            return self._based(text, line, keyword)
        if _DATE_START.match(text):
            return self._date(text, line, keyword)
        return Value("ident", text, text, line)

    def _based(self, text: str, line: int, keyword: str) -> Value:
        m = _BASED.fullmatch(text)
        if not m:
            self.issue("SYNTAX-007", line, f"{text!r} is not a based integer (form: 16#FF7FFFFB#)", keyword)
            return Value("bad", text, text, line)
        sign, base_text, digits = m.groups()
        base = int(base_text) if len(base_text) <= 2 else 0  # a longer base is none of 2, 8, 16
        if base not in _BASE_DIGITS:
            self.issue("SYNTAX-007", line, f"{text[:40]}: base {base_text[:20]} is not 2, 8 or 16", keyword)
            return Value("bad", text, text, line)
        if not digits or any(ch not in _BASE_DIGITS[base] for ch in digits):
            self.issue("SYNTAX-007", line, f"{text}: {digits!r} are not base-{base} digits", keyword)
            return Value("bad", text, text, line)
        return self._integer(f"{sign or ''}{digits}", base, text, line, keyword)

    def _integer(self, digits: str, base: int, text: str, line: int, keyword: str) -> Value:
        """The integer `digits` (a sign maybe, then digits in `base`) written as `text`; one
        longer than MAX_INTEGER_DIGITS is a finding and kept as text (see there)."""
        count = len(digits.lstrip("+-"))
        if count > MAX_INTEGER_DIGITS:
            self.issue("SYNTAX-001", line, f"{keyword}: an integer of {count} digits (at most "
                       f"{MAX_INTEGER_DIGITS} are read)", keyword)
            return Value("bad", text, text, line)
        kind = "int" if base == 10 else "based"
        return Value(kind, text, int(digits, base), line)

    def _date(self, text: str, line: int, keyword: str) -> Value:
        problem = date_problem(text)
        if problem:
            self.issue("SYNTAX-008", line, f"{text}: {problem}", keyword)
            return Value("bad", text, text, line)
        return Value("date", text, text, line)

    def _finish(self) -> None:
        for block in reversed(self.stack[1:]):
            self.issue(
                "SYNTAX-005",
                block.line,
                f"{block.kind} = {block.name} is never closed with END_{block.kind}",
                block.name,
            )
        if self.lowercase:
            word, line = self.lowercase[0]
            self.issue(
                "SYNTAX-003",
                line,
                f"{len(self.lowercase)} keyword(s) not in upper case, first {word!r}",
                word,
            )


def is_sfdu(word: str) -> bool:
    """True for a PDS SFDU wrapper (see sfdu_problem)."""
    return len(word) >= 40 and word.startswith("CCSD") and sfdu_problem(word) is None


def sfdu_problem(word: str) -> str | None:
    """Why `word` is not the SFDU labels that wrap a PDS label (a CCSD Z-class label, then
    the labels it holds, 20 characters each), or None."""
    if len(word) < 40 or len(word) % 20:  # (restricted ASCII: upper-case letters and digits)
        return f"{len(word)} characters; SFDU labels are 20 each, a CCSD Z-class one and the label's own"
    for start in range(0, len(word), 20):
        part = word[start : start + 20]
        m = _SFDU_LABEL.fullmatch(word, start, start + 20)
        if m is None:
            return f"{part!r} is not an SFDU label (authority, version 1-3, class, delimitation, '0', id, length)"
        _, version, _, delimitation, _, length = m.groups()
        if version == "2" or delimitation == "B":
            return f"{part!r} has a binary length, which a text label cannot hold"
        if version == "1" and delimitation != "0":
            return f"{part!r}: a version-1 SFDU label has '0' where version 3 states the delimitation"
        if version == "3" and delimitation not in _SFDU_DELIMITATIONS:
            return f"{part!r}: delimitation {delimitation} is none of " + ", ".join(sorted(_SFDU_DELIMITATIONS))
        if delimitation not in "CS" and not (length.isascii() and length.isdigit()):
            return f"{part!r}: its length {part[12:]!r} is not 8 ASCII digits"
    if not word.startswith("CCSD") or word[5] != "Z":
        return "the first SFDU label is not the CCSD Z-class label that wraps the others"
    return None


def date_problem(text: str) -> str | None:
    """Why `text` is not a PDS3 date/time (CCYY-MM-DDThh:mm:ss.fff or CCYY-DDD...), or None."""
    if _TIME.fullmatch(text) and ":" in text:
        return _time_problem(text)
    m = _DATE.fullmatch(text)
    if not m:
        return "not a PDS3 date/time (CCYY-MM-DDThh:mm:ss.sss or CCYY-DDDThh:mm:ss.sss)"
    if m.group("doy"):
        if not 1 <= int(m.group("doy")) <= 366:
            return f"day of year {m.group('doy')} is outside 001..366"
    else:
        month = int(m.group("month"))
        if not 1 <= month <= 12:
            return f"month {month} is outside 01..12"
        if m.group("day") and not 1 <= int(m.group("day")) <= _DAYS[month - 1]:
            return f"day {m.group('day')} is outside the month"
    if m.group("time") is not None:
        return _time_problem(m.group("time"))
    return None


def _time_problem(text: str) -> str | None:
    m = _TIME.fullmatch(text)
    if not m:
        return "time is not hh:mm:ss.sss (two digits per field)"
    if int(m.group("h")) > 23:
        return f"hour {m.group('h')} is outside 00..23"
    if m.group("m") and int(m.group("m")) > 59:
        return f"minute {m.group('m')} is outside 00..59"
    if m.group("s") and int(m.group("s")) > 59:
        return f"second {m.group('s')} is outside 00..59"
    if m.group("f") is not None and not 1 <= len(m.group("f")) <= 9:
        return "fraction of a second needs 1 to 9 digits"
    return None


def parse_label(text: str) -> Label:
    """Parse label text (decoded one character per byte) into a `Label`; never raises."""
    parser = _Parser(text)
    parser.parse()
    limit = parser.label_end if parser.end_found else len(text)
    return Label(
        root=parser.root,
        text=text,
        label_end=limit,
        end_found=parser.end_found,
        lines=split_lines(text, limit),
        issues=parser.issues,
        first_keyword=parser.first_keyword,
        first_line=parser.first_line,
        sfdu=parser.sfdu,
    )


# -- the END rule and a file's label head ---------------------------------------------

# END (any case: ODL keywords are) alone on its line, maybe with ';' and a comment after it,
# or followed directly by binary data with no line end (ISIS and several pipelines write it
# so). What the parser takes for END, as a pattern on bytes: the reading of a label's head
# stops where it matches.
END_LINE = re.compile(rb"(?im)^[ \t]*END[ \t]*;?[ \t]*(?:/\*.*)?(?:\r?$|(?=[^\x20-\x7e\r\n]))")

def has_end(data: bytes) -> bool:
    """True when `data` holds a label's END line."""
    return END_LINE.search(data) is not None


def end_of_label(data: bytes) -> int | None:
    """The offset just past END and what follows it on its line (before the line end), or None."""
    found = END_LINE.search(data)
    return found.end() if found is not None else None


def label_length(data: bytes) -> int | None:
    """The length of the label `data` starts with: up to and including END's line end, or None."""
    end = end_of_label(data)
    if end is None:
        return None
    if data.startswith(b"\r\n", end):
        return end + 2
    return end + 1 if data.startswith((b"\n", b"\r"), end) else end


def read_label_head(path: str | os.PathLike[str], first: int = 65536, step: int = 65536,
                    limit: int = 4 << 20) -> bytes:
    """The file's first bytes up to its label's END line (and the rest of the last block
    read): `first` bytes, then `step` more at a time until END or `limit` bytes. The data
    after an attached label is read no further. OSError when the file cannot be read."""
    with open_regular(path) as stream:
        return read_on_to_end(stream, stream.read(first), first, step, limit)


def read_on_to_end(stream: BinaryIO, data: bytes, first: int = 65536, step: int = 65536,
                   limit: int = 4 << 20) -> bytes:
    """`data` (the first `first` bytes read from `stream`) and what follows, as read_label_head."""
    if len(data) < first or has_end(data):  # the whole file, or its label, read
        return data
    blocks = [data]
    size = len(data)
    while size < limit:
        block = stream.read(min(step, limit - size))
        if not block:
            break
        blocks.append(block)
        size += len(block)
        if has_end(blocks[-2] + block):  # END may straddle two blocks
            break
    return b"".join(blocks)


# -- a label file, read once ------------------------------------------------------------------

FIRST_READ = 256 * 1024  # most labels (and small attached products) are read in one block
LABEL_LIMIT = 16 * 1024 * 1024  # no real label is larger; the head of a file is read no further

# What a PDS3 label file starts with: its first keyword (ODL_VERSION_ID in some PDS version 2
# labels), or the SFDU label that wraps it; blanks before it are allowed, case is not asked.
_PDS3_START = re.compile(rb"\s*(?:PDS_VERSION_ID|ODL_VERSION_ID|CCSD3)", re.IGNORECASE)


def is_pds3_head(head: bytes) -> bool:
    """True when a file's first bytes are those of a PDS3 label."""
    return _PDS3_START.match(head) is not None


@dataclass(eq=False)
class LabelFile:
    """One PDS3 label file (attached or detached) as read: the bytes up to its END line (and
    the rest of the last block read), the parsed label and the file's size."""

    path: Path
    size: int
    head: bytes
    label: Label
    # The file is its label alone (all of it read, nothing but blanks after END): an attached
    # label whose data are absent. Known when read, so a kept copy may drop the bytes after END.
    label_only: bool = False

    @classmethod
    def read(cls, path: str | os.PathLike[str]) -> LabelFile:
        """The file's label, whatever its first bytes (the validator reports a file that is no
        PDS3 label itself; `is_pds3` says whether it looks like one). OSError when unreadable."""
        found = cls._read(Path(path), pds3_only=False)
        assert found is not None
        return found

    @classmethod
    def read_pds3(cls, path: str | os.PathLike[str]) -> LabelFile | None:
        """The file's label, or None when its first bytes are no PDS3 label's (then nothing
        more of the file is read). OSError when unreadable."""
        return cls._read(Path(path), pds3_only=True)

    @classmethod
    def _read(cls, path: Path, pds3_only: bool) -> LabelFile | None:
        with open_regular(path) as stream:
            size = os.fstat(stream.fileno()).st_size
            first = stream.read(FIRST_READ)
            if pds3_only and not is_pds3_head(first):
                return None
            head = read_on_to_end(stream, first, FIRST_READ, LABEL_LIMIT, LABEL_LIMIT)
        label = parse_label(head.decode("latin-1"))
        rest = head[label.label_end:]
        return cls(path, size, head, label, len(head) >= size and not rest.strip(b" \r\n\x00\x1a"))

    @property
    def is_pds3(self) -> bool:
        return is_pds3_head(self.head)

    @property
    def root(self) -> Block:
        return self.label.root

    @property
    def end_found(self) -> bool:
        return self.label.end_found

    def first_statement(self, key: str) -> Statement | None:
        return first_statement(self.root, key)

    def first(self, key: str) -> str | None:
        """`key`'s value as written (a string unquoted), at the top or in the first block that
        has it as a single value; None when no block has."""
        return first_text(self.root, key)

    def image(self) -> Block | None:
        return image_object(self.root)

    def projection(self) -> Block | None:
        return projection_object(self.root)

    @cached_property
    def pointers(self) -> list[Pointer]:
        """The pointers of the label's top level, classified (tree.py's parse_pointer)."""
        return label_pointers(self.root)

    def at(self, path: Path) -> LabelFile:
        """The same label as read through another name of the file (a hard link)."""
        return self if path == self.path else replace(self, path=path)

    def kept(self) -> LabelFile:
        """This label without the bytes after its END line (what a cache holds: an attached
        label's data are not kept in memory)."""
        end = label_length(self.head)
        return self if end is None or end >= len(self.head) else replace(self, head=self.head[:end])
