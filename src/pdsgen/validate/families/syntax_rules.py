"""SYNTAX family: problems the label reader found, plus duplicate keywords.

The reader (lexer.py) tags what it sees with rule ids as it parses; these checks hand
those on, so every syntax finding goes through the one rule table.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator

from ...label.grammar import IDENTIFIER_RE
from ..context import FileContext
from ..model import Hit

_IDENT = IDENTIFIER_RE


def from_reader(rule: str) -> Callable[[FileContext], Iterator[Hit]]:
    """A check that reports the reader's issues tagged `rule`."""

    def check(ctx: FileContext) -> Iterator[Hit]:
        for issue in ctx.label.issues:
            if issue.rule == rule:
                yield Hit(issue.message, issue.line, issue.keyword)

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
