"""The output encoders: one per format pdsgen writes, and their one refusal (EncodeError).

Every value pdsgen writes into an output passes the encoder of that output's format, which
writes it faithfully (it reads back as exactly the value given) or refuses it with an
`EncodeError` naming the keyword and the source. So a value from outside - delivery text,
a params file, a PDS3 catalog, a label value, a file name - can never become markup, a
statement or a row of its own. Here: the PVL string and keyword rules (label.values writes
PVL values with them), XML text and attributes and the PDS4 templates' output hook, table
fields, terminal/report text (`shown`), the HTML and README.TXT templates' output hooks.
tests/test_architecture_encoders.py names each home. This module imports no folder, so
every floor may use it.
"""

from __future__ import annotations

import os
import re
import unicodedata
from collections.abc import Mapping
from dataclasses import fields, is_dataclass

from .errors import PdsgenError


class EncodeError(PdsgenError, ValueError):
    """A value that its output format cannot carry: `source: keyword: reason` on one line."""

    def __init__(self, source: str | os.PathLike[str] | None, keyword: str | None, reason: str,
                 value: object = None) -> None:
        self.keyword = keyword
        self.reason = reason
        self.value = value  # what was refused, so a caller can say where it came from
        super().__init__(source, f"{keyword or 'a value'}: {reason}")

    def naming(self, source: str | os.PathLike[str] | None = None, keyword: str | None = None) -> EncodeError:
        """The same refusal with the source and keyword its caller knows filled in."""
        return EncodeError(self.path if self.path is not None else source, self.keyword or keyword, self.reason,
                           self.value)


# Terminal and report text: C0/C1 controls (a newline too: one finding is one line), format
# characters such as U+202E RIGHT-TO-LEFT OVERRIDE, surrogates (a file name's undecodable bytes
# under surrogateescape), line and paragraph separators, unassigned and private-use code points.
_HIDDEN_CATEGORIES = frozenset({"Cc", "Cf", "Cs", "Co", "Cn", "Zl", "Zp"})


def _escape(char: str) -> str:
    code = ord(char)
    if 0xDC80 <= code <= 0xDCFF:  # an undecodable byte of a name, as surrogateescape carries it
        return f"\\x{code - 0xDC00:02x}"
    if code < 0x100:
        return f"\\x{code:02x}"
    return f"\\u{code:04x}" if code < 0x10000 else f"\\U{code:08x}"


def shown(text: object) -> str:
    """`text` as a terminal, a text report, an annotation or a page shows it: every character
    that moves the cursor (a TAB aside), reorders the line or is invisible escaped (`\\x1b`,
    `\\u202e`, a non-UTF-8 byte of a file name as `\\xe9`); printable text unchanged. The result
    encodes as UTF-8 whatever the name held."""
    value = os.fspath(text) if isinstance(text, os.PathLike) else text
    if isinstance(value, bytes):
        value = value.decode("utf-8", "surrogateescape")
    string = str(value)
    if string.isascii() and string.isprintable():
        return string
    return "".join(_escape(c) if c != "\t" and unicodedata.category(c) in _HIDDEN_CATEGORIES else c
                   for c in string)


def shown_lines(text: object) -> str:
    """`shown`, line by line: a text block (a page's <pre>, a JUnit failure) keeps its lines."""
    return "\n".join(shown(line) for line in str(text).split("\n"))


def ascii_text(value: object) -> str:
    """The output hook of the plain-text templates (Extras README.TXT, 7-bit ASCII): each line
    `shown`, and what is not ASCII escaped too - a file name's `\xe9` read as written,
    never a `?`."""
    text = shown_lines(value)
    return text if text.isascii() else "".join(c if c.isascii() else _escape(c) for c in text)


def html_finalize(value: object) -> object:
    """The output hook of the HTML templates (the review page): every `{{ }}` value `shown`
    line by line before autoescape writes it - a non-UTF-8 file name or a U+202E in a label
    value is seen escaped, never written raw (nor a UnicodeEncodeError); markup a filter made
    passes as it is."""
    if hasattr(value, "__html__") or not isinstance(value, str):
        return value
    return shown_lines(value)


# What a quoted PDS3 string may hold: printable 7-bit ASCII but the double quote that ends it,
# and the white space (TAB, LF, CR) a reader folds into one space.
_PVL_STRING_RE = re.compile(r'[\t\n\r\x20\x21\x23-\x7e]*')
_PVL_BAD_RE = re.compile(r'[^\t\n\r\x20\x21\x23-\x7e]')


def pvl_string_problem(text: str) -> str | None:
    """Why `text` cannot be a quoted PDS3 string (None when it can)."""
    if _PVL_STRING_RE.fullmatch(text):
        return None
    bad = _PVL_BAD_RE.search(text)
    char = bad.group() if bad else "?"
    if char == '"':
        return "a PDS string cannot contain a double quote"
    if not char.isascii():
        return f"PDS labels are 7-bit ASCII, and it holds {_escape(char)}"
    return f"holds the control character {_escape(char)}, which a PDS label cannot carry"


