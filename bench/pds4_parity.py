"""PDS4 parity: pdsgen validate against NASA's validator on NASA's own regression suite.

Usage: python bench/pds4_parity.py VALIDATE_CHECKOUT [--schemas DIR ...] [--absent FILE]
                                   [--json OUT] [--only ISSUE[-SUBTEST],...] [--no-cwd-check]

VALIDATE_CHECKOUT is a checkout of NASA-PDS/validate (pinned: PINNED_COMMIT below); its
Cucumber cases are src/test/resources/features/*.feature, one row per case: the issue, the
test data directory under src/test/resources, validate's arguments and the expected counts
(an omitted totalErrors means 0). Each case pdsgen can run is run in this process, offline
(no download: schemas come from the shipped set, from --schemas DIRs such as a checkout
of the pds.nasa.gov/pds4 mirror sbn-psi/pds4-schema-files, and from the case's own -x/-S
files), and its error verdict (any error finding, or a usage error) compared with NASA's
(totalErrors > 0). Printed: the confusion table, and every disagreement with the
expected message types and pdsgen's error findings, with the reason where it is known
(REASONS below).

How pdsgen is run: directories named are given as directories (pdsgen's own search, which
recognises labels by content); for -R pds4.bundle / pds4.collection on a label, its
directory, so that the delivery checks (DLV-*) run as NASA's referential-integrity checks
do. In runs without those rules NASA makes no integrity check, and pdsgen's DLV findings
are set aside. NASA's options map onto pdsgen's configuration:
--skip-context-validation ignores PDS4-063 (context products), and
--skip-strict-collection-membership reports missing members (DLV-010, DLV-015) as warnings.

Not comparable, and counted apart with the reason: runs configured by files pdsgen does
not read (-c, -M, --target-manifest, --alternate_file_paths, -e with real patterns),
--skip-product-validation runs, integrity runs whose directory holds other bundle or
collection labels than the one named (NASA checks that one, pdsgen the directory; other
versions of the same LID are no such rivals: NASA skips them as not the latest version, and
pdsgen checks each version against its own members), runs on a
directory where pdsgen finds labels by content that NASA's extension filter leaves out
(.lblx, PDS3 .lbl: a different input, not a different verdict; NASA's no_products_found
on a directory of .lblx labels is one of these), cases whose data files are absent from
the checkout (--absent lists them, one path per line relative to the checkout), and cases
where a schema a label names was not found (PDS4-002: the verdict would be on a partial
check). Findings on files NASA's run does not look at are set aside, the bundle and
collection versions an integrity run skips included (_superseded). Each comparable case
is run a second time from another working directory (unless --no-cwd-check) and must give
the same findings.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shlex
import sys
import tempfile
import time
import traceback
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "src"))

PINNED_COMMIT = "df054fd182e4c211af3940e3b570fa020384c7c3"  # NASA-PDS/validate, 2026-08-02
FEATURES = Path("src/test/resources/features")
RESOURCES = Path("src/test/resources")

# Flags taking one value, whose meaning pdsgen has (or that do not change the verdict).
VALUE_FLAGS = {"-R", "--rule", "-x", "--schema", "-S", "--schematron", "-schema", "-schematron", "-C", "--catalog",
               "--label-extension",
               "-v", "--verbose", "-c", "--config", "-e", "--regexp", "-M", "--checksum-manifest",
               "--target-manifest", "-r", "--report-file", "-s", "--report-style", "--alternate",
               "--alternate_file_paths",
               "--add-context-products", "--max-errors", "-progress", "--progress"}
# NASA's --skip-strict-collection-membership reports missing members as warnings: pdsgen's
# configuration does the same with these severities.
LENIENT_MEMBERSHIP = {"DLV-010": "warning", "DLV-015": "warning"}
NOT_COMPARABLE_FLAGS = {
    "-c": "a configuration file", "--config": "a configuration file", "-M": "a checksum manifest",
    "--checksum-manifest": "a checksum manifest",
    "--target-manifest": "a target manifest", "--alternate": "alternate file paths",
    "--alternate_file_paths": "alternate file paths",
}
# Rules that check a bundle's or collection's integrity (pds4.folder checks a directory's
# labels one by one, as a run on a directory does by default).
DELIVERY_RULES = {"pds4.bundle", "pds4.collection"}
_EXTENSION = re.compile(r"\*?\.?([A-Za-z0-9]+)")

# Why pdsgen and NASA differ on a case (case id -> reason), checked by hand on each case.
REASONS: dict[str, str] = {
    "173-2": "NASA reads a collection's inventory in an integrity run even with --skip-content-validation "
             "(records_mismatch); pdsgen's --labels-only reads no data file, inventories included",
    "209-2": "NASA accepts bit fields 20-23 overlapping 23-... here yet reports the same kind of overlap in "
             "392-2; pdsgen reports both",
    "71-1": "NASA's errors come from its XML catalog of this case (5 unresolvable resources); with the "
            "same schema files resolved by name, pdsgen finds the label valid against them",
    "71-2": "as 71-1",
}


@dataclass
class Case:
    id: str
    feature: str
    datasrc: Path
    args: list[str]
    expectation: dict[str, int]
    targets: list[Path] = field(default_factory=list)
    schema_files: list[Path] = field(default_factory=list)
    schema_dirs: list[Path] = field(default_factory=list)
    labels_only: bool = False
    integrity: bool = False  # -R pds4.bundle / pds4.collection: the directory's integrity too
    lenient_membership: bool = False
    skip_context: bool = False
    extension: str = "xml"
    skip: str | None = None

    @property
    def nasa_error(self) -> bool:
        return self.expectation.get("summary:totalErrors", 0) > 0

    @property
    def nasa_types(self) -> list[str]:
        return [k.split(":")[-1] + f"={v}" for k, v in self.expectation.items() if "messageTypes" in k]


_ROW = re.compile(r'^\|\s*(\d+)\s*\|\s*(\d+)\s*\|\s*"([^"]*)"\s*\|\s*"([^"]*)"\s*\|\s*(?:"([^"]*)")?\s*\|\s*$')


def read_cases(checkout: Path) -> list[Case]:
    cases = []
    for feature in sorted((checkout / FEATURES).glob("*.feature")):
        for line in feature.read_text(encoding="utf-8").splitlines():
            match = _ROW.match(line.strip())
            if not match:
                continue
            issue, subtest, datasrc, args, expectation = match.groups()
            source = checkout / RESOURCES / datasrc
            expanded = [_absolute(a.replace("{datasrc}", str(source)).replace("%20", " "), checkout)
                        for a in args.split()]
            expected = {}
            for item in filter(None, (expectation or "").split(",")):
                key, _, value = item.partition("=")
                expected[key.strip()] = int(value)
            cases.append(_parse(Case(f"{issue}-{subtest}", feature.stem, source, expanded, expected)))
    return cases


def _absolute(arg: str, checkout: Path) -> str:
    """validate's tests run in the checkout's root: a relative path is relative to it."""
    return str(checkout / arg) if arg.startswith("src/") else arg


def _parse(case: Case) -> Case:
    """Targets and options of one case; `skip` says why it is not comparable."""
    args, i = case.args, 0
    while i < len(args):
        arg = args[i]
        value = args[i + 1] if i + 1 < len(args) else ""
        if arg in NOT_COMPARABLE_FLAGS:
            case.skip = f"run configured by {NOT_COMPARABLE_FLAGS[arg]}"
        if arg in ("-R", "--rule") and value in DELIVERY_RULES:
            case.integrity = True
        if arg in ("-x", "--schema", "-S", "--schematron", "-schema", "-schematron"):
            case.schema_files.append(Path(value))
        if arg in ("-e", "--regexp"):  # file patterns: comparable when each is an extension (lblx, *.xml)
            extensions = [_EXTENSION.fullmatch(p) for p in value.split(",")]
            if len(extensions) == 1 and extensions[0] is not None:
                case.extension = extensions[0][1]
            else:
                case.skip = "run configured by file-name patterns (-e)"
        if arg in ("-C", "--catalog"):
            case.schema_dirs.append(case.datasrc)  # its catalog maps pds.nasa.gov/pds4 onto the test data
        if arg == "--label-extension":
            case.extension = value.lstrip(".")
        if arg in ("--skip-content-validation", "--no-data-check"):
            case.labels_only = True
        if arg == "--skip-strict-collection-membership":
            case.lenient_membership = True
        if arg == "--skip-context-validation":
            case.skip_context = True
        if arg == "--skip-product-validation":
            case.skip = "--skip-product-validation: only bundle/collection integrity is checked"
        if arg in VALUE_FLAGS:
            i += 2
            continue
        if arg in ("-t", "--target"):
            i += 1
            continue
        if not arg.startswith("-"):
            case.targets.append(Path(arg))
        i += 1
    if not case.targets and case.skip is None:
        case.skip = "no target"
    return case


def _pattern(case: Case) -> str:
    """NASA's label file pattern, in either case (its default is *.xml,*.XML)."""
    return "*." + "".join(f"[{c.lower()}{c.upper()}]" if c.isalpha() else c for c in case.extension)


