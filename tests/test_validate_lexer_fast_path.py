"""Statements the lexer reads in one match (`KEYWORD = value <unit>` alone on its line)
next to look-alikes it must leave to the token-by-token path: both give the findings
the token path always gave."""

from __future__ import annotations

import pytest

from pdsgen.label.parser import parse_label


def _issues(text: str) -> set[tuple[str, int | None]]:
    return {(i.rule, i.line) for i in parse_label("PDS_VERSION_ID = PDS3\n" + text + "END\n").issues}


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("A = 5\n<KM>\n", {("SYNTAX-014", 3)}),  # a unit starting the next line belongs to the value
        ("A = 5 /* note */ B = 6\n", {("SYNTAX-001", 2)}),  # a statement after a comment on the line
        ("A = 5 /* note */\n", set()),
        ("RECORD_BYTES\x00 = 81\n", {("SYNTAX-002", 2)}),  # NUL ends no word: not a keyword
        ("A = \x0081\n", set()),  # NUL before a token is a blank
        ('A = "text" <KM>\n', {("SYNTAX-001", 2)}),  # no unit after quoted text
        ("A = 5;\n", {("SYNTAX-012", 2)}),
        ("A = (1, 2}\n", {("SYNTAX-001", 2)}),
        ("A = ()\n", {("SYNTAX-013", 2)}),
        ("A = 5 <>\n", {("SYNTAX-011", 2)}),
        ("OBJECT = X\nEND_OBJECT = Y\n", {("SYNTAX-005", 3)}),
        ("OBJECT = X\nEND_OBJECT = X <KM>\n", {("SYNTAX-001", 3)}),
        ("A_KEYWORD_THAT_IS_FAR_TOO_LONG_X = 1\n", {("SYNTAX-015", 2)}),
        ("T = 2000-13-01\n", {("SYNTAX-008", 2)}),
    ],
)
def test_findings_of_simple_statements_and_look_alikes(text, expected):
    assert _issues(text) == expected


def test_sequence_over_lines_with_a_unit():
    label = parse_label("PDS_VERSION_ID = PDS3\r\nV = (1, 'a',\r\n     \"b\nc\", 2.5) <KM>\r\nW = 1\r\nEND\r\n")
    assert label.issues == []
    value = label.root.value("V")
    assert [(item.kind, item.line, item.unit) for item in value.scalars()] == [
        ("int", 2, "KM"), ("symbol", 2, "KM"), ("string", 3, "KM"), ("real", 4, "KM")]
    assert label.root.get("W").line == 5 and value.raw.startswith("(1, 'a',\r\n")