def check_pvl_string(text: str, keyword: str | None = None, source: str | os.PathLike[str] | None = None) -> str:
    """`text` if a PDS3 label can carry it as a quoted string; an EncodeError naming `keyword`
    and `source` if not. Readers of values meant for labels (params, delivery text) call it,
    so a value is refused where it came in, with the name the person wrote; label.values'
    format_string, the one writer of quoted PDS3 strings, calls it on every value it writes."""
    problem = pvl_string_problem(text)
    if problem:
        raise EncodeError(source, keyword, problem, text)
    return text


# A PVL keyword (an iMars .pvl's Algorithm parameters): letters, digits and underscores, and not
# one of the words that open or close an aggregation or the label, nor one a reader takes for a
# value (TRUE, NULL, NAN ...).
PVL_KEYWORD_RE = re.compile(r"[A-Za-z][A-Za-z0-9_]*")
PVL_RESERVED = frozenset({"END", "OBJECT", "END_OBJECT", "BEGIN_OBJECT", "GROUP", "END_GROUP", "BEGIN_GROUP",
                          "TRUE", "FALSE", "NULL", "NAN", "INF", "INFINITY"})


def check_pvl_keyword(name: str, keyword: str, source: str | os.PathLike[str] | None = None) -> str:
    """`name` if it can stand as a PVL keyword; refused otherwise (a name holding `=` or a line
    break would write statements of its own)."""
    if not PVL_KEYWORD_RE.fullmatch(name) or name.upper() in PVL_RESERVED:
        raise EncodeError(source, keyword, f"the name {shown(name)!r} is not a PVL keyword "
                                           "(a letter, then letters, digits, underscores; "
                                           "not END, OBJECT, GROUP, TRUE, NAN ...)", name)
    return name


# XML 1.0's Char production: what a well-formed document may hold at all.
_NOT_XML = re.compile("[^\t\n\r\u0020-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]")
_XML_TEXT = {"&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&#34;", "'": "&#39;", "\r": "&#13;"}
_XML_ATTRIBUTE = {**_XML_TEXT, "\t": "&#9;", "\n": "&#10;"}
_XML_TEXT_RE = re.compile("[&<>\"'\r]")
_XML_ATTRIBUTE_RE = re.compile("[&<>\"'\r\t\n]")


def xml_problem(value: str) -> str | None:
    """Why `value` cannot be XML character data (None when it can)."""
    bad = _NOT_XML.search(value)
    if bad is None:
        return None
    return f"holds {_escape(bad.group())}, which XML 1.0 cannot carry"


def xml_text(value: object, keyword: str | None = None, source: str | os.PathLike[str] | None = None) -> str:
    """Element content: markup characters as references, a CR as `&#13;` (a parser would
    fold a bare one into LF); a character XML cannot hold refused."""
    text = str(value)
    problem = xml_problem(text)
    if problem:
        raise EncodeError(source, keyword, problem, value)
    return _XML_TEXT_RE.sub(lambda m: _XML_TEXT[m.group()], text)


def xml_attribute(value: object, keyword: str | None = None, source: str | os.PathLike[str] | None = None) -> str:
    """An attribute value in double quotes: as `xml_text`, and TAB, LF as references too
    (a parser would turn them into spaces)."""
    text = str(value)
    problem = xml_problem(text)
    if problem:
        raise EncodeError(source, keyword, problem, value)
    return _XML_ATTRIBUTE_RE.sub(lambda m: _XML_ATTRIBUTE[m.group()], text)


def table_field(value: str, keyword: str, source: str | os.PathLike[str] | None = None) -> str:
    """A field of a PDS3 ASCII table (INDEX.TAB): printable 7-bit ASCII without a double quote,
    since the quotes delimit it and CR LF ends its row; anything else refused, never changed."""
    for char in value:
        if not (" " <= char <= "~") or char == '"':
            what = "a double quote" if char == '"' else _escape(char)
            raise EncodeError(source, keyword, f"holds {what}; a table field is printable ASCII "
                                               "without double quotes")
    return value


def locate(context: Mapping[str, object], value: object, depth: int = 4) -> str | None:
    """Where in a template's context `value` sits, as `ident.TITLE` - the keyword a refusal
    from a template's output hook names (None when it is not found)."""
    def walk(node: object, path: str, left: int) -> str | None:
        if node is value or (isinstance(node, str) and isinstance(value, str) and node == value):
            return path
        if left == 0 or isinstance(node, (str, bytes)):
            return None
        items: list[tuple[str, object]] = []
        if isinstance(node, Mapping):
            items = [(str(k), v) for k, v in node.items()]
        elif is_dataclass(node) and not isinstance(node, type):
            items = [(f.name, getattr(node, f.name, None)) for f in fields(node)]
        elif isinstance(node, (list, tuple)):
            items = [(f"[{i}]", v) for i, v in enumerate(node)]
        for key, child in items:
            found = walk(child, f"{path}.{key}" if path and not key.startswith("[") else f"{path}{key}", left - 1)
            if found:
                return found
        return None

    return walk(dict(context), "", depth)


def xml_finalize(value: object) -> object:
    """The output hook of the XML (PDS4 label) templates: every `{{ }}` value leaves as
    `xml_text` - markup a filter or macro made (jinja2's Markup) as it is. autoescape alone
    would write a control character raw and the label would not be well-formed."""
    from markupsafe import Markup

    if isinstance(value, Markup):
        return value
    return Markup(xml_text(value))