def label_files(case: Case) -> list[Path]:
    """The labels NASA's validator would check: files named, and files with the label
    extension under directories named (pdsgen would also check PDS3 labels found there)."""
    found: list[Path] = []
    for target in case.targets:
        if target.is_dir():
            found.extend(sorted(p for p in target.rglob(_pattern(case)) if p.is_file()))
        else:
            found.append(target)
    return found


def pdsgen_paths(case: Case) -> list[Path]:
    """What pdsgen is given: the files named, directories as directories (pdsgen's own
    search, by content); for an integrity run (-R pds4.bundle) on a bundle label, the
    bundle's directory, as NASA's validator checks it."""
    return [target.parent if case.integrity and target.is_file() else target for target in case.targets]


def _scope(case: Case, given: list[Path]) -> list[Path]:
    """The labels NASA's run checks on the paths pdsgen is given: files named, and in
    directories (an integrity run's bundle directory included) those of the label extension."""
    return [p for path in given for p in (sorted(path.rglob(_pattern(case))) if path.is_dir() else [path])
            if p.is_file()]


def _found_beyond(given: list[Path], scope: list[Path], discover: Callable[[list[Path]], list[Path]]) -> str:
    """The kinds of label pdsgen finds by content in the directories it is given that NASA's
    extension filter does not select (".lbl, .lblx"), or ""."""
    selected = {p.resolve() for p in scope}
    beyond = {p.suffix.lower() or p.name for d in given if d.is_dir() for p in discover([d])
              if p.resolve() not in selected}
    return ", ".join(sorted(beyond))


