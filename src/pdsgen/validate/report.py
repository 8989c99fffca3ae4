"""A validation run's result and its three renderings: text for people, JSON and JUnit XML for CI.

Exit status: 0 when no file has an error (and, with strict, no warning), 1 otherwise.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field

from lxml import etree

from .model import Finding


@dataclass
class FileReport:
    path: str
    findings: list[Finding] = field(default_factory=list)

    def count(self, severity: str) -> int:
        return sum(1 for f in self.findings if f.severity == severity)


@dataclass
class Report:
    files: list[FileReport]
    strict: bool = False

    @property
    def findings(self) -> list[Finding]:
        return [f for r in self.files for f in r.findings]

    def count(self, severity: str) -> int:
        return sum(r.count(severity) for r in self.files)

    def failed(self, report: FileReport) -> bool:
        return report.count("error") > 0 or (self.strict and report.count("warning") > 0)

    @property
    def exit_code(self) -> int:
        return 1 if any(self.failed(r) for r in self.files) else 0

    def summary(self) -> dict:
        return {
            "files": len(self.files),
            "files_failed": sum(1 for r in self.files if self.failed(r)),
            "errors": self.count("error"),
            "warnings": self.count("warning"),
            "info": self.count("info"),
            "strict": self.strict,
            "exit_code": self.exit_code,
        }

    def summary_line(self) -> str:
        """One line for people: counts and the verdict (what the demo prints)."""
        s = self.summary()
        verdict = "FAILED" if s["exit_code"] else "OK"
        return (f"{s['files']} file(s) checked: {s['errors']} error(s), {s['warnings']} warning(s), "
                f"{s['info']} info{' (strict)' if self.strict else ''} - {verdict}")

    def rule_ids(self, severity: str | None = None) -> set[str]:
        return {f.rule for f in self.findings if severity is None or f.severity == severity}


def _where(f: Finding) -> str:
    return f"{f.file}:{f.line}" if f.line else f.file


def render_text(report: Report, show_info: bool = True) -> str:
    lines = []
    for file_report in report.files:
        for f in file_report.findings:
            if f.severity == "info" and not show_info:
                continue
            keyword = f" {f.keyword}:" if f.keyword else ""
            lines.append(f"{_where(f)}: {f.severity} [{f.rule}]{keyword} {f.message}")
    lines.append(report.summary_line())
    return "\n".join(lines) + "\n"


def render_json(report: Report) -> str:
    files = [
        {
            "path": r.path,
            "passed": not report.failed(r),
            "errors": r.count("error"),
            "warnings": r.count("warning"),
            "info": r.count("info"),
            "findings": [f.as_dict() for f in r.findings],
        }
        for r in report.files
    ]
    return json.dumps({"files": files, "summary": report.summary()}, indent=2) + "\n"


def render_junit(report: Report) -> str:
    """One testsuite, one testcase per file; errors (and warnings when strict) are failures."""
    s = report.summary()
    suites = etree.Element("testsuites", name="pdsgen validate", tests=str(s["files"]),
                           failures=str(s["files_failed"]), errors="0")
    suite = etree.SubElement(suites, "testsuite", name="pdsgen validate", tests=str(s["files"]),
                             failures=str(s["files_failed"]), errors="0", skipped="0")
    for r in report.files:
        case = etree.SubElement(suite, "testcase", classname="pdsgen.validate", name=r.path)
        failing = [f for f in r.findings if f.severity == "error" or (report.strict and f.severity == "warning")]
        if failing:
            failure = etree.SubElement(
                case, "failure", type=failing[0].rule,
                message=f"{len(failing)} problem(s), first [{failing[0].rule}] {failing[0].message}"[:500],
            )
            failure.text = "\n".join(f"{_where(f)}: {f.severity} [{f.rule}] {f.message}" for f in failing)
        others = [f for f in r.findings if f not in failing]
        if others:
            out = etree.SubElement(case, "system-out")
            out.text = "\n".join(f"{_where(f)}: {f.severity} [{f.rule}] {f.message}" for f in others)
    return etree.tostring(suites, pretty_print=True, xml_declaration=True, encoding="UTF-8").decode()


def render(report: Report, fmt: str) -> str:
    return {"text": render_text, "json": render_json, "junit": render_junit}[fmt](report)
