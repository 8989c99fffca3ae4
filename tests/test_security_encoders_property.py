"""Property-based tests of every output encoder (issue 48): for arbitrary Unicode - controls,
surrogates (a non-UTF-8 name under surrogateescape), format characters such as U+202E, markup
and quote characters - an encoder's output is well-formed and reads back, through an independent
reader (pvl, lxml, csv, html.parser), to exactly the value given, or the value is refused with
the encoder's one error type (EncodeError). A fixed, derandomized budget keeps each test to
seconds; a failure found is kept below as an @example."""

from __future__ import annotations

import csv
import html.parser
import io
import unicodedata

import pvl
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from lxml import etree
from markupsafe import escape

from pdsgen.encode import (
    EncodeError,
    ascii_text,
    check_pvl_keyword,
    html_finalize,
    shown,
    table_field,
    xml_attribute,
    xml_text,
)
from pdsgen.label.layout import layout_label
from pdsgen.label.values import format_string

BUDGET = settings(max_examples=400, deadline=None, derandomize=True)
# Characters that have broken or could break an output, mixed with any code point at all
# (surrogates included: hypothesis leaves them out unless asked).
HOSTILE = "\x00\x07\x1b\t\n\r\x0b\x0c\x85\xa0\u2028\u2029\u202e\u200b\ufeff\ufffe\udce9\ud800\"'&<>=;,/*\\"
ANY_CHARACTER = st.characters(min_codepoint=0, max_codepoint=0x10FFFF, blacklist_categories=())
TEXT = st.text(st.one_of(st.characters(max_codepoint=0x7F), st.sampled_from(HOSTILE), ANY_CHARACTER), max_size=40)
HIDDEN = {"Cc", "Cf", "Cs", "Co", "Cn", "Zl", "Zp"}


def _folded(text: str) -> str:
    """A quoted PVL string as every PVL reader reads it: white space runs are one space, none at the ends."""
    return " ".join(text.split())


def _encoded(encoder, value: str, keyword: str) -> str | None:
    """The encoder's output, or None when it refused - with its one error type, in one line
    naming the keyword and the source."""
    try:
        return encoder(value, keyword, "test")
    except EncodeError as exc:
        assert str(exc).startswith(f"test: {keyword}: ") and len(str(exc).splitlines()) == 1
        return None


@BUDGET
@given(TEXT)
@example('A"\r\nVOLUME_ID = "FORGED_VOL')
@example("T\x00")
@example("\t")
def test_pvl_string_reads_back_as_written_or_is_refused(value):
    encoded = _encoded(format_string, value, "KEY")
    if encoded is None:
        return
    assert encoded.isascii() and encoded.isprintable()  # one line: no statement can follow inside it
    module = pvl.loads(f"KEY = {encoded}\r\nEND")
    assert list(module.keys()) == ["KEY"] and module["KEY"] == _folded(value)


@BUDGET
@given(TEXT)
@example("END")
@example("NAN")
@example("W\nEND_OBJECT = Algorithm\nOBJECT = ProductInfo")
def test_pvl_keyword_is_one_statement_or_is_refused(name):
    if _encoded(check_pvl_keyword, name, "MATCHER_PARAMETERS") is None:
        return
    module = pvl.loads(f"OBJECT = Algorithm\r\n  {name} = 1\r\nEND_OBJECT = Algorithm\r\nEND")
    assert list(module.keys()) == ["Algorithm"] and list(module["Algorithm"].items()) == [(name, 1)]


@BUDGET
@given(TEXT)
@example("\r")
@example("\udce9")
@example("]]>&#34;")
def test_xml_text_reads_back_as_written_or_is_refused(value):
    encoded = _encoded(xml_text, value, "title")
    if encoded is None:
        return
    element = etree.fromstring(f"<title>{encoded}</title>".encode())
    assert (element.text or "") == value