def _in_nasa_run(case: Case, rule: str, file: str, checked: set[str], skipped: frozenset[Path] = frozenset()) -> bool:
    """Whether a finding is on what NASA's run checks: the labels it selects (not, say, the
    PDS3 labels pdsgen also finds in a directory), the run as a whole, and in integrity runs
    the delivery checks' findings on any file of the directory but the bundle and collection
    versions the run skips (a superseded version's own members are not looked at)."""
    if rule.startswith("DLV-"):
        return case.integrity and not (file and Path(file).resolve() in skipped)
    return not file or rule == "USAGE" or os.path.normpath(Path(file).resolve()) in checked


def _rivals(case: Case) -> bool:
    """Whether an integrity run's directory holds another label of the kind named (a second
    bundle, or another collection), which pdsgen would check with it. Other versions of the
    one named are no rivals: NASA skips them (_superseded) and pdsgen checks each version
    against its own members."""
    for target in case.targets:
        if target.is_file():
            named = _aggregate(target)
            if named is None:
                continue
            others = (_aggregate(p) for p in target.parent.rglob(_pattern(case)) if p != target)
            if any(other is not None and other.kind == named.kind and other.lid != named.lid for other in others):
                return True
        elif len({a.lid for a in map(_aggregate, target.glob(_pattern(case))) if a and a.kind == "Bundle"}) > 1:
            return True
    return False


@dataclass
class _Aggregate:
    """A bundle or collection label as NASA's integrity run selects among versions."""
    path: Path
    kind: str  # Bundle or Collection
    lid: str
    version: str
    members: list[str]  # a bundle's Bundle_Member_Entry references (LIDVID or LID)

    @property
    def order(self) -> tuple[int, ...]:
        return tuple(int(n) for n in re.findall(r"\d+", self.version))


def _aggregate(path: Path) -> _Aggregate | None:
    """The identity of a bundle or collection label; None for any other file."""
    from lxml import etree

    kind = _product_class(path)
    if kind is None:
        return None
    ns = "{http://pds.nasa.gov/pds4/pds/v1}"
    try:
        root = etree.parse(str(path), etree.XMLParser(no_network=True, resolve_entities=False)).getroot()
    except (OSError, etree.XMLSyntaxError):
        return None
    lid = (root.findtext(f"{ns}Identification_Area/{ns}logical_identifier") or "").strip()
    version = (root.findtext(f"{ns}Identification_Area/{ns}version_id") or "").strip()
    members = [(e.text or "").strip() for tag in ("lidvid_reference", "lid_reference")
               for e in root.iterfind(f"{ns}Bundle_Member_Entry/{ns}{tag}")]
    return _Aggregate(path.resolve(), kind.decode(), lid, version, members)


