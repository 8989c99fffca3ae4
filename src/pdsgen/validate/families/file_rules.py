"""FILE family: the label as bytes - ASCII, line ends, line length, first/last statement, padding.

PDS3 labels are 7-bit ASCII with CR LF line ends and at most 78 characters per line
(80 bytes with CR LF). Real archives bend some of this: LF-only copies of detached
labels are reported as warnings; in a file with binary data after the label the line
ends are part of the record arithmetic, so LF there is an error.
"""

from __future__ import annotations

import re
from collections.abc import Iterator

from ...label.grammar import MAX_LINE_CHARS
from ...label.parser import sfdu_problem
from ..context import FileContext
from ..model import Hit
from ..registry import Rule, register

MAX_CONTENT = MAX_LINE_CHARS
_MAX_REPORTED = 10


def _content_lengths(ctx: FileContext) -> list[tuple[int, int, str]]:
    """(line number, content length, ending) for each label line up to END."""
    return [(ln.number, ln.end - ln.start, ln.ending) for ln in ctx.label.lines]


_NOT_TEXT = re.compile(r"[^\x20-\x7e\r\n\t\x00]")
_PDS2_SFDU = re.compile(r"NJPL3IF0PDS2", re.IGNORECASE)  # the SFDU of a PDS version 2 label


def check_ascii(ctx: FileContext) -> Iterator[Hit]:
    label = ctx.label
    if not _NOT_TEXT.search(label.text, 0, label.label_end):
        return
    count = 0
    for ln in label.lines:
        chunk = label.text[ln.start : ln.end]
        bad = [c for c in chunk if ord(c) > 127 or (ord(c) < 32 and c not in "\t\x00")]
        if bad:
            count += 1
            if count <= _MAX_REPORTED:
                codes = ", ".join(f"0x{ord(c):02X}" for c in bad[:4])
                yield Hit(f"byte(s) {codes} are not printable 7-bit ASCII", ln.number)
    if count > _MAX_REPORTED:
        yield Hit(f"{count - _MAX_REPORTED} more lines with non-ASCII bytes")


def _terminated(ctx: FileContext) -> list[tuple[int, str]]:
    """Line endings, ignoring a last line cut off at end of file."""
    return [(ln.number, ln.ending) for ln in ctx.label.lines if ln.ending]


def _data_follows(ctx: FileContext) -> bool:
    """True when binary data really follow the label in this file (not a label-only copy)."""
    return ctx.attached and not ctx.labels_only and ctx.size > ctx.label.label_end


def check_line_ends_error(ctx: FileContext) -> Iterator[Hit]:
    ends = _terminated(ctx)
    if not ends:
        return
    kinds = {e for _, e in ends}
    if kinds == {"CRLF"}:
        return
    if kinds == {"LF"}:
        if _data_follows(ctx):
            yield Hit(
                "label lines end in LF only, expected CR LF; in a file with attached data "
                "the label bytes count in its records",
                ends[0][0],
            )
        return
    wrong = [(n, e) for n, e in ends if e != "CRLF"]
    for n, e in wrong[:_MAX_REPORTED]:
        yield Hit(f"line ends in {e}, expected CR LF (the other lines use CR LF)", n)
    if len(wrong) > _MAX_REPORTED:
        yield Hit(f"{len(wrong) - _MAX_REPORTED} more lines do not end in CR LF")


def check_line_ends_warning(ctx: FileContext) -> Iterator[Hit]:
    ends = _terminated(ctx)
    if ends and {e for _, e in ends} == {"LF"} and not _data_follows(ctx):
        yield Hit("all label lines end in LF only; PDS3 requires CR LF", ends[0][0])


def _padded_width(ctx: FileContext) -> int | None:
    """RECORD_BYTES-2 when an attached fixed-length label pads every line to a record."""
    rb = ctx.record_bytes
    if rb is None or not ctx.attached or ctx.root.text("RECORD_TYPE") != "FIXED_LENGTH":
        return None
    lengths = [n for _, n, _ in _content_lengths(ctx)]
    if len(lengths) >= 2 and sum(1 for n in lengths if n == rb - 2) * 2 > len(lengths):
        return rb - 2
    return None