@BUDGET
@given(TEXT)
@example("\t\n\r")
def test_xml_attribute_reads_back_as_written_or_is_refused(value):
    encoded = _encoded(xml_attribute, value, "unit")
    if encoded is None:
        return
    assert etree.fromstring(f'<a unit="{encoded}"/>'.encode()).get("unit") == value


@BUDGET
@given(TEXT)
@example("MARS\r\n")
@example('MA"RS')
def test_table_field_keeps_its_row_and_width_or_is_refused(value):
    encoded = _encoded(table_field, value, "TARGET_NAME")
    if encoded is None:
        return
    row = f'"{encoded}",1\r\n'
    assert len(row.encode("ascii")) == len(value) + 6  # fixed width: one byte a character
    assert list(csv.reader(io.StringIO(row, newline=""))) == [[value, "1"]]


class _Text(html.parser.HTMLParser):
    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.parts: list[str] = []

    def handle_data(self, data: str) -> None:
        self.parts.append(data)


@BUDGET
@given(TEXT)
@example("caf\udce9\u202e.IMG")
@example("<script>alert(1)</script>")
def test_html_writes_the_shown_value_and_nothing_else(value):
    encoded = str(escape(html_finalize(value)))
    encoded.encode("utf-8")  # no surrogate reaches the page
    parser = _Text()
    parser.feed(f"<p>{encoded}</p>")
    parser.close()
    read = "".join(parser.parts)
    assert read == "\n".join(shown(line) for line in value.split("\n"))
    assert not any(unicodedata.category(c) in HIDDEN for c in read if c not in "\t\n")


@BUDGET
@given(TEXT)
@example("file\u202eTXT.exe")
@example("\x1b]0;title\x07")
def test_terminal_text_is_one_visible_line(value):
    line = shown(value)
    line.encode("utf-8")
    assert not any(unicodedata.category(c) in HIDDEN for c in line if c != "\t")
    assert len(line.splitlines()) <= 1
    if value.isascii() and value.isprintable():
        assert line == value


@BUDGET
@given(TEXT)
def test_plain_text_file_text_is_ascii(value):
    text = ascii_text(value)
    assert text.isascii() and text.count("\n") == value.count("\n")
    assert all(line.isprintable() or "\t" in line for line in text.split("\n"))


@pytest.mark.parametrize("encoder", [format_string, xml_text, xml_attribute])
def test_the_refusal_is_one_line_naming_keyword_and_source(encoder):
    with pytest.raises(EncodeError) as refused:
        encoder("a\x00b", "DATA_SET_NAME", "params.toml")
    assert str(refused.value).startswith("params.toml: DATA_SET_NAME: ") and "\\x00" in str(refused.value)


def _pds3_environment():
    from pdsgen.label.render import template_environment

    return template_environment()


def _pds4_environment():
    from pdsgen.pds4.label import _environment

    return _environment()


TEMPLATE_CASES = {  # output hook -> (template with an unfiltered value, an independent reader, what it must read)
    "pds3": (_pds3_environment, "KEY = {{ value }}\nEND\n", lambda text: list(pvl.loads(layout_label(text)).items()),
             lambda value: [("KEY", _folded(value))]),
    "pds4": (_pds4_environment, "<title>{{ value }}</title>", lambda text: etree.fromstring(text.encode()).text or "",
             lambda value: value),
}


@pytest.mark.parametrize("case", sorted(TEMPLATE_CASES))
@BUDGET
@given(value=TEXT)
@example(value='x"\nEND')
@example(value="</title><forged/>")
def test_a_template_writes_even_an_unfiltered_value_through_its_formats_hook(case, value):
    """`{{ value }}` without a filter is encoded by the environment's output hook: PVL for a PDS3
    label (laid out in 80-byte lines as every label is, read back as PVL folds white space), XML
    text for a PDS4 label (read back exactly)."""
    environment, template, read, expected = TEMPLATE_CASES[case]
    try:
        text = environment().from_string(template).render(value=value)
    except EncodeError:
        return
    assert read(text) == expected(value)
