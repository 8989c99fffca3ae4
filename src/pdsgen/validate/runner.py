"""Run the rule table over files and directories: discovery, per-file checks, set checks.

Per-file work is independent, so `jobs > 1` spreads files over a process pool; each
worker returns plain findings plus a small summary for the SET rules, which then run
once over the whole run. No input can raise out of here: a file that cannot be read
or parsed is a finding, and a check that fails on some odd label becomes an error
finding naming the rule, instead of a traceback.
"""

from __future__ import annotations

import os
import stat
import sys
from collections.abc import Callable, Iterable
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from ..errors import PdsgenError
from ..pds4 import validate as pds4
from .context import FileContext
from .dictionary import load as load_dictionary
from .imars_context import ImarsContext, is_imars_metadata
from .model import Finding
from .report import FileReport, Report
from .rules import rules
from .set_rules import Summary, summarise

LABEL_SUFFIXES = (".lbl",)
_SNIFF = (b"PDS_VERSION_ID", b"CCSD3")


def is_label_file(path: Path) -> bool:
    """Detached labels by name, iMars metadata files (`*_ucl.pvl`); other files only if
    they start with a PDS3 label."""
    if path.suffix.lower() in LABEL_SUFFIXES or is_imars_metadata(path) or pds4.is_pds4_label(path):
        return True
    try:
        with open(path, "rb") as fh:
            head = fh.read(64).lstrip()
    except OSError:
        return False
    return head.upper().startswith(_SNIFF)


