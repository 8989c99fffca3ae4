"""What a run reports, for CI: rule selection, per-path ignores, severity overrides, fail-on,
and a baseline of known findings.

Read from `[tool.pdsgen.validate]` in pyproject.toml, or `[validate]` (or
`[tool.pdsgen.validate]`) in pdsgen.toml, found in the working directory or the nearest
parent; command-line flags override it. Like ruff's `select`/`ignore`, entries are rule
ids (`MAP-003`) or whole families (`DICT`); a name that is neither is an error, so a typo
never silently turns a check off.

    [tool.pdsgen.validate]
    select = ["FILE", "SYNTAX", "PTR", "REC", "IMG", "MAP"]
    ignore = ["FILE-004"]
    fail-on = "warning"
    [tool.pdsgen.validate.per-path-ignores]
    "legacy/**" = ["DICT"]
    [tool.pdsgen.validate.severity]
    "DICT-001" = "error"

A baseline (`--write-baseline FILE`) records the findings of today's run; a later run with
`--baseline FILE` reports only findings not in it. Findings are matched by file, rule,
keyword and message (not line: editing a label moves its lines), counted, so a second
identical problem in the same file is new.
"""

from __future__ import annotations

import fnmatch
import json
import os
from collections import Counter
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from ..bounded import load_json, load_toml
from ..errors import PdsgenError
from .model import SEVERITIES, Finding
from .report import FAIL_LEVELS

_KEYS = ("select", "ignore", "per-path-ignores", "severity", "fail-on")
CONFIG_NAMES = ("pdsgen.toml", "pyproject.toml")


@dataclass(frozen=True)
class RuleSettings:
    """Which findings a run keeps, at which severity, and which level fails it."""

    select: frozenset[str] | None = None  # rule ids or families; None: all rules
    ignore: frozenset[str] = frozenset()
    per_path_ignores: tuple[tuple[str, frozenset[str]], ...] = ()
    severity: Mapping[str, str] = field(default_factory=dict)
    fail_on: str = "error"
    source: str | None = None  # the configuration file read, if any

    def keeps(self, rule: str) -> bool:
        return (self.select is None or _matches(rule, self.select)) and not _matches(rule, self.ignore)

    def apply(self, finding: Finding) -> Finding | None:
        """The finding as this configuration reports it, or None when it is not reported."""
        if not self.keeps(finding.rule) or self._ignored_here(finding):
            return None
        level = self.severity.get(finding.rule) or self.severity.get(finding.rule.split("-")[0])
        return replace(finding, severity=level) if level and level != finding.severity else finding

    def _ignored_here(self, finding: Finding) -> bool:
        if not self.per_path_ignores:
            return False
        path = _relative(finding.file)
        return any(_matches(finding.rule, rules) and _path_matches(path, pattern)
                   for pattern, rules in self.per_path_ignores)

    def filter(self, findings: Iterable[Finding]) -> list[Finding]:
        return [kept for f in findings if (kept := self.apply(f)) is not None]


def _matches(rule: str, names: frozenset[str]) -> bool:
    return rule in names or rule.split("-")[0] in names


def _relative(path: str) -> str:
    try:
        rel = os.path.relpath(path)
    except ValueError:
        rel = path
    return rel.replace(os.sep, "/")


def _path_matches(path: str, pattern: str) -> bool:
    """Glob match of a path relative to the working directory ("**" spans directories;
    a pattern without a slash matches the file name anywhere)."""
    pattern = pattern.replace(os.sep, "/").removeprefix("./")
    if "/" not in pattern:
        return fnmatch.fnmatchcase(path.rsplit("/", 1)[-1], pattern)
    return fnmatch.fnmatchcase(path, pattern) or fnmatch.fnmatchcase(path, pattern.replace("/**/", "/"))


def known_names() -> set[str]:
    from .registry import families, rules

    return set(rules()) | set(families())


def _check_names(names: Iterable[str], where: str) -> frozenset[str]:
    known = known_names()
    out = frozenset(str(n).strip().upper() for n in names)
    unknown = sorted(out - known)
    if unknown:
        raise PdsgenError(where, f"unknown rule id(s) {', '.join(unknown)} (see 'pdsgen validate --list-rules')")
    return out


def _check_level(level: Any, where: str, allowed: tuple[str, ...]) -> str:
    text = str(level).strip().lower()
    if text not in allowed:
        raise PdsgenError(where, f"{level!r} is not one of {', '.join(allowed)}")
    return text


def _as_list(value: Any, where: str) -> list[str]:
    if isinstance(value, str):
        return [v for v in value.replace(",", " ").split() if v]
    if isinstance(value, (list, tuple)) and all(isinstance(v, str) for v in value):
        return list(value)
    raise PdsgenError(where, "expected a list of rule ids")


