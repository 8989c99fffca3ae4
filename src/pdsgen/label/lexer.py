"""The PDS3 (ODL) label scanner: the tokens of label text, and its physical lines.

Whitespace, line ends and comments are skipped; each token keeps its line number so
the parser (parser.py) can point at the line of a problem. A problem met while
scanning (an unclosed quote or comment) travels with its token as an `Issue`.
"""

from __future__ import annotations

import re
from itertools import accumulate, repeat

from .tree import Issue, Line

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