def _superseded(case: Case, scope: list[Path]) -> set[Path]:
    """Bundle and collection labels an integrity run skips as 'not latest version'
    (AggregateManager @ df054fd: of the bundle labels, the one named or else the latest
    version; of each collection LID, the one named, else the version that bundle lists, else
    the latest). pdsgen checks every version, each against its own members; findings on the
    labels NASA skips are set aside like those on any file its run does not look at."""
    if not case.integrity:
        return set()
    named = {t.resolve() for t in case.targets if t.is_file()}
    groups: dict[tuple[str, str], list[_Aggregate]] = {}
    for aggregate in filter(None, map(_aggregate, scope)):
        groups.setdefault((aggregate.kind, aggregate.lid if aggregate.kind == "Collection" else ""),
                          []).append(aggregate)
    bundles = groups.get(("Bundle", ""), [])
    bundle = next((b for b in bundles if b.path in named), None) or max(bundles, key=lambda b: b.order, default=None)
    listed = set(bundle.members) if bundle is not None else set()
    skipped: set[Path] = set()
    for (kind, lid), versions in groups.items():
        keep = (next((v for v in versions if v.path in named), None)
                or next((v for v in versions if kind == "Bundle" and v is bundle), None)
                or next((v for v in versions if f"{lid}::{v.version}" in listed), None)
                or max(versions, key=lambda v: v.order))
        skipped |= {v.path for v in versions if v is not keep}
    return skipped


def _product_class(path: Path) -> bytes | None:
    try:
        with open(path, "rb") as stream:
            match = re.search(rb"<Product_(Bundle|Collection)[\s>]", stream.read(4096))
    except OSError:
        return None
    return match[1] if match else None


@dataclass
class Outcome:
    case: Case
    status: str  # agree / false-error / missed-error / not-comparable / crash
    reason: str = ""
    errors: list[str] = field(default_factory=list)


def run_case(case: Case, extra_schemas: list[str], absent: set[Path], cwd_check: bool,
             scratch: Path) -> Outcome:
    from pdsgen.errors import PdsgenError
    from pdsgen.validate import RuleSettings, discover, validate_paths

    if case.skip:
        return Outcome(case, "not-comparable", case.skip)
    if any(case.datasrc in path.parents or path.parent == case.datasrc for path in absent):
        return Outcome(case, "not-comparable", "data files of the case are absent from the checkout")
    labels = label_files(case)
    schemas = list(extra_schemas) + [str(d) for d in case.schema_dirs]
    if case.schema_files:
        own = scratch / f"schemas-{case.id}"
        own.mkdir(exist_ok=True)
        for file in case.schema_files:
            if file.is_file() and not (own / file.name).exists():
                (own / file.name).symlink_to(file.resolve())
        schemas.append(str(own))
    if not labels:  # NASA finds no product (no_products_found); does pdsgen find none either?
        found = sum(1 for target in case.targets if target.is_dir() for _ in discover([target]))
        if found:
            return Outcome(case, "not-comparable", f"NASA selects labels by extension (*.{case.extension}) and "
                                                   f"finds none; pdsgen finds {found} by content")
    given = pdsgen_paths(case)
    scope = _scope(case, given)
    extra = _found_beyond(given, scope, discover)
    if extra:
        return Outcome(case, "not-comparable", f"pdsgen also finds labels NASA's extension filter (*.{case.extension}) "
                                               f"leaves out ({extra})")
    if case.integrity and _rivals(case):
        return Outcome(case, "not-comparable", "other bundle/collection labels beside the one named (NASA "
                                               "checks the one named, pdsgen the directory)")
    skipped = _superseded(case, scope)
    checked = {os.path.normpath(p.resolve()) for p in scope if p.resolve() not in skipped}
    settings = RuleSettings(severity=LENIENT_MEMBERSHIP if case.lenient_membership else {},
                        ignore=frozenset({"PDS4-063"} if case.skip_context else set()))
    runs = []
    for cwd in ([scratch / "a", scratch / "b"] if cwd_check else [scratch / "a"]):
        cwd.mkdir(exist_ok=True)
        os.chdir(cwd)
        try:
            # the case's data directory is the trusted tree (--root), as NASA's run reads the whole of it
            report = validate_paths(given, labels_only=case.labels_only, schemas=schemas, settings=settings,
                                    root=case.datasrc if case.datasrc.is_dir() else None)
            findings = [(f.rule, f.severity, f.file, f.line, f.message) for f in report.findings
                        if _in_nasa_run(case, f.rule, f.file, checked, frozenset(skipped))]
        except PdsgenError as exc:
            findings = [("USAGE", "error", "", None, str(exc))]
        except Exception:  # noqa: BLE001 - a crash is what the harness must count, not stop on
            return Outcome(case, "crash", traceback.format_exc(limit=3))
        runs.append(findings)
    if cwd_check and runs[0] != runs[1]:
        return Outcome(case, "crash", "findings depend on the working directory")
    findings = runs[0]
    missing = sorted({m.split()[1] for r, _, _, _, m in findings if r == "PDS4-002"})
    if missing:
        return Outcome(case, "not-comparable", "schema not found: " + ", ".join(missing[:4]))
    errors = [f"{r} {Path(file).name}:{line or ''} {m[:160]}" for r, sev, file, line, m in findings
              if sev == "error"]
    ours = bool(errors)
    if ours == case.nasa_error:
        return Outcome(case, "agree", errors=errors)
    return Outcome(case, "false-error" if ours else "missed-error", REASONS.get(case.id, ""), errors)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("checkout", type=Path, help="a checkout of NASA-PDS/validate")
    parser.add_argument("--schemas", action="append", default=[], help="extra schema directory (repeatable)")
    parser.add_argument("--absent", type=Path, help="file listing checkout paths absent from it")
    parser.add_argument("--json", type=Path, help="write every case's outcome here")
    parser.add_argument("--only", default="", help="comma-separated case ids (ISSUE-SUBTEST) or issues")
    parser.add_argument("--no-cwd-check", action="store_true", help="run each case from one directory only")
    options = parser.parse_args()
    checkout = options.checkout.resolve()
    if not (checkout / FEATURES).is_dir():
        print(f"{checkout}: no {FEATURES} here; give a checkout of NASA-PDS/validate "
              f"(pinned commit {PINNED_COMMIT})", file=sys.stderr)
        return 2
    absent = set()
    if options.absent:
        absent = {checkout / line.strip() for line in options.absent.read_text().splitlines() if line.strip()}
    cases = read_cases(checkout)
    if options.only:
        wanted = set(options.only.split(","))
        cases = [c for c in cases if c.id in wanted or c.id.split("-")[0] in wanted]
    started = time.monotonic()
    outcomes = []
    with tempfile.TemporaryDirectory(prefix="pds4-parity-") as scratch:
        for case in cases:
            outcomes.append(run_case(case, [str(Path(s).resolve()) for s in options.schemas], absent,
                                     not options.no_cwd_check, Path(scratch)))
        os.chdir(REPO)
    elapsed = time.monotonic() - started
    report(outcomes, elapsed)
    if options.json:
        options.json.write_text(json.dumps([{
            "case": o.case.id, "feature": o.case.feature, "status": o.status, "reason": o.reason,
            "nasa_error": o.case.nasa_error, "nasa_types": o.case.nasa_types, "pdsgen_errors": o.errors,
            "args": shlex.join(o.case.args)} for o in outcomes], indent=1))
    return 0


