"""Render label templates and settle the record arithmetic of attached labels.

Templates live in the top-level `templates/` directory; every value passes
through the `pds` filter (values.format_value), and layout.layout_label decides
indentation, alignment and wrapping. Injection is impossible by construction: the
environment's output hook (`finalize`) encodes any value a template writes without
the filter as a PVL value too, so no `{{ }}` writes text that is not PVL-encoded;
tests/test_architecture_encoders.py keeps every output naming its encoder.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from functools import cache
from typing import TYPE_CHECKING, Any

from ..encode import EncodeError, locate
from ..resources import templates_dir, user_cache_dir
from .layout import layout_label
from .values import Quantity, Symbol, format_value

if TYPE_CHECKING:
    import jinja2


class PvlText(str):
    """Text already encoded for a PDS3 label (by the `pds`, `symbol`, `keyword` or `comments` filter)."""


def _pds(value: object) -> PvlText:
    return value if isinstance(value, PvlText) else PvlText(format_value(value))


def _symbol(value: str) -> PvlText:
    """An enumerated value written bare (PLANETOCENTRIC); refused unless it is an identifier."""
    return PvlText(format_value(Symbol(value)))


def _keyword(name: str) -> PvlText:
    """A keyword written by a template from its context (HRSC's carried keys), `NAME`, `NS:NAME`
    or a pointer `^NAME`: refused unless each part is an identifier, so a name cannot open a
    statement."""
    for part in name.removeprefix("^").split(":", 1):
        Symbol(part)
    return PvlText(name)


def _comment(line: str) -> PvlText:
    """One `/* ... */` comment line pdsgen wrote (a mission's note): printable ASCII, one
    comment, nothing after it - so a note cannot open a statement."""
    body = line[2:-2] if line.startswith("/*") and line.endswith("*/") else None
    if body is None or "*/" in body or "/*" in body or not (body.isascii() and body.isprintable()):
        raise EncodeError(None, "comment", f"{line[:40]!r} is not one printable /* ... */ comment")
    return PvlText(line)


def _comments(lines: str) -> PvlText:
    return PvlText("\n".join(_comment(line) for line in lines.split("\n")))


def _finalize(value: object) -> PvlText:
    """The output hook: every `{{ }}` value leaves as PVL text - one a filter encoded as it
    is, any other encoded now (a value PVL cannot carry is refused, never written)."""
    return _pds(value)


def named_refusal(exc: EncodeError, context: Mapping[str, Any]) -> EncodeError:
    """A template's refusal with the keyword filled in: where in its context the value was."""
    return exc.naming(keyword=locate(context, exc.value)) if exc.keyword is None else exc


@cache
def template_environment() -> jinja2.Environment:
    """The one template environment; jinja2 is imported on first use, so commands that
    start long work (JP2 encoding) can render their label in the background."""
    import jinja2

    env = jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(templates_dir())),
        bytecode_cache=_compiled_templates_cache(jinja2),
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
        keep_trailing_newline=True,
        autoescape=False,
        finalize=_finalize,
    )
    env.filters.update(pds=_pds, symbol=_symbol, comments=_comments, keyword=_keyword)
    env.globals.update(
        km=lambda value: Quantity(value, "KM"),
        deg=lambda value: Quantity(value, "DEG"),
        unit=Quantity,
    )
    return env


def _compiled_templates_cache(jinja2: Any) -> Any:
    """Compiled templates kept between runs (~/.cache/pdsgen/templates), so a small product
    does not spend a third of its own time compiling its label template. jinja2 checks each
    entry against the template's source and the Python version, so a stale one is never used;
    a cache that cannot be written is skipped, never a reason for a product to fail."""

    class QuietCache(jinja2.FileSystemBytecodeCache):
        def load_bytecode(self, bucket: Any) -> None:
            try:
                super().load_bytecode(bucket)
            except OSError:
                pass

        def dump_bytecode(self, bucket: Any) -> None:
            try:
                super().dump_bytecode(bucket)
            except OSError:
                pass

    directory = user_cache_dir("templates")
    try:
        directory.mkdir(parents=True, exist_ok=True)
    except OSError:
        return None
    # entries of their own name: one compiled before the output hook (finalize) existed would
    # write values unencoded, and jinja2 checks an entry against the source, not the settings
    return QuietCache(str(directory), "__jinja2_encoded_%s.cache")


def render_label(template_name: str, context: Mapping[str, Any]) -> str:
    """Render one label template into final label text (CR LF, 80-byte lines)."""
    template = template_environment().get_template(template_name)
    try:
        return layout_label(template.render(**context))
    except EncodeError as exc:
        raise named_refusal(exc, context) from None


@dataclass(frozen=True)
class RecordLayout:
    """Record numbers of an attached-label product with FIXED_LENGTH records."""

    record_bytes: int
    label_records: int
    data_records: int

    @property
    def image_pointer(self) -> int:
        """1-based record number where the image starts (^IMAGE)."""
        return self.label_records + 1

    @property
    def file_records(self) -> int:
        return self.label_records + self.data_records

    @property
    def label_bytes(self) -> int:
        return self.label_records * self.record_bytes

    @property
    def file_bytes(self) -> int:
        return self.file_records * self.record_bytes


def settle_attached_label(
    render: Callable[[RecordLayout], str], record_bytes: int, data_records: int
) -> tuple[RecordLayout, str]:
    """Find the label-record count that is consistent with the label's own text.

    The label states LABEL_RECORDS, FILE_RECORDS and ^IMAGE, whose digits change
    its length, which can change LABEL_RECORDS again; iterate until it stops
    changing instead of trusting a one-shot estimate.
    """
    layout = RecordLayout(record_bytes, 1, data_records)
    for _ in range(64):
        text = render(layout)
        needed = max(1, math.ceil(len(text.encode("ascii")) / record_bytes))
        if needed == layout.label_records:
            return layout, text
        layout = RecordLayout(record_bytes, needed, data_records)
    raise RuntimeError("label record count did not converge")


def pad_label(text: str, layout: RecordLayout) -> bytes:
    """The label bytes padded with spaces to fill its records exactly."""
    raw = text.encode("ascii")
    if len(raw) > layout.label_bytes:
        raise ValueError("label text is longer than its reserved records")
    return raw + b" " * (layout.label_bytes - len(raw))
