"""SYNTAX family: problems the label reader found, plus duplicate keywords.

The label reader (label/parser.py) tags what it sees with rule ids as it parses; these
checks hand those on, so every syntax finding goes through the one rule table.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator

from ...label.grammar import IDENTIFIER_RE
from ..context import FileContext
from ..model import Hit
from ..registry import Rule, register

_IDENT = IDENTIFIER_RE


def from_reader(rule: str) -> Callable[[FileContext], Iterator[Hit]]:
    """A check that reports the reader's issues tagged `rule`."""

    def check(ctx: FileContext) -> Iterator[Hit]:
        for issue in ctx.label.issues:
            if issue.rule == rule:
                yield Hit(issue.message, issue.line, issue.keyword, severity=issue.severity)

    check.__name__ = f"check_{rule.replace('-', '_').lower()}"
    return check


def check_duplicates(ctx: FileContext) -> Iterator[Hit]:
    for block in ctx.root.walk():
        seen: dict[str, int] = {}
        for stmt in block.statements():
            key = stmt.key
            if key == "^STRUCTURE":  # several format files may be included into one object
                continue
            if key in seen:
                where = f"in OBJECT {block.name}" if block.kind != "ROOT" else "at the top level"
                yield Hit(f"{key} appears again {where} (first at line {seen[key]})", stmt.line, key)
            else:
                seen[key] = stmt.line


def check_unquoted(ctx: FileContext) -> Iterator[Hit]:
    """Unquoted values that are not identifiers: readers differ on them, so quote them."""
    for block in ctx.root.walk():
        for stmt in block.statements():
            if stmt.pointer:
                continue
            for value in stmt.value.scalars():
                if value.kind == "ident" and not _IDENT.fullmatch(value.raw) and value.raw not in (
                    "N/A",
                ):
                    yield Hit(f"{stmt.key} = {value.raw}: unquoted value is not an identifier; "
                              f'write "{value.raw}"', stmt.line, stmt.key)
                    break


register(
    Rule("SYNTAX-001", "error", "statements parse: KEYWORD = value, quotes and brackets closed",
         from_reader("SYNTAX-001")),
    Rule("SYNTAX-002", "error", "keyword names are identifiers: a letter, then letters, digits and _",
         from_reader("SYNTAX-002")),
    Rule("SYNTAX-015", "warning", "keyword names have at most 30 characters (pointer names may be "
         "longer: ^DATA_SET_MAP_PROJECTION_CATALOG)", from_reader("SYNTAX-015")),
    Rule("SYNTAX-003", "warning", "keywords are upper case", from_reader("SYNTAX-003")),
    Rule("SYNTAX-004", "error", "a keyword appears once within its object", check_duplicates),
    Rule("SYNTAX-005", "error", "OBJECT/END_OBJECT and GROUP/END_GROUP balance and match",
         from_reader("SYNTAX-005")),
    Rule("SYNTAX-006", "info", "END_OBJECT/END_GROUP repeat the object name", from_reader("SYNTAX-006")),
    Rule("SYNTAX-007", "error", "based integers are 2#..#, 8#..# or 16#..# with valid digits",
         from_reader("SYNTAX-007")),
    Rule("SYNTAX-008", "error", "dates and times are valid CCYY-MM-DDThh:mm:ss.sss / CCYY-DDD",
         from_reader("SYNTAX-008")),
    Rule("SYNTAX-009", "error", "every keyword has a value", from_reader("SYNTAX-009"),
         note="warning where the line ends after '=' and the next line starts a statement: every reader "
         "(NASA's PDS3 tools, pvl, pdr) takes the value as empty"),
    Rule("SYNTAX-010", "warning", "unquoted values are identifiers (else quote them)",
         check_unquoted),
    Rule("SYNTAX-011", "error", "units are not empty", from_reader("SYNTAX-011")),
    Rule("SYNTAX-012", "warning", "no ';' statement terminators (PVL, not PDS3)", from_reader("SYNTAX-012")),
    Rule("SYNTAX-013", "warning", "values are not empty (\"\" or ()); an empty set {} is valid ODL",
         from_reader("SYNTAX-013")),
    Rule("SYNTAX-016", "warning", "real numbers have a decimal point (1.0E+30, not 1E+30)",
         from_reader("SYNTAX-016")),
    Rule("SYNTAX-014", "warning", "a <unit> follows its value on the same line (pvl reads it either way)",
         from_reader("SYNTAX-014")),
)