def check_line_length(ctx: FileContext) -> Iterator[Hit]:
    """An error in labels pdsgen writes (and under --strict); a warning elsewhere, as NASA's
    PDS3 tools rate it: released archives have longer lines (HiRISE DTM DATA_SET_NAME)."""
    if _padded_width(ctx) is not None:
        return
    level = None if ctx.strict or ctx.written_by_pdsgen else "warning"
    long = [(n, c) for n, c, _ in _content_lengths(ctx) if c > MAX_CONTENT]
    for n, c in long[:_MAX_REPORTED]:
        yield Hit(f"line has {c} characters before its line end, at most {MAX_CONTENT}", n, severity=level)
    if len(long) > _MAX_REPORTED:
        yield Hit(f"{len(long) - _MAX_REPORTED} more lines are too long", severity=level)


def check_padded_lines(ctx: FileContext) -> Iterator[Hit]:
    """An error in labels pdsgen writes (and under --strict); a warning elsewhere, as NASA's
    PDS3 tools rate it: the pointer, not the padding, says where the data start, so a reader
    does not misread them, and the label still fits its LABEL_RECORDS (REC-003 checks that)."""
    width = _padded_width(ctx)
    if width is None:
        return
    level = None if ctx.strict or ctx.written_by_pdsgen else "warning"
    for n, c, _ in _content_lengths(ctx):
        if c != width:
            yield Hit(
                f"line has {c} characters; the other lines are padded to {width} "
                f"(RECORD_BYTES {width + 2} with CR LF)",
                n, severity=level,
            )


def check_first_statement(ctx: FileContext) -> Iterator[Hit]:
    label = ctx.label
    if label.first_keyword is None:
        yield Hit("the file holds no label statements (PDS_VERSION_ID = PDS3 first)")
        return
    if label.first_keyword != "PDS_VERSION_ID":
        if label.sfdu and _PDS2_SFDU.search(label.sfdu):
            yield Hit(f"an SFDU-wrapped PDS version 2 label ({label.sfdu[:40]}): no PDS_VERSION_ID; "
                      "checked as far as PDS3 rules apply", label.first_line, label.first_keyword,
                      severity="warning")
        else:
            yield Hit(
                f"first statement is {label.first_keyword}, expected PDS_VERSION_ID",
                label.first_line,
                label.first_keyword,
            )
    for issue in label.issues:
        if issue.rule == "FILE-006":
            yield _sfdu_hit(issue.message, issue.line, issue.keyword, label.sfdu)


def _sfdu_hit(message: str, line: int | None, keyword: str | None, sfdu: str | None) -> Hit:
    """A malformed SFDU head is an error, except where it is a well-formed one with the
    letter l typed for the digit 1 (a Rings Node label of 2003, NASA's SFDULabel.lbl): a
    warning, as NASA's parser accepts it and every reader still finds the label after it."""
    if sfdu and "l" in sfdu and sfdu_problem(sfdu.replace("l", "1")) is None:
        return Hit(f"{message} (the letter l typed for the digit 1: read as the SFDU it spells)", line,
                   keyword, severity="warning")
    return Hit(message, line, keyword)


def check_version(ctx: FileContext) -> Iterator[Hit]:
    """A version other than PDS3 is an error, except PDS2: a PDS version 2 label that says so
    (Phobos 2 volumes) is a deviation genuine archives hold, like the SFDU-wrapped PDS2 labels
    without a PDS_VERSION_ID (FILE-006), and is checked as far as PDS3 rules apply."""
    stmt = ctx.root.get("PDS_VERSION_ID")
    if stmt is None or stmt.value.text.upper() == "PDS3":
        return
    if stmt.value.text.upper() == "PDS2":
        yield Hit("PDS_VERSION_ID is PDS2: a PDS version 2 label, checked as far as PDS3 rules apply",
                  stmt.line, "PDS_VERSION_ID", severity="warning")
    else:
        yield Hit(f"PDS_VERSION_ID is {stmt.value.raw}, expected PDS3", stmt.line, "PDS_VERSION_ID")


