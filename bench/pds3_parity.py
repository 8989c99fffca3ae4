"""PDS3 parity: pdsgen validate against NASA's PDS3 tools on their own JUnit tests.

Usage: python bench/pds3_parity.py PDS3_TOOLS_CHECKOUT [--cases FILE] [--json OUT] [--only ID,...]
                                   [--strict] [--nasa-severities] [--no-set-aside]

PDS3_TOOLS_CHECKOUT is a checkout of NASA-PDS/pds3-product-tools (pinned: PINNED_COMMIT);
the labels and test dictionaries are read from it (src/test-data). The cases are
bench/pds3_parity_cases.json, written by hand from the JUnit tests under src/test/: one
per test method that runs a label through NASA's parser (and validator), with the
problems it asserts (NASA ProblemType, line, message key), the asserted total if any,
and which run it makes ("validate": with the tests' dictionary, pdsdd.full merged with
testdd.full, in place of the validator's own; "default": the validator's own dictionary;
"parse": the parser alone). Each label is run once per run kind through pdsgen's
validator in this process, and compared:

- the verdict: NASA's (an ERROR-severity ProblemType among the problems in the case's
  scope) against pdsgen's (an error finding in that scope). A case asserting the total
  has the whole label as scope (NASA's problems: all those asserted on the label, plus
  the unasserted ones the case table records); otherwise the lines it asserts.
- the lines: each problem NASA asserts at a line, found by pdsgen at that line under a
  rule MAPPING gives for its type; and where found, whether the severity is NASA's.

pdsgen findings NASA's run cannot make are set aside (SET_ASIDE, with the reason), and
every disagreement is printed with its reason: a MAPPING row's (a severity the policy
sets otherwise), BY_DESIGN's (a check NASA's library does not make), or REASONS' for
the case; a disagreement without a reason is a defect to fix.
`--strict` runs pdsgen as `pdsgen validate --strict` does (ranges, lengths and
over-long lines then errors), and `--nasa-severities` with the severity settings of
NASA_LEVELS (what a user gets with `--severity DICT-001=error` ...), for comparison: what
remains then is not a matter of severity.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "src"))

PINNED_COMMIT = "16f7c86a618ae412e10dd69101d916cb1b0e26a8"  # NASA-PDS/pds3-product-tools, 2025-12-26
CASES = Path(__file__).with_name("pds3_parity_cases.json")
TEST_DATA = Path("src/test-data")
LINE_LENGTH_RULES = frozenset({"FILE-004", "FILE-005"})

# NASA's ProblemType severities (Constants.ProblemType), for the types the tests assert;
# MISSING_FILE stands for the exception the parser throws for a missing file.
NASA_SEVERITY = {
    "PARSE_ERROR": "error", "UNKNOWN_KEY": "error", "UNKNOWN_VALUE_TYPE": "error", "UNKNOWN_VALUE": "warning",
    "TYPE_MISMATCH": "error", "INVALID_VALUE": "error", "MANIPULATED_VALUE": "warning", "INVALID_TYPE": "error",
    "MISSING_MEMBER": "error", "EXCESSIVE_LINE_LENGTH": "warning", "WRONG_LINE_LENGTH": "warning",
    "ILLEGAL_LINE_ENDING": "error", "MISSING_ID": "error", "MISSING_VALUE": "warning", "SHORT_VALUE": "error",
    "BAD_VALUE": "error", "EXCESSIVE_VALUE_LENGTH": "error", "OOR": "error", "INVALID_DATE": "error",
    "CIRCULAR_POINTER_REF": "error", "PLACEHOLDER_VALUE": "info", "ATTACHED_START_BYTE_MISMATCH": "error",
    "START_BYTE_POSSIBLE_MISMATCH": "warning", "MISSING_FILE": "error", "MISSING_RESOURCE": "error",
}

# NASA ProblemType -> (pdsgen rules that report the same problem; the severities pdsgen
# gives it by design where they differ from NASA's; why). The one table of correspondence:
# a severity not NASA's and not listed here is a defect.
WARN, INFO, ERR = frozenset({"warning"}), frozenset({"info"}), frozenset({"error"})
MAPPING: dict[str, tuple[tuple[str, ...], frozenset[str], str]] = {
    "PARSE_ERROR": (("SYNTAX-001", "SYNTAX-005"), frozenset(), "a statement that does not parse"),
    "MISSING_ID": (("SYNTAX-001", "SYNTAX-002"), frozenset(), "a statement without a keyword"),
    "MISSING_VALUE": (("SYNTAX-009", "SYNTAX-013"), ERR,
                      "a keyword without a value: a warning where its line ends after '=' (NASA, pvl and pdr "
                      "read the value as empty); pdsgen's error where ')', ',' or '=' follows the '=' (no reader "
                      "has a value to take); an empty \"\" is SYNTAX-013, a warning"),
    "ILLEGAL_LINE_ENDING": (("FILE-002", "FILE-003"), WARN,
                            "lines not ending CR LF; an LF-only detached label is a warning (FILE-003): genuine "
                            "archives hold LF-only copies"),
    "EXCESSIVE_LINE_LENGTH": (("FILE-004",), frozenset(), "a line over 78 characters (a warning in labels pdsgen "
                              "did not write, an error in its own and under --strict)"),
    "WRONG_LINE_LENGTH": (("FILE-005",), frozenset(),
                          "a line of a record-padded attached label not padded to RECORD_BYTES-2 (a warning in "
                          "labels pdsgen did not write, an error in its own and under --strict)"),
    "MISSING_MEMBER": (("REC-001",), frozenset(), "RECORD_TYPE = FIXED_LENGTH without RECORD_BYTES"),
    "ATTACHED_START_BYTE_MISMATCH": (("PTR-004", "PTR-005", "REC-003"), frozenset(),
                                     "attached data do not start where the pointer says"),
    "START_BYTE_POSSIBLE_MISMATCH": (("PTR-006",), INFO,
                                     "attached data begin with blanks: pdsgen's note (NASA: warning) - the pointer "
                                     "may be right, the blanks may be data"),
    "CIRCULAR_POINTER_REF": (("PTR-007",), frozenset(), "a ^STRUCTURE include loop"),
    "UNKNOWN_KEY": (("DICT-001",), WARN,
                    "a keyword not in the dictionary: an error against the dictionaries named (--dictionary, as the "
                    "tests name theirs); pdsgen's warning against its built-in dictionary alone - genuine archives "
                    "carry local keywords"),
    "UNKNOWN_VALUE_TYPE": (("DICT-007",), WARN,
                           "a unit not in the dictionary's list: an error against the dictionaries named; "
                           "pdsgen's warning against its built-in dictionary alone - genuine archives write units "
                           "the list lacks"),
    "UNKNOWN_VALUE": (("DICT-004", "DICT-005", "DICT-010", "DICT-013"), INFO | ERR,
                      "a value outside a keyword's value set: pdsgen's error where the keyword says how to read "
                      "the data, else a warning or a note by the set's kind (STATIC, SUGGESTED, DYNAMIC)"),
    "INVALID_VALUE": (("DICT-004",), WARN,
                      "a value outside a closed value set: an error against the dictionaries named; against the "
                      "built-in one a standard value written with a space for the underscore (\"ASCII INTEGER\") "
                      "is pdsgen's warning: it is recognisable, and genuine archives write layout values so "
                      "(Kaguya MI/TC: BAND_STORAGE_TYPE = \"BAND SEQUENTIAL\")"),
    "MANIPULATED_VALUE": (("DICT-004",), frozenset(), "a standard value written in another case"),
    "TYPE_MISMATCH": (("DICT-002", "DICT-009", "SYNTAX-007", "SYNTAX-008"), INFO,
                      "a value of another type than the keyword's: an error against the dictionaries named; "
                      "against the built-in one an unquoted number for a text keyword is pdsgen's note (DICT-009) "
                      "- every reader takes it as the text"),
    "INVALID_TYPE": (("DICT-002", "SYNTAX-007", "FILE-001"), frozenset(),
                     "a value of the keyword's type written wrongly (non-ASCII text: FILE-001)"),
    "BAD_VALUE": (("SYNTAX-007", "SYNTAX-001", "DICT-002"), frozenset(), "a value no token of the grammar reads"),
    "INVALID_DATE": (("SYNTAX-008", "DICT-002"), frozenset(),
                     "a date or time outside the calendar or written wrongly"),
    "OOR": (("DICT-003",), WARN,
            "a number outside the dictionary range: an error against the dictionaries named, in labels pdsgen "
            "writes and under --strict; a warning in others' labels against the built-in dictionary - genuine "
            "archives break ranges"),
    "SHORT_VALUE": (("DICT-006",), WARN, "a value shorter than the dictionary's minimum length: as OOR"),
    "EXCESSIVE_VALUE_LENGTH": (("DICT-006",), WARN, "a value longer than the dictionary's maximum length: as OOR"),
    "PLACEHOLDER_VALUE": (("DICT-008",), frozenset(), "NULL: a value still to be supplied"),
    "MISSING_FILE": (("USAGE",), frozenset(), "a file named that does not exist"),
    "MISSING_RESOURCE": (("PTR-002", "PTR-010"), WARN | INFO,
                         "a file a pointer names that is not there (no test asserts it): a data file is an "
                         "error (PTR-002), a format file an error in a volume given whole (PTR-010); a document "
                         "is a warning, a catalog file a warning in a volume - no reader misreads the data"),
}

# pdsgen findings set aside: checks NASA's run does not make at all, on labels written to
# test something else.
SET_ASIDE = {
    "SYNTAX-004": "a keyword repeated within an object: NASA's Validator runs no DuplicateIdentifierValidator "
                  "by default, and its test labels repeat a keyword on purpose, one value per line",
}

# pdsgen checks NASA's library does not make: an error finding of these rules where NASA
# reports none is a difference by design.
BY_DESIGN = {
    "REC-002": "pdsgen checks RECORD_BYTES x FILE_RECORDS against the file's size; NASA's label tests use "
               "stub files",
    "REC-003": "pdsgen checks LABEL_RECORDS against where the label ends",
    "REC-005": "pdsgen checks the objects fit the file's records",
    "REC-006": "pdsgen checks the data file holds every byte of each object (the tests' attached stubs do not)",
    "PTR-002": "pdsgen checks that files named by data pointers exist",
    "PTR-004": "pdsgen checks that attached data do not start inside the label",
}

# What --strict makes errors by pdsgen's policy (over-long and unpadded lines of any label).
STRICT_ERRORS = frozenset({"EXCESSIVE_LINE_LENGTH", "WRONG_LINE_LENGTH"})


def by_design(kind: str, strict: bool = False) -> frozenset[str]:
    """The severities pdsgen gives a NASA problem type by design (MAPPING, and --strict's)."""
    levels = MAPPING.get(kind, ((), frozenset(), ""))[1]
    return levels | ERR if strict and kind in STRICT_ERRORS else levels


# --nasa-severities: pdsgen's own severity settings (`pdsgen validate --severity RULE=LEVEL`)
# that give the problems NASA's tools rate otherwise NASA's severity, to show what remains
# when only the severity policy is set aside.
NASA_LEVELS = {"DICT-001": "error", "DICT-003": "error", "DICT-006": "error", "DICT-007": "error",
               "DICT-009": "error", "DICT-010": "warning", "SYNTAX-009": "warning", "PTR-006": "warning"}

# Where NASA and pdsgen place the same problem on different lines, by design: (label, NASA's
# line) -> (pdsgen's line, why).
LINE_SHIFTS: dict[tuple[str, int], tuple[int, str]] = {
    ("sequenceValue.lbl", 5): (6, "NASA gives the line a statement starts on, pdsgen the line of the value "
                                  "in question (the 59-digit integer of MRO:LOOKUP_CONVERSION_TABLE)"),
}

# Why a case disagrees, where neither table above says it (checked by hand on each case).
REASONS: dict[str, str] = {
    "DateTimeFormatterTest.testFractionalSecondsOOR":
        "by design: 2000-12-22T23:59:59.9999 is a valid time (PDS3 allows fractions of up to 9 digits, and NASA "
        "accepts .888888888 on line 45); NASA's reader rounds the fraction to milliseconds (round(1000 x .9999) "
        "= 1000, past the field's 999) and calls the time out of range",
}


@dataclass
class Case:
    id: str
    test: str
    label: str
    run: str
    problems: list[dict]
    count: int | None
    unasserted: list[dict] = field(default_factory=list)
    note: str = ""


def read_cases(path: Path = CASES) -> tuple[dict, list[Case]]:
    """The case table: its header (repository, commit ...) and its cases."""
    doc = json.loads(path.read_text(encoding="utf-8"))
    cases = [Case(c["id"], c["test"], c["label"], c["run"], c["problems"], c["count"], c.get("unasserted", []),
                  c.get("note", "")) for c in doc["cases"]]
    return doc, cases


@dataclass
class Finding:
    rule: str
    severity: str
    line: int | None
    message: str


def run_pdsgen(label: Path, run: str, dictionaries: tuple[str, ...], strict: bool = False,
               levels: dict[str, str] | None = None) -> list[Finding]:
    """pdsgen's findings on one label for one kind of NASA run, minus those set aside;
    `levels` are severity settings (rule -> severity) as --severity gives them."""
    from pdsgen.errors import PdsgenError
    from pdsgen.validate import RuleSettings, validate_paths

    try:
        report = validate_paths([label], dictionaries=dictionaries if run == "validate" else (), strict=strict,
                                settings=RuleSettings(severity=levels or {}))
    except PdsgenError as exc:
        return [Finding("USAGE", "error", None, str(exc))]
    kept = []
    for f in report.findings:
        if f.rule in SET_ASIDE:
            continue
        if run == "parse" and (f.rule.startswith("DICT-") or f.rule in LINE_LENGTH_RULES):
            continue  # NASA's parser alone checks no dictionary and no line length
        kept.append(Finding(f.rule, f.severity, f.line, f.message))
    return kept


def label_problems(cases: list[Case]) -> dict[tuple[str, str], list[dict]]:
    """NASA's problems per (label, run): every problem asserted on it, plus the unasserted ones."""
    found: dict[tuple[str, str], list[dict]] = {}
    for case in cases:
        known = found.setdefault((case.label, case.run), [])
        for problem in case.problems + case.unasserted:
            if problem not in known:
                known.append(problem)
    return found


def nasa_error(problems: list[dict]) -> bool:
    """An ERROR ProblemType among these; an unasserted problem of unknown type counts as none."""
    return any(NASA_SEVERITY.get(p.get("type") or "", "") == "error" for p in problems)


@dataclass
class Outcome:
    case: Case
    status: str  # agree / false-error / missed-error / not-comparable
    nasa: bool = False
    ours: list[Finding] = field(default_factory=list)  # pdsgen's error findings in scope
    reason: str = ""


def compare(case: Case, findings: list[Finding], on_label: list[dict], strict: bool = False) -> Outcome:
    """The case's verdict against pdsgen's, in the case's scope (see the module docstring)."""
    if case.count is None and not case.problems:
        return Outcome(case, "not-comparable", reason=case.note)
    whole = case.count is not None
    problems = on_label if whole else case.problems
    lines = {p.get("line") for p in problems}
    errors = [f for f in findings if f.severity == "error" and (whole or f.line in lines or None in lines)]
    nasa = nasa_error(problems)
    if bool(errors) == nasa:
        return Outcome(case, "agree", nasa, errors)
    status = "false-error" if errors else "missed-error"
    return Outcome(case, status, nasa, errors, explain(case, status, problems, errors, findings, strict))


def explain(case: Case, status: str, problems: list[dict], errors: list[Finding], findings: list[Finding],
            strict: bool = False) -> str:
    """The reason for a disagreement: the case's own (REASONS), a by-design check
    (BY_DESIGN), or MAPPING rows whose by-design severities account for it; "" when none
    applies (a defect)."""
    if case.id in REASONS:
        return REASONS[case.id]
    if status == "false-error":
        reasons = [_why_error(f, problems, strict) for f in errors]
        return "" if not all(reasons) else "by design: " + "; ".join(sorted(set(reasons)))
    nasa_errors = [p for p in problems if NASA_SEVERITY.get(p.get("type") or "") == "error"]
    reasons = [_why_not_error(p, findings, strict) for p in nasa_errors]
    return "" if not all(reasons) else "by design: " + "; ".join(sorted(set(reasons)))


def _why_error(finding: Finding, problems: list[dict], strict: bool) -> str:
    """Why pdsgen's error is one where NASA has none: a check NASA does not make, or a
    problem NASA reports at that line at a lower severity that pdsgen's policy rates an error."""
    if finding.rule in BY_DESIGN:
        return BY_DESIGN[finding.rule]
    for p in problems:
        rules, _, why = MAPPING.get(p.get("type") or "", ((), frozenset(), ""))
        if finding.rule in rules and p.get("line") in (None, finding.line) and "error" in by_design(p["type"], strict):
            return why
    return ""


def _why_not_error(problem: dict, findings: list[Finding], strict: bool) -> str:
    """Why pdsgen has no error for a NASA error: it reports it at a severity MAPPING lists."""
    rules, _, why = MAPPING.get(problem["type"], ((), frozenset(), ""))
    for f in findings:
        at_line = problem.get("line") in (None, f.line)
        if f.rule in rules and at_line and f.severity in by_design(problem["type"], strict):
            return why
    return ""


def line_agreement(cases: list[Case], findings: dict[tuple[str, str], list[Finding]]) -> list[tuple]:
    """Each problem NASA asserts at a line (once per label and run): (label, type, line,
    NASA severity, pdsgen's severity at that line under a mapped rule or None)."""
    seen, rows = set(), []
    for case in cases:
        for p in case.problems:
            key = (case.label, case.run, p["type"], p["line"])
            if p["line"] is None or key in seen:
                continue
            seen.add(key)
            rules = MAPPING.get(p["type"], ((), frozenset(), ""))[0]
            line = LINE_SHIFTS.get((case.label, p["line"]), (p["line"], ""))[0]
            levels = [f.severity for f in findings[(case.label, case.run)] if f.rule in rules and f.line == line]
            nasa = NASA_SEVERITY[p["type"]]
            ours = nasa if nasa in levels else (min(levels, key=("error", "warning", "info").index) if levels else None)
            rows.append((case.label, p["type"], p["line"], nasa, ours))
    return rows


def run_all(checkout: Path, cases: list[Case], strict: bool = False, levels: dict[str, str] | None = None
            ) -> tuple[list[Outcome], list[tuple], dict[tuple[str, str], list[Finding]]]:
    """Every case compared; pdsgen runs once per (label, run kind)."""
    labels = checkout / TEST_DATA / "labels"
    dictionaries = tuple(str(checkout / TEST_DATA / name) for name in ("pdsdd.full", "testdd.full"))
    findings = {key: run_pdsgen(labels / key[0], key[1], dictionaries, strict, levels)
                for key in dict.fromkeys((c.label, c.run) for c in cases)}
    on_label = label_problems(cases)
    outcomes = [compare(c, findings[(c.label, c.run)], on_label[(c.label, c.run)], strict) for c in cases]
    return outcomes, line_agreement(cases, findings), findings


def label_verdicts(cases: list[Case], findings: dict) -> Counter:
    """(NASA error, pdsgen error) per label and run kind, over the whole label."""
    problems = label_problems(cases)
    return Counter((nasa_error(problems[key]), any(f.severity == "error" for f in found))
                   for key, found in findings.items()
                   if any(c.count is not None or c.problems for c in cases if (c.label, c.run) == key))


def report(outcomes: list[Outcome], lines: list[tuple], labels: Counter, elapsed: float, strict: bool = False) -> None:
    comparable = [o for o in outcomes if o.status != "not-comparable"]
    table = Counter((o.nasa, bool(o.ours)) for o in comparable)
    agree = sum(o.status == "agree" for o in comparable)
    print(f"NASA-PDS/pds3-product-tools JUnit cases: {len(outcomes)} ({elapsed:.1f} s); comparable: "
          f"{len(comparable)}")
    print()
    print("                     pdsgen: error   pdsgen: no error")
    print(f"NASA: error          {table[(True, True)]:>13}   {table[(True, False)]:>16}")
    print(f"NASA: no error       {table[(False, True)]:>13}   {table[(False, False)]:>16}")
    print()
    print(f"agreement on the error verdict: {agree}/{len(comparable)} = {100 * agree / max(len(comparable), 1):.1f} %")
    data = sum(o.status == "false-error" and all(f.rule in BY_DESIGN for f in o.ours) for o in comparable)
    rest = len(comparable) - data
    print(f"  leaving out the {data} cases where only pdsgen's checks of the data against the label (BY_DESIGN) "
          f"fail: {agree}/{rest} = {100 * agree / max(rest, 1):.1f} %")
    same = sum(labels[(v, v)] for v in (True, False))
    print(f"labels (whole label): {same}/{sum(labels.values())} agree; false errors {labels[(False, True)]}, "
          f"misses {labels[(True, False)]}")
    found = [row for row in lines if row[4] is not None]
    print(f"problem lines: {len(found)}/{len(lines)} = {100 * len(found) / max(len(lines), 1):.1f} % found by pdsgen "
          "at NASA's line (under a mapped rule)")
    same_level = sum(row[3] == row[4] for row in found)
    print(f"severity where both report the line: {same_level}/{len(found)} = "
          f"{100 * same_level / max(len(found), 1):.1f} % the same")
    for status in ("false-error", "missed-error"):
        chosen = [o for o in outcomes if o.status == status]
        if chosen:
            print()
            print(f"{status} ({len(chosen)}; {sum(not o.reason for o in chosen)} without a reason, i.e. defects):")
        for o in chosen:
            nasa = ", ".join(f"{p['type']}@{p['line']}" for p in o.case.problems) or f"{o.case.count} problem(s)"
            print(f"  {o.case.id} [{o.case.label}] NASA: {nasa}")
            print(f"      reason: {o.reason or 'DEFECT (no reason known)'}")
            for f in o.ours[:3]:
                print(f"      pdsgen: {f.rule} {f.severity} line {f.line}: {f.message[:110]}")
    missing = [row for row in lines if row[4] is None]
    if missing:
        print()
        print(f"NASA's problem lines pdsgen does not report ({len(missing)}):")
        for label, kind, line, _, _ in missing:
            print(f"  {label}:{line} {kind} (pdsgen rules {', '.join(MAPPING.get(kind, ((), frozenset(), ''))[0])})")
    other = [row for row in found if row[3] != row[4]]
    if other:
        print()
        print(f"severities that differ ({len(other)}), by type (by design: the MAPPING row says why):")
        for (kind, nasa, ours), n in Counter((r[1], r[3], r[4]) for r in other).most_common():
            verdict = "by design" if ours in by_design(kind, strict) else "DEFECT"
            print(f"  {n:>3}  {kind}: NASA {nasa}, pdsgen {ours} ({verdict})")
    skipped = [o for o in outcomes if o.status == "not-comparable"]
    if skipped:
        print()
        print(f"not comparable ({len(skipped)}):")
        for o in skipped:
            print(f"  {o.case.id} [{o.case.label}]: {o.reason}")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("checkout", type=Path, help="a checkout of NASA-PDS/pds3-product-tools")
    parser.add_argument("--cases", type=Path, default=CASES, help="the case table (JSON)")
    parser.add_argument("--json", type=Path, help="write every case's outcome here")
    parser.add_argument("--only", default="", help="comma-separated case ids (Class.method) or label names")
    parser.add_argument("--strict", action="store_true", help="run pdsgen as --strict does")
    parser.add_argument("--no-set-aside", action="store_true",
                        help="count the findings SET_ASIDE lists too (a repeated keyword: SYNTAX-004)")
    parser.add_argument("--nasa-severities", action="store_true",
                        help="give the rules of NASA_LEVELS NASA's severity (pdsgen's --severity settings)")
    options = parser.parse_args()
    checkout = options.checkout.resolve()
    if not (checkout / TEST_DATA / "labels").is_dir():
        print(f"{checkout}: no {TEST_DATA}/labels here; give a checkout of NASA-PDS/pds3-product-tools "
              f"(pinned commit {PINNED_COMMIT})", file=sys.stderr)
        return 2
    doc, cases = read_cases(options.cases)
    if doc["commit"] != PINNED_COMMIT:
        print(f"note: the case table was written at {doc['commit']}, the bench pins {PINNED_COMMIT}", file=sys.stderr)
    if options.only:
        wanted = set(options.only.split(","))
        cases = [c for c in cases if c.id in wanted or c.label in wanted]
    if options.no_set_aside:
        SET_ASIDE.clear()
    started = time.monotonic()
    levels = NASA_LEVELS if options.nasa_severities else None
    outcomes, lines, findings = run_all(checkout, cases, options.strict, levels)
    report(outcomes, lines, label_verdicts(cases, findings), time.monotonic() - started, options.strict)
    if options.json:
        options.json.write_text(json.dumps([{
            "case": o.case.id, "label": o.case.label, "status": o.status, "reason": o.reason, "nasa_error": o.nasa,
            "pdsgen_errors": [f"{f.rule} {f.line}: {f.message}" for f in o.ours]} for o in outcomes], indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
