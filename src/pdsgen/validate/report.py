"""A validation run's result and its renderings: text for people; JSON, JUnit XML, SARIF and
GitHub workflow commands for CI.

Every format is written as a stream: a file's findings go out as soon as the file is
checked, and only the counts are kept, so a run over 100,000 labels holds no more than
one directory's reports at a time. Label text can hold any byte; every format escapes
what its syntax cannot carry (XML 1.0 forbids most control characters; workflow commands
end at a line break), so no label can break or crash a report.

Exit status: 0 when no file has a finding at or above the fail-on level (error, or
warning with --strict / fail-on = "warning"), 1 otherwise.
"""

from __future__ import annotations

import io
import json
import os
import tempfile
from abc import ABC, abstractmethod
from collections.abc import Iterable
from dataclasses import dataclass, field
from json.encoder import encode_basestring_ascii
from typing import IO, Any
from urllib.parse import quote

from lxml import etree

from ..encode import shown, shown_lines
from .model import Finding

FORMATS = ("text", "json", "junit", "sarif", "github", "html")
# Findings that mean "still to be written": delivery text placeholders (DLV-006) and the products'
# identification keywords left UNK (DLV-007 PDS3, DLV-008 PDS4). Counted apart in every summary
# (`placeholders`), so a run that passes with some left is not taken for a finished delivery.
PLACEHOLDER_RULES = frozenset({"DLV-006", "DLV-007", "DLV-008"})
FAIL_LEVELS = ("error", "warning")


@dataclass
class FileReport:
    path: str
    findings: list[Finding] = field(default_factory=list)

    def count(self, severity: str) -> int:
        return sum(1 for f in self.findings if f.severity == severity)

    @property
    def placeholders(self) -> int:
        return sum(1 for f in self.findings if f.rule in PLACEHOLDER_RULES)


def failing_severities(fail_on: str) -> tuple[str, ...]:
    """The severities that fail a run whose fail-on level is `fail_on`."""
    return ("error",) if fail_on == "error" else ("error", "warning")


def fails(report: FileReport, fail_on: str) -> bool:
    """True when the file has a finding at or above the fail-on level."""
    levels = failing_severities(fail_on)
    return any(f.severity in levels for f in report.findings)


@dataclass
class Tally:
    """The counts a summary needs, accumulated file by file."""

    fail_on: str = "error"
    files: int = 0
    files_failed: int = 0
    errors: int = 0
    warnings: int = 0
    info: int = 0
    baseline_suppressed: int = 0
    dictionary: str = ""
    placeholders: int = 0  # findings of PLACEHOLDER_RULES: text and keywords still to be written

    @property
    def strict(self) -> bool:
        return self.fail_on == "warning"

    def add(self, report: FileReport) -> None:
        self.files += 1
        self.files_failed += fails(report, self.fail_on)
        self.errors += report.count("error")
        self.warnings += report.count("warning")
        self.info += report.count("info")
        self.placeholders += report.placeholders

    @property
    def exit_code(self) -> int:
        return 1 if self.files_failed else 0

    def summary(self) -> dict:
        out: dict[str, Any] = {
            "files": self.files,
            "files_failed": self.files_failed,
            "errors": self.errors,
            "warnings": self.warnings,
            "info": self.info,
            "placeholders": self.placeholders,
            "strict": self.strict,
            "fail_on": self.fail_on,
            "exit_code": self.exit_code,
        }
        if self.baseline_suppressed:
            out["baseline_suppressed"] = self.baseline_suppressed
        if self.dictionary:
            out["dictionary"] = self.dictionary
        return out

    def summary_line(self) -> str:
        """One line for people: counts and the verdict (what the demo prints)."""
        verdict = "FAILED" if self.exit_code else "OK"
        known = f", {self.baseline_suppressed} known (baseline)" if self.baseline_suppressed else ""
        left = f", {self.placeholders} placeholder(s) still to write" if self.placeholders else ""
        return (f"{self.files} file(s) checked: {self.errors} error(s), {self.warnings} warning(s), "
                f"{self.info} info{known}{left}{' (strict)' if self.strict else ''} - {verdict}")