def check_end(ctx: FileContext) -> Iterator[Hit]:
    if ctx.size and not ctx.label.end_found:
        yield Hit("no END statement closes the label", len(ctx.label.lines) or None)


def check_empty(ctx: FileContext) -> Iterator[Hit]:
    if ctx.size == 0:
        yield Hit("the file is empty")


def check_tabs(ctx: FileContext) -> Iterator[Hit]:
    label = ctx.label
    lines = [ln.number for ln in label.lines if "\t" in label.text[ln.start : ln.end]]
    if lines:
        yield Hit(f"{len(lines)} line(s) contain tab characters, use spaces", lines[0])


# The gap between END and the first attached object is looked at in its first 16 MiB (a pad is a
# record or so): a pointer's start byte is the label's word, and the file's bytes and this
# window bound the read, not that word (RECORD_BYTES of 10^12 was a MemoryError).
PADDING_WINDOW = 16 * 1024 * 1024


def padding_bytes(ctx: FileContext) -> tuple[int, bytes] | None:
    """(data start, bytes between the END line and the first attached object, as far as the
    file holds them and at most PADDING_WINDOW) if attached."""
    offsets = (ctx.pointer_offset(p) for p in ctx.data_pointers() if p.attached)
    starts = [s for s in offsets if s is not None]
    if not starts:
        return None
    start = min(starts)
    end = ctx.label.label_end
    if start <= end:
        return start, b""
    if start <= len(ctx.head):
        return start, ctx.head[end:start]
    with open(ctx.path, "rb") as fh:
        fh.seek(end)
        return start, fh.read(max(0, min(start, ctx.size, end + PADDING_WINDOW) - end))


def check_padding(ctx: FileContext) -> Iterator[Hit]:
    if not ctx.attached or not ctx.label.end_found:
        return
    found = padding_bytes(ctx)
    if found is None:
        return
    _, pad = found
    stripped = pad.strip(b" \r\n")
    if stripped and not stripped.strip(b"\x00"):
        yield Hit("label is padded with NUL bytes, expected spaces", len(ctx.label.lines))


register(
    Rule("FILE-001", "error", "label bytes are printable 7-bit ASCII", check_ascii),
    Rule("FILE-002", "error", "lines end in CR LF (mixed ends, or LF in a file with attached data)",
         check_line_ends_error),
    Rule("FILE-003", "warning", "a detached label uses LF-only line ends", check_line_ends_warning),
    Rule("FILE-004", "error", "a label line has at most 78 characters (80 bytes with CR LF)",
         check_line_length, note="warning for labels pdsgen did not write, unless --strict: "
         "NASA's PDS3 tools rate it so, and released HiRISE DTM labels have 91-character lines"),
    Rule("FILE-005", "error", "a label padded to its records pads every line to RECORD_BYTES",
         check_padded_lines, note="warning for labels pdsgen did not write, unless --strict: NASA's PDS3 "
         "tools rate it so, and the pointer, not the padding, says where the data start"),
    Rule("FILE-006", "error", "PDS_VERSION_ID is the first statement (after a valid SFDU)",
         check_first_statement, note="warning for SFDU-wrapped PDS version 2 labels (Voyager, "
         "Galileo, Magellan volumes), which have no PDS_VERSION_ID, and for an SFDU head with the letter l "
         "typed for the digit 1"),
    Rule("FILE-007", "error", "an END statement closes the label", check_end),
    Rule("FILE-008", "warning", "the label is padded with spaces (not NUL)", check_padding),
    Rule("FILE-009", "warning", "label lines contain no tab characters", check_tabs),
    Rule("FILE-010", "error", "PDS_VERSION_ID = PDS3", check_version,
         note="warning for PDS version 2 labels (PDS_VERSION_ID = PDS2, Phobos 2 volumes), checked as "
         "far as PDS3 rules apply"),
    Rule("FILE-011", "error", "the file is not empty", check_empty),
    # FILE-013 is reported by the runner for a file named on the command line
    Rule("FILE-013", "error", "a file named for validation is a PDS3 label (not a JP2, TIFF, bare image)",
         None),
    # FILE-012 is reported by the runner itself when a file cannot be opened
    Rule("FILE-012", "error", "the file can be read", None),
)