def from_table(table: Mapping[str, Any], where: str) -> RuleSettings:
    """RuleSettings from a configuration table; any unknown key, rule id or level is an error."""
    unknown = sorted(set(table) - set(_KEYS))
    if unknown:
        raise PdsgenError(where, f"unknown setting(s) {', '.join(unknown)}; known: {', '.join(_KEYS)}")
    select = _check_names(_as_list(table["select"], where), where) if "select" in table else None
    ignore = _check_names(_as_list(table.get("ignore", []), where), where)
    paths = table.get("per-path-ignores", {})
    if not isinstance(paths, Mapping):
        raise PdsgenError(where, "per-path-ignores must be a table of glob = [rule ids]")
    per_path = tuple((str(glob), _check_names(_as_list(ids, where), where)) for glob, ids in paths.items())
    levels = table.get("severity", {})
    if not isinstance(levels, Mapping):
        raise PdsgenError(where, "severity must be a table of rule id = \"error\" | \"warning\" | \"info\"")
    _check_names(list(levels), where)
    severity = {str(name).strip().upper(): _check_level(level, where, SEVERITIES) for name, level in levels.items()}
    fail_on = _check_level(table.get("fail-on", "error"), where, FAIL_LEVELS)
    return RuleSettings(select, ignore, per_path, severity, fail_on, where)


def find_config(start: Path | None = None) -> Path | None:
    """The nearest pdsgen.toml, or pyproject.toml with a [tool.pdsgen.validate] table,
    in the working directory or a parent of it."""
    directory = (start or Path.cwd()).resolve()
    for folder in (directory, *directory.parents):
        for name in CONFIG_NAMES:
            candidate = folder / name
            if candidate.is_file() and (name == "pdsgen.toml" or _table(candidate) is not None):
                return candidate
    return None


def _table(path: Path) -> Mapping[str, Any] | None:
    data = load_toml(path, what="configuration file")
    table = data.get("tool", {}).get("pdsgen", {}).get("validate")
    if table is None and path.name == "pdsgen.toml":
        table = data.get("validate", {})
    return table


def load(path: str | os.PathLike[str] | None = None, search: bool = True) -> RuleSettings:
    """RuleSettings from `path`, or from the configuration file found near the working directory
    (when `search`), or the defaults."""
    found = Path(path) if path is not None else (find_config() if search else None)
    if found is None:
        return RuleSettings()
    if not found.is_file():
        raise PdsgenError(found, "no such configuration file")
    table = _table(found)
    return from_table(table or {}, str(found))


def override(settings: RuleSettings, select: Iterable[str] = (), ignore: Iterable[str] = (),
             severity: Iterable[str] = (), fail_on: str | None = None) -> RuleSettings:
    """Command-line flags over the configuration: --select replaces the selection, --ignore
    adds to it, --severity RULE=LEVEL overrides one rule, --fail-on replaces the level."""
    where = "command line"
    changes: dict[str, Any] = {}
    select = [n for item in select for n in _as_list(item, where)]
    if select:
        changes["select"] = _check_names(select, where)
    ignore = [n for item in ignore for n in _as_list(item, where)]
    if ignore:
        changes["ignore"] = settings.ignore | _check_names(ignore, where)
    if severity:
        levels = dict(settings.severity)
        for item in severity:
            name, sep, level = item.partition("=")
            if not sep:
                raise PdsgenError(where, f"--severity {item!r}: expected RULE=LEVEL (e.g. DICT-001=error)")
            (rule,) = _check_names([name], where)
            levels[rule] = _check_level(level, where, SEVERITIES)
        changes["severity"] = levels
    if fail_on is not None:
        changes["fail_on"] = _check_level(fail_on, where, FAIL_LEVELS)
    return replace(settings, **changes) if changes else settings


# -- baseline ------------------------------------------------------------------------------
BASELINE_VERSION = 1


def fingerprint(finding: Finding) -> str:
    """What identifies a finding across runs: file (as given), rule, keyword and message."""
    return "\x1f".join((_relative(finding.file), finding.rule, finding.keyword or "", finding.message))


def write_baseline(path: str | os.PathLike[str], findings: Iterable[Finding]) -> int:
    """Record findings (counted by fingerprint) as JSON; written under a temporary name and
    renamed, so an interrupted run never leaves half a baseline. Returns the number written."""
    counts = Counter(fingerprint(f) for f in findings)
    entries = [dict(zip(("file", "rule", "keyword", "message"), key.split("\x1f"), strict=True), count=n)
               for key, n in sorted(counts.items())]
    from ..storage.staging import staged_file  # only when a baseline is written

    target = Path(path)
    try:
        with staged_file(target, target.with_name(target.name + ".tmp")) as tmp:
            tmp.write_text(json.dumps({"pdsgen_baseline": BASELINE_VERSION, "findings": entries}, indent=1) + "\n",
                           encoding="utf-8")
    except OSError as exc:
        raise PdsgenError(path, f"cannot write the baseline: {exc.strerror or exc}") from None
    return sum(counts.values())


class Baseline:
    """Known findings; `known(finding)` consumes one occurrence of its fingerprint."""

    def __init__(self, counts: Counter[str]) -> None:
        self.remaining = counts
        self.suppressed = 0

    @classmethod
    def read(cls, path: str | os.PathLike[str]) -> Baseline:
        data = load_json(path, what="baseline file")
        if not isinstance(data, dict) or data.get("pdsgen_baseline") != BASELINE_VERSION:
            raise PdsgenError(path, "not a pdsgen baseline (written by 'pdsgen validate --write-baseline')")
        counts: Counter[str] = Counter()
        for entry in data.get("findings", []):
            key = "\x1f".join(str(entry.get(k) or "") for k in ("file", "rule", "keyword", "message"))
            counts[key] += int(entry.get("count", 1))
        return cls(counts)

    def known(self, finding: Finding) -> bool:
        key = fingerprint(finding)
        if self.remaining[key] > 0:
            self.remaining[key] -= 1
            self.suppressed += 1
            return True
        return False