@dataclass
class ValidationReport:
    """A whole run held in memory (the Python API); the CLI streams instead."""

    files: list[FileReport]
    strict: bool = False
    fail_on: str | None = None
    baseline_suppressed: int = 0
    dictionary: str = ""

    def __post_init__(self) -> None:
        if self.fail_on is None:
            self.fail_on = "warning" if self.strict else "error"
        self.strict = self.fail_on == "warning"

    @property
    def findings(self) -> list[Finding]:
        return [f for r in self.files for f in r.findings]

    def count(self, severity: str) -> int:
        return sum(r.count(severity) for r in self.files)

    def failed(self, report: FileReport) -> bool:
        return fails(report, self.fail_on or "error")

    def tally(self) -> Tally:
        tally = Tally(self.fail_on or "error", baseline_suppressed=self.baseline_suppressed,
                      dictionary=self.dictionary)
        for r in self.files:
            tally.add(r)
        return tally

    @property
    def exit_code(self) -> int:
        return self.tally().exit_code

    def summary(self) -> dict:
        return self.tally().summary()

    def summary_line(self) -> str:
        return self.tally().summary_line()

    def rule_ids(self, severity: str | None = None) -> set[str]:
        return {f.rule for f in self.findings if severity is None or f.severity == severity}


def _where(f: Finding) -> str:
    return f"{f.file}:{f.line}" if f.line else f.file


def finding_line(f: Finding) -> str:
    keyword = f" {f.keyword}:" if f.keyword else ""
    return f"{_where(f)}: {f.severity} [{f.rule}]{keyword} {f.message}"


# -- escaping ---------------------------------------------------------------------------
# One encoder for report text (pdsgen.encode.shown): control characters (a line break too, so
# that a file name or label text cannot start a line of its own - a forged finding, or a CI
# workflow command such as ::error), bidi and other format characters (U+202E), a non-UTF-8
# name's bytes - all escaped; XML 1.0 can carry what it leaves.


def xml_safe(text: str) -> str:
    """Text XML 1.0 can carry, each line shown as a terminal shows it (see `terminal_safe`)."""
    return shown_lines(text)


def terminal_safe(text: str) -> str:
    """Text a terminal shows as written, on one line, in its order: control characters (line
    breaks included, tabs not), format characters and undecodable bytes escaped."""
    return shown(text)