_SPECIAL_KINDS = ((stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
                  (stat.S_ISFIFO, "a FIFO"), (stat.S_ISSOCK, "a socket"))


def _unusable_path_reason(path: Path, missing: str = "no such file or directory") -> str | None:
    """Why a path named on the command line (a label, a directory of them, a dictionary)
    cannot be read as one (None when it can). Devices and FIFOs are refused by name:
    reading one may never end."""
    try:
        mode = path.stat().st_mode
    except (FileNotFoundError, NotADirectoryError):
        return missing
    except OSError as exc:
        return f"cannot access it: {exc.strerror or exc}"
    if stat.S_ISREG(mode) or stat.S_ISDIR(mode):
        return None
    kind = next((name for test, name in _SPECIAL_KINDS if test(mode)), "a special file")
    return f"not a regular file ({kind})"


def discover(paths: Iterable[str | os.PathLike[str]]) -> list[Path]:
    """Files to validate: files as given, label files found recursively in directories.

    Inside directories only regular files are considered (a FIFO is skipped, not opened)."""
    found: list[Path] = []
    for raw in paths:
        path = Path(raw)
        reason = _unusable_path_reason(path)
        if reason is not None:
            raise PdsgenError(path, reason)
        if path.is_file():
            found.append(path)
            continue
        for dirpath, dirnames, filenames in os.walk(path):
            dirnames.sort()
            for name in sorted(filenames):
                candidate = Path(dirpath) / name
                if candidate.is_file() and is_label_file(candidate):
                    found.append(candidate)
    return list(dict.fromkeys(found))  # a file named twice (itself and in its directory) once


def validate_file(path: Path, labels_only: bool = False, dictionaries: tuple[str, ...] = (),
                  schemas: tuple[str, ...] = ()) -> tuple[FileReport, Summary | None]:
    """All per-file rules on one file: PDS3 label rules, or IMARS rules for iMars metadata."""
    if pds4.is_pds4_label(path):  # PDS4 hook: pdsgen.pds4 checks it and returns Findings
        return FileReport(str(path), pds4.validate_label(path, schemas, labels_only)), None
    imars = is_imars_metadata(path)
    try:
        ctx = ImarsContext(path, labels_only) if imars else FileContext(
            path, labels_only=labels_only, dictionaries=dictionaries)
    except OSError as exc:
        finding = Finding("FILE-012", "error", str(path), f"cannot read the file: {exc.strerror or exc}")
        return FileReport(str(path), [finding]), None
    try:
        findings = _run_rules(ctx, path, "imars" if imars else "label", labels_only)
    finally:
        if isinstance(ctx, ImarsContext):
            ctx.close()
    summary = None
    if isinstance(ctx, FileContext):
        try:
            summary = summarise(ctx)
        except Exception:
            summary = None
    findings.sort(key=lambda f: (f.line or 0, f.rule))
    return FileReport(str(path), findings), summary


def _run_rules(ctx: FileContext | ImarsContext, path: Path, target: str, labels_only: bool) -> list[Finding]:
    findings: list[Finding] = []
    for rule in rules().values():
        if rule.check is None or rule.target != target or (labels_only and rule.needs_data):
            continue
        try:
            for hit in rule.check(ctx):  # type: ignore[arg-type]
                findings.append(Finding(rule.id, rule.severity, hit.file or str(path), hit.message,
                                        hit.line, hit.keyword))
        except Exception as exc:  # a check must never turn odd input into a traceback
            findings.append(Finding(rule.id, "error", str(path),
                                    f"check could not run on this file ({type(exc).__name__}: {exc})"))
    return findings


def _one(args: tuple[str, bool, tuple[str, ...], tuple[str, ...]]) -> tuple[FileReport, Summary | None]:
    return validate_file(Path(args[0]), args[1], args[2], args[3])


def validate_paths(
    paths: Iterable[str | os.PathLike[str]],
    strict: bool = False,
    jobs: int = 1,
    labels_only: bool = False,
    progress: Callable[[int, int], None] | None = None,
    dictionaries: Iterable[str | os.PathLike[str]] = (),
    schemas: Iterable[str | os.PathLike[str]] = (),
) -> Report:
    """Validate label files and directories of them; the API behind `pdsgen validate`.

    Raises PdsgenError when the paths hold no label at all (an empty or wrong directory):
    checking nothing is a usage error, not a pass.
    strict makes warnings fail the run too. labels_only skips every rule that opens the
    data files (data existence, file sizes, statistics, JP2), for label-only checks.
    dictionaries are extra data dictionaries (PSDD `.full` format) merged over the built-in one.
    schemas are directories of PDS4 schemas (.xsd/.sch) added to the shipped ones.
    """
    extra = tuple(str(d) for d in dictionaries)
    for d in extra:
        reason = _unusable_path_reason(Path(d), missing="no such dictionary file")
        if reason is None and Path(d).is_dir():
            reason = "a directory, not a dictionary file"
        if reason is not None:
            raise PdsgenError(d, reason)
    if extra:
        load_dictionary(extra)  # refuses a file that is not a PSDD dictionary; cached for this process
    schema_dirs = pds4.check_schema_dirs(schemas)
    paths = list(paths)
    files = discover(paths)
    if not files:  # a CI job pointed at the wrong directory must not pass
        raise PdsgenError(None, "no PDS3 labels found under " + ", ".join(os.fspath(p) for p in paths))
    results: list[tuple[FileReport, Summary | None]] = []
    work = [(str(p), labels_only, extra, schema_dirs) for p in files]
    if jobs > 1 and len(files) > 1:
        with ProcessPoolExecutor(max_workers=jobs) as pool:
            for i, result in enumerate(pool.map(_one, work, chunksize=max(1, len(work) // (jobs * 8)))):
                results.append(result)
                if progress:
                    progress(i + 1, len(files))
    else:
        for i, item in enumerate(work):
            results.append(_one(item))
            if progress:
                progress(i + 1, len(files))
    reports = [r for r, _ in results]
    pds4.add_run_notes(reports)  # PDS4 hook: one note when Schematron could not run
    summaries = [s for _, s in results if s is not None]
    by_path = {r.path: r for r in reports}
    for rule in rules().values():
        if rule.set_check is None:
            continue
        try:
            for finding in rule.set_check(summaries):
                by_path[finding.file].findings.append(finding)
        except Exception as exc:  # never a traceback, whatever the labels hold
            if reports:
                reports[0].findings.append(Finding(rule.id, "error", reports[0].path,
                                                   f"set check could not run ({type(exc).__name__}: {exc})"))
    return Report(reports, strict=strict)


def terminal_progress(done: int, total: int) -> None:
    """A one-line progress bar on stderr (used only when stderr is a terminal)."""
    width = 30
    filled = width * done // total if total else width
    sys.stderr.write(f"\r[{'#' * filled}{'.' * (width - filled)}] {done}/{total} files")
    if done == total:
        sys.stderr.write("\n")
    sys.stderr.flush()