def report(outcomes: list[Outcome], elapsed: float) -> None:
    counts = Counter(o.status for o in outcomes)
    comparable = [o for o in outcomes if o.status in ("agree", "false-error", "missed-error")]
    table = Counter((o.case.nasa_error, bool(o.errors)) for o in comparable)
    agree = counts["agree"]
    print(f"NASA-PDS/validate regression cases: {len(outcomes)} ({elapsed:.1f} s)")
    print(f"comparable: {len(comparable)}; not comparable: {counts['not-comparable']}; crashes: {counts['crash']}")
    print()
    print("                     pdsgen: error   pdsgen: no error")
    print(f"NASA: error          {table[(True, True)]:>13}   {table[(True, False)]:>16}")
    print(f"NASA: no error       {table[(False, True)]:>13}   {table[(False, False)]:>16}")
    print()
    if comparable:
        print(f"agreement on the error verdict: {agree}/{len(comparable)} = {100 * agree / len(comparable):.1f} %")
    print()
    print("Not comparable, by reason:")
    for reason, n in Counter(_reason_kind(o.reason) for o in outcomes if o.status == "not-comparable"
                             ).most_common():
        print(f"  {n:>4}  {reason}")
    for status in ("crash", "false-error", "missed-error"):
        chosen = [o for o in outcomes if o.status == status]
        if not chosen:
            continue
        print()
        print(f"{status} ({len(chosen)}):")
        for o in chosen:
            print(f"  {o.case.id} [{o.case.feature}] NASA: {', '.join(o.case.nasa_types) or 'no messages'}")
            if o.reason:
                print(f"      reason: {o.reason.strip().splitlines()[-1] if status == 'crash' else o.reason}")
            for error in o.errors[:3]:
                print(f"      pdsgen: {error}")


def _reason_kind(reason: str) -> str:
    return reason.split(":")[0] if reason.startswith("schema not found") else reason


if __name__ == "__main__":
    sys.exit(main())