def _gh_data(text: str) -> str:
    return terminal_safe(text.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A"))


def _gh_property(text: str) -> str:
    return _gh_data(text).replace(":", "%3A").replace(",", "%2C")


# -- streaming writers -------------------------------------------------------------------
class Writer(ABC):
    """Writes one format: start(), then file() per checked file, then finish(tally)."""

    def __init__(self, out: IO[str], show_info: bool = True) -> None:
        self.out = out
        self.show_info = show_info

    def start(self) -> None:  # noqa: B027 - optional hook: formats without a header keep it
        """Write what comes before the first file (nothing, unless the format has a header)."""

    @abstractmethod
    def file(self, report: FileReport, failed: bool) -> None:
        """Write one checked file's findings (`failed`: it fails the run)."""

    def finish(self, tally: Tally) -> None:  # noqa: B027 - optional hook: formats without a footer keep it
        """Write what comes after the last file (nothing, unless the format has a footer)."""


class TextWriter(Writer):
    def file(self, report: FileReport, failed: bool) -> None:
        for f in report.findings:
            if f.severity != "info" or self.show_info:
                self.out.write(terminal_safe(finding_line(f)) + "\n")

    def finish(self, tally: Tally) -> None:
        self.out.write(tally.summary_line() + "\n")


class JsonWriter(Writer):
    """{"files": [one object per file], "summary": {...}}, written object by object."""

    def start(self) -> None:
        self.out.write('{\n  "files": [')
        self.first = True

    def file(self, report: FileReport, failed: bool) -> None:
        entry = {
            "path": report.path,
            "passed": not failed,
            "errors": report.count("error"),
            "warnings": report.count("warning"),
            "info": report.count("info"),
        }
        findings = ",\n    ".join(_indented(f.as_dict(), "    ") for f in report.findings)
        # json.dumps(entry + findings, indent=2), values through json's C encoder (its
        # indenting encoder is pure Python, and a report holds thousands of findings)
        text = _indented(entry, "")[:-2] + ',\n  "findings": ' + (f"[\n    {findings}\n  ]" if findings else "[]")
        text = (text + "\n}").replace("\n", "\n    ")
        self.out.write(("\n    " if self.first else ",\n    ") + text)
        self.first = False

    def finish(self, tally: Tally) -> None:
        summary = json.dumps(tally.summary(), indent=2).replace("\n", "\n  ")
        self.out.write(("\n  " if not self.first else "") + f'],\n  "summary": {summary}\n}}\n')


def _encode(value: Any) -> str:
    """json.dumps(value) for the scalars a report holds, strings by json's C function."""
    if isinstance(value, str):
        return encode_basestring_ascii(value)
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "true" if value else "false"
    if type(value) is int:
        return repr(value)
    return json.dumps(value)


def _indented(flat: dict[str, Any], pad: str) -> str:
    """json.dumps(flat, indent=2) of a non-empty dict of scalars, its lines after the first
    indented by `pad`."""
    inner = ",\n".join(f"{pad}  {_encode(key)}: {_encode(value)}" for key, value in flat.items())
    return f"{{\n{inner}\n{pad}}}"


class JunitWriter(Writer):
    """One testsuite, one testcase per file; failing findings are the failure, the rest
    system-out. Totals belong at the top, so test cases are spooled to a temporary file."""

    def start(self) -> None:
        self.spool = tempfile.TemporaryFile("w+", encoding="utf-8")

    def file(self, report: FileReport, failed: bool) -> None:
        case = etree.Element("testcase", classname="pdsgen.validate", name=xml_safe(report.path))
        failing = [f for f in report.findings if failed and f.severity in ("error", "warning")
                   and (f.severity == "error" or self.fail_on_warning)]
        if failing:
            failure = etree.SubElement(
                case, "failure", type=failing[0].rule,
                message=xml_safe(f"{len(failing)} problem(s), first [{failing[0].rule}] {failing[0].message}"[:500]),
            )
            failure.text = xml_safe("\n".join(terminal_safe(finding_line(f)) for f in failing))
        others = [f for f in report.findings if f not in failing]
        if others:
            out = etree.SubElement(case, "system-out")
            out.text = xml_safe("\n".join(terminal_safe(finding_line(f)) for f in others))
        self.spool.write("    " + etree.tostring(case, encoding="unicode").rstrip() + "\n")

    fail_on_warning = False

    def finish(self, tally: Tally) -> None:
        attrs = f'tests="{tally.files}" failures="{tally.files_failed}" errors="0"'
        self.out.write("<?xml version='1.0' encoding='UTF-8'?>\n")
        self.out.write(f'<testsuites name="pdsgen validate" {attrs}>\n')
        self.out.write(f'  <testsuite name="pdsgen validate" {attrs} skipped="0">\n')
        self.spool.seek(0)
        for chunk in iter(lambda: self.spool.read(1 << 16), ""):
            self.out.write(chunk)
        self.spool.close()
        self.out.write("  </testsuite>\n</testsuites>\n")


_SARIF_LEVEL = {"error": "error", "warning": "warning", "info": "note"}


class SarifWriter(Writer):
    """SARIF 2.1.0 (GitHub code scanning): one run, the rule table as the driver's rules,
    one result per finding with the file (relative to the working directory) and line.
    INFO findings are notes (an offset convention detected ...), not something to fix: code
    scanning would show each as an alert, so they are left out (the summary counts them)."""

    def start(self) -> None:
        from .. import __version__
        from .registry import rules

        driver = {
            "name": "pdsgen validate",
            "version": __version__,
            "rules": [
                {"id": r.id, "name": r.id.replace("-", ""),
                 "shortDescription": {"text": r.summary},
                 "defaultConfiguration": {"level": _SARIF_LEVEL[r.severity]}}
                for r in rules().values()
            ],
        }
        head = {"$schema": "https://json.schemastore.org/sarif-2.1.0.json", "version": "2.1.0"}
        text = json.dumps(head, indent=2)[:-2]
        self.out.write(text + ',\n  "runs": [\n    {\n      "tool": {"driver": '
                       + json.dumps(driver) + '},\n      "results": [')
        self.first = True

    def file(self, report: FileReport, failed: bool) -> None:
        for f in report.findings:
            if f.severity == "info":
                continue
            location: dict[str, Any] = {"artifactLocation": {"uri": _uri(f.file)}}
            if f.line:
                location["region"] = {"startLine": f.line}
            result = {
                "ruleId": f.rule,
                "level": _SARIF_LEVEL.get(f.severity, "note"),
                "message": {"text": shown((f"{f.keyword}: " if f.keyword else "") + f.message)},
                "locations": [{"physicalLocation": location}],
            }
            self.out.write(("\n        " if self.first else ",\n        ") + json.dumps(result))
            self.first = False

    def finish(self, tally: Tally) -> None:
        self.out.write("\n      ],\n      \"properties\": " + json.dumps(tally.summary())
                       + "\n    }\n  ]\n}\n")


def _uri(path: str) -> str:
    """A file as a SARIF artifact URI: relative to the working directory, forward slashes."""
    try:
        rel = os.path.relpath(path)
    except ValueError:
        rel = path
    plain = rel.replace(os.sep, "/") if not rel.startswith("..") else os.path.abspath(path).replace(os.sep, "/")
    return quote(os.fsencode(plain), safe="/:")  # a URI: a non-ASCII name's own bytes, percent-encoded


_GH_COMMAND = {"error": "error", "warning": "warning", "info": "notice"}


class GithubWriter(Writer):
    """GitHub Actions workflow commands: one annotation per error or warning, with file and line.
    INFO findings are notes, not annotations to act on: left out (the summary line counts them)."""

    def file(self, report: FileReport, failed: bool) -> None:
        for f in report.findings:
            if f.severity == "info":
                continue
            props = f"file={_gh_property(f.file)}" + (f",line={f.line}" if f.line else "")
            props += f",title={_gh_property(f.rule + (' ' + f.keyword if f.keyword else ''))}"
            self.out.write(f"::{_GH_COMMAND.get(f.severity, 'notice')} {props}::{_gh_data(f.message)}\n")

    def finish(self, tally: Tally) -> None:
        self.out.write(tally.summary_line() + "\n")


WRITERS: dict[str, type[Writer]] = {
    "text": TextWriter, "json": JsonWriter, "junit": JunitWriter, "sarif": SarifWriter, "github": GithubWriter,
}


def write_stream(reports: Iterable[FileReport], fmt: str, out: IO[str], tally: Tally,
                 show_info: bool = True, writer_class: type[Writer] | None = None) -> Tally:
    """Render file reports as they come; returns the tally (for the exit code).

    writer_class: a format written by a higher layer (html: the review page, pdsgen.review)."""
    writer = (writer_class or WRITERS[fmt])(out, show_info)
    if isinstance(writer, JunitWriter):
        writer.fail_on_warning = tally.fail_on == "warning"
    writer.start()
    for report in reports:
        tally.add(report)
        writer.file(report, fails(report, tally.fail_on))
    writer.finish(tally)
    return tally


def render(report: ValidationReport, fmt: str) -> str:
    """The whole report in one format, as a string."""
    buffer = io.StringIO()
    tally = Tally(report.fail_on or "error", baseline_suppressed=report.baseline_suppressed,
                  dictionary=report.dictionary)
    write_stream(report.files, fmt, buffer, tally)
    return buffer.getvalue()


def render_text(report: ValidationReport, show_info: bool = True) -> str:
    buffer = io.StringIO()
    write_stream(report.files, "text", buffer, Tally(report.fail_on or "error",
                 baseline_suppressed=report.baseline_suppressed), show_info)
    return buffer.getvalue()
