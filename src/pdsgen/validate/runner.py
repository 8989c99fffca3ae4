"""Run the rule table over files and directories: discovery, per-file checks, set checks.

Per-file work is independent, so `jobs > 1` spreads files over a process pool; each
worker returns plain findings plus a small summary for the SET rules, which then run
once over the whole run. No input can raise out of here: a file that cannot be read
or parsed is a finding, and a check that fails on some odd label becomes an error
finding naming the rule, instead of a traceback.
"""

from __future__ import annotations

import contextlib
import functools
import itertools
import multiprocessing
import os
import pickle
import re
import stat
import sys
import tempfile
from collections.abc import Callable, Generator, Iterable, Iterator
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..errors import PdsgenError
from ..formats.sniff import file_head
from ..label.parser import is_pds3_head
from ..pds4.detect import is_pds4_label
from . import facts
from .config import Baseline, RuleSettings
from .context import FileContext
from .dictionary import load as load_dictionary
from .dictionary import version as dictionary_version
from .families import pds4_rules
from .families.delivery_rules import DeliveryChecks
from .families.set_rules import summarise
from .imars_context import ImarsContext, is_imars_metadata
from .model import Finding, Hit
from .registry import rules
from .report import FileReport, ValidationReport
from .summary import LabelSummary

if TYPE_CHECKING:
    from ..label.read import LabelCache

LABEL_SUFFIXES = (".lbl",)


def is_label_file(path: Path) -> bool:
    """Detached labels by name, iMars metadata files (`*_ucl.pvl`); other files only if
    they start with a PDS3 label."""
    if path.suffix.lower() in LABEL_SUFFIXES or is_imars_metadata(path) or is_pds4_label(path):
        return True
    return is_pds3_head(file_head(path, 64) or b"")


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
    return list(_discover_lazily(list(paths)))


def _discover_lazily(paths: list[str | os.PathLike[str]], skip_non_labels: bool = False) -> Iterator[Path]:
    """discover(), one file at a time; every named path is checked before the first is given."""
    for raw in paths:
        reason = _unusable_path_reason(Path(raw))
        if reason is not None:
            raise PdsgenError(raw, reason)
    return _walk(paths, skip_non_labels)


def _walk(paths: list[str | os.PathLike[str]], skip_non_labels: bool = False) -> Iterator[Path]:
    """Named files (with skip_non_labels, only those a directory search would take as
    labels), then the labels found in named directories. A file named twice (itself and in
    its directory) is given once; one path names each file once, and nothing is kept of the
    files given (a tree of 100,000 labels is not held as it is walked)."""
    seen: set[str] | None = set() if len(paths) > 1 else None
    for raw in paths:
        path = Path(raw)
        if path.is_file():
            candidates: Iterable[Path] = [path] if not skip_non_labels or is_label_file(path) else []
        else:
            candidates = _label_files(path)
        for candidate in candidates:
            if seen is None:
                yield candidate
            elif (name := str(candidate)) not in seen:
                seen.add(name)
                yield candidate


def _label_files(directory: Path) -> Iterator[Path]:
    for dirpath, dirnames, filenames in os.walk(directory):
        dirnames.sort()
        for name in sorted(filenames):
            candidate = Path(dirpath) / name
            if candidate.is_file() and is_label_file(candidate):
                yield candidate


def not_a_label(path: Path) -> str | None:
    """Why a file named on the command line is not a PDS3 label (None when it may be one).

    Label names (.lbl, iMars metadata) and files that start like a label are read as
    labels; a file whose first bytes are binary (a JP2, a GeoTIFF, a bare .IMG) is not,
    and gets one finding instead of thousands about its bytes."""
    if is_label_file(path):
        return None
    head = file_head(path, _SNIFF_BYTES)  # None: unreadable, which FILE-012 reports
    if not head or not _BINARY.search(head):
        return None
    kind = next((name for magic, name in _MAGIC if head.startswith(magic)), "binary data")
    return f"not a PDS3 label: the file starts with {kind}, not PDS_VERSION_ID (give its label instead)"


_SNIFF_BYTES = 1024
_BINARY = re.compile(rb"[^\x20-\x7e\t\r\n\x0c]")
_MAGIC = ((b"\x00\x00\x00\x0cjP  ", "a JPEG 2000 signature"), (b"\xff\x4f\xff\x51", "a JPEG 2000 codestream"),
          (b"II*\x00", "a TIFF header"), (b"MM\x00*", "a TIFF header"), (b"II+\x00", "a BigTIFF header"),
          (b"\xff\xd8\xff", "a JPEG header"), (b"\x89PNG", "a PNG header"))


@dataclass(frozen=True)
class ValidationJob:
    """What a validation run checks and how: the one set of options `validate_paths`,
    `iter_reports` and `validate_file` take (as a job, or as its fields by keyword).

    strict makes warnings fail the run too (and keeps over-long lines an error for labels
    of any origin). labels_only skips every rule that opens the data files (data existence,
    file sizes, statistics, JP2), for label-only checks. dictionaries are extra data
    dictionaries (PSDD `.full` format) merged over the built-in one. settings select rules
    and set severities (see config.py); baseline drops findings already known.
    schemas are directories of PDS4 schemas (.xsd/.sch) added to the shipped ones;
    schema_cache is a directory of downloaded PDS4 schemas, which download_schemas lets
    grow from the URLs labels name (without a cache, no download).
    skip_non_labels passes over named files that are not labels (see iter_reports).
    root widens the tree the files a label names must stay inside (label/beside.trusted_tree:
    the directory given, else the label's directory): a label given alone inside `root` may
    name ../../LABEL/X.FMT of its volume.
    jobs > 1 checks files in that many processes. cluster: a Dask client (distributed.Client)
    whose workers check the files instead, a partition of them each (see partitions.py);
    everything that looks across files still runs here, so the report is the same.
    """

    strict: bool = False
    jobs: int = 1
    labels_only: bool = False
    dictionaries: tuple[str, ...] = ()
    settings: RuleSettings = field(default_factory=RuleSettings)
    baseline: Baseline | None = None
    schemas: tuple[str, ...] = ()
    skip_non_labels: bool = False
    schema_cache: str | None = None
    download_schemas: bool = False
    root: str | None = None
    labels: LabelCache | None = field(default=None, compare=False)  # a run's labels, read once (deliver)
    cluster: Any = field(default=None, compare=False)  # a Dask client the files are checked on

    def __post_init__(self) -> None:
        # paths of any kind become strings (the job is sent to worker processes); None: defaults
        set_ = object.__setattr__
        set_(self, "dictionaries", tuple(os.fspath(d) for d in self.dictionaries))
        set_(self, "schemas", tuple(os.fspath(d) for d in self.schemas))
        set_(self, "settings", self.settings or RuleSettings())
        set_(self, "root", os.fspath(self.root) if self.root is not None else None)
        cache = os.fspath(self.schema_cache) if self.schema_cache is not None else None
        set_(self, "schema_cache", cache)
        set_(self, "download_schemas", bool(self.download_schemas and cache is not None))

    @classmethod
    def of(cls, job: ValidationJob | None, options: dict[str, Any]) -> ValidationJob:
        """`job`, or a job of these options (unknown names are a TypeError, as for any call)."""
        if job is None:
            return cls(**options)
        if options:
            raise TypeError(f"give a ValidationJob or its options, not both ({', '.join(options)})")
        return job

    @property
    def fail_on(self) -> str:
        return "warning" if self.strict else self.settings.fail_on


def target_of(path: Path) -> str:
    """Which rules a file is for (a rule's `target`): "pds4" for a PDS4 label, "imars"
    for iMars metadata, "label" for everything else (PDS3 labels, or what claims to be one)."""
    if is_pds4_label(path):
        return "pds4"
    return "imars" if is_imars_metadata(path) else "label"


def validate_file(path: Path, job: ValidationJob | None = None, tree: Path | None = None,
                  **options: Any) -> tuple[FileReport, LabelSummary | None]:
    """Every per-file rule of the file's target on one file (before configuration), and
    the summary of a PDS3 label the SET rules compare. `tree`: the directory the user gave
    that holds the file (the file's own directory when None), widened by the job's root."""
    job = ValidationJob.of(job, options)
    target = target_of(path)
    reason = not_a_label(path) if target == "label" else None
    if reason is not None:
        return FileReport(str(path), [Finding("FILE-013", _severity("FILE-013"), str(path), reason)]), None
    try:
        ctx = _open(path, target, job, tree)
    except OSError as exc:
        finding = Finding("FILE-012", "error", str(path), f"cannot read the file: {exc.strerror or exc}")
        return FileReport(str(path), [finding]), None
    try:
        skip_data = job.labels_only or (isinstance(ctx, FileContext) and ctx.data_absent)
        findings = _run_rules(ctx, path, target, skip_data)
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


def _open(path: Path, target: str, job: ValidationJob, tree: Path | None) -> Any:
    """The context the rules of `target` take."""
    from ..label.beside import trusted_tree
    if target == "pds4":
        return pds4_rules.open_label(path, job.labels_only, job.schemas, job.schema_cache, job.download_schemas,
                                     trusted_tree(path, tree, Path(job.root) if job.root else None))
    if target == "imars":
        return ImarsContext(path, job.labels_only)
    file = job.labels.open(path) if job.labels is not None else None
    return FileContext(path, labels_only=job.labels_only, dictionaries=job.dictionaries, strict=job.strict, file=file,
                       tree=trusted_tree(path, tree, Path(job.root) if job.root else None))


def _severity(rule_id: str) -> str:
    return rules()[rule_id].severity


def _run_rules(ctx: Any, path: Path, target: str, labels_only: bool) -> list[Finding]:
    findings: list[Finding] = []
    for rule in rules().values():
        if rule.check is None or rule.target != target or (labels_only and rule.needs_data):
            continue
        try:
            for hit in rule.check(ctx):
                findings.append(Finding(rule.id, hit.severity or rule.severity, hit.file or str(path),
                                        hit.message, hit.line, hit.keyword))
        except Exception as exc:  # a check must never turn odd input into a traceback
            findings.append(Finding(rule.id, "error", str(path),
                                    f"check could not run on this file ({type(exc).__name__}: {exc})"))
    return findings


_JOB = ValidationJob()  # a worker's job, sent once per process
_SKIP: frozenset[str] = frozenset()  # the fact readers a worker need not apply (facts.read)


def _init_worker(job: ValidationJob, skip: frozenset[str] = frozenset()) -> None:
    global _JOB, _SKIP
    _JOB, _SKIP = job, skip


Item = tuple[str, str | None]  # a file and the directory given that holds it (None: the file was named)
Checked = tuple[FileReport, LabelSummary | None, dict[str, bytes]]


def _one(item: Item) -> Checked:
    """One file, in this process or a worker of the pool: see _checked (a pool's workers read
    the file's facts too)."""
    report, summary, read = _checked(item, _JOB, gather=_JOB.jobs > 1, skip=_SKIP)
    return report, summary, facts.packed(read)


def _checked(item: Item, job: ValidationJob, gather: bool,
             skip: frozenset[str] = frozenset()) -> tuple[FileReport, LabelSummary | None, dict[str, Any]]:
    """One file: its findings as the configuration reports them, its summary for the SET rules,
    and (`gather`, in a worker) what the checks across files read of it (facts.py; not the
    readers in `skip`), so that the run's process need not read it again."""
    path, given = item
    report, summary = validate_file(Path(path), job, Path(given) if given else None)
    report.findings = job.settings.filter(report.findings)
    return report, summary, facts.read(path, target_of(Path(path)), skip) if gather else {}


def _facts_of(item: Item) -> tuple[str, dict[str, bytes]]:
    """What the checks across files read of one file (facts.py), in a worker of the pool."""
    rules()  # the families register their readers as they load
    return item[0], facts.made(item[0], target_of(Path(item[0])))


def validate_partition(items: list[Item], job: ValidationJob, cwd: str,
                       skip: frozenset[str] = frozenset()) -> list[Checked]:
    """A partition of a run's files, on a cluster's worker (see partitions.py): each checked
    as _checked checks it, a name relative to the client's directory `cwd` read there and
    named as given in what comes back (the worker's own directory is left alone: other
    tasks share its process)."""
    from .partitions import ClientPaths

    paths = ClientPaths(cwd)
    done = []
    for item in items:
        report, summary, read = paths.as_given(item, _checked(paths.absolute(item), job, gather=True, skip=skip))
        done.append((report, summary, facts.packed(read)))
    return done


def facts_of_partition(items: list[Item], job: ValidationJob, cwd: str) -> list[tuple[str, dict[str, bytes]]]:
    """What the checks across files read of each file of a partition, on a cluster's worker
    (named as given, as validate_partition names its results)."""
    from .partitions import ClientPaths

    rules()  # the families register their readers as they load
    paths = ClientPaths(cwd)
    done = []
    for item in items:
        path, _ = paths.absolute(item)
        done.append((item[0], facts.packed(paths.as_given(item, facts.read(path, target_of(Path(path)))))))
    return done


def _check_dictionaries(extra: tuple[str, ...]) -> None:
    for d in extra:
        reason = _unusable_path_reason(Path(d), missing="no such dictionary file")
        if reason is None and Path(d).is_dir():
            reason = "a directory, not a dictionary file"
        if reason is not None:
            raise PdsgenError(d, reason)
    if extra:
        load_dictionary(extra)  # refuses a file that is not a PSDD dictionary; cached for this process


def iter_reports(paths: Iterable[str | os.PathLike[str]], job: ValidationJob | None = None,
                 progress: Callable[[int, int], None] | None = None, **options: Any) -> Iterator[FileReport]:
    """File reports one by one, as files are checked: the streaming core of validate_paths.
    `job` (or its fields as keywords, see ValidationJob) says what to check and how.

    Files are found lazily and checked in order (in `job.jobs` processes when > 1). The SET
    rules compare files of one directory, so a directory's reports are held until its last
    file is checked; reports of labels that describe no data wait for the end of the run
    (another label may include them). Memory is bounded by one directory, not the run.
    Usage errors (a missing path, no label at all, a bad dictionary) are raised before the
    first report, so nothing is written for a run that cannot start.

    skip_non_labels: files named that are not labels (an ordinary .xml, a bare .img whose
    label is detached) are passed over as a directory search passes them over, and a run
    given only such files checks nothing and passes; for hooks (pre-commit) that hand over
    every changed file of some suffixes. A named directory without labels is still an error.
    """
    job = ValidationJob.of(job, options)
    _check_dictionaries(job.dictionaries)
    pds4_rules.check_schema_dirs(job.schemas)
    paths = list(paths)
    found = _discover_lazily(paths, job.skip_non_labels)
    first = next(found, None)
    if first is None and job.skip_non_labels and all(Path(p).is_file() for p in paths):
        return iter(())  # files named, none a label: nothing to check (a directory must hold labels)
    if first is None:  # a CI job pointed at the wrong directory must not pass
        raise PdsgenError(None, "no PDS3 or PDS4 label found under " + ", ".join(os.fspath(p) for p in paths))
    files = itertools.chain([first], found)
    given = [Path(p) for p in paths if Path(p).is_dir()]  # the trees the user gave (label/beside.trusted_tree)
    deliveries = DeliveryChecks(paths, job.labels_only, job.labels)  # a delivery directory is also checked whole
    facts.forget()
    names = ((str(p), _given_tree(p, given)) for p in files)
    return _run(names, deliveries, job, progress)


def _run(names: Iterator[Item], deliveries: DeliveryChecks, job: ValidationJob,
         progress: Callable[[int, int], None] | None) -> Iterator[FileReport]:
    """The reports, as files are checked, with what the checks across files find beside them.

    A delivery's checks look at every label before the first report can have its findings.
    A one-process run reads the labels for them on its first report (DeliveryChecks). A run
    on workers goes over the files twice instead: the workers read what the checks across
    files need of every file (facts.py), a process forked for the purpose learns it and
    checks the delivery, and hands back only its findings (the names spooled to a temporary
    file meanwhile); then the files are validated and the reports stream out. So the run's
    process holds no report and no label's facts for the delivery's sake: a delivery's
    labels are held together only by the checking process, which ends when it is done; the
    workers then no longer read what it has read. The count of files checked moves from the
    start: in the first pass as files are read, in the second out of the files the first found."""
    with contextlib.ExitStack() as stack:
        taken: frozenset[str] = frozenset()
        if _in_workers(job) and deliveries.found():
            spool = stack.enter_context(tempfile.TemporaryFile())
            found = [0]
            deliveries, taken = _checked_apart(deliveries, _spooled(names, spool, found), job, progress)
            spool.seek(0)
            names = _unspooled(spool)
            if progress is not None:
                progress = functools.partial(_out_of, progress, found[0])
        reports = _reports(names, job, progress, taken)
        yield from _forgetting(_with_run_checks(_with_deliveries(reports, deliveries, job), job))


def _in_workers(job: ValidationJob) -> bool:
    return job.jobs > 1 or job.cluster is not None


def _reports(names: Iterator[Item], job: ValidationJob, progress: Callable[[int, int], None] | None,
             taken: frozenset[str]) -> Iterator[FileReport]:
    """The files' own reports, in order, as they are checked (on the job's workers, if any,
    each reading what the checks across files need of its files (facts.py), but the facts of
    the readers already `taken`)."""
    groups = _SetGroups(job.settings)
    if not _in_workers(job):
        _init_worker(job)
        yield from _collect(map(_one, names), groups, progress, job.baseline)
        return
    with _workers(job, skip=taken) as on_workers:
        yield from _collect(on_workers(_one, functools.partial(validate_partition, skip=taken), names), groups,
                            progress, job.baseline)


def _out_of(progress: Callable[[int, int], None], total: int, done: int, _: int) -> None:
    progress(done, total)


def _checked_apart(deliveries: DeliveryChecks, names: Iterator[Item], job: ValidationJob,
                   progress: Callable[[int, int], None] | None) -> tuple[DeliveryChecks, frozenset[str]]:
    """The deliveries checked over what the job's workers read of every file (see _run), and
    the fact readers the check used: the facts go from the workers through this process to a
    checking process forked before any worker (this process has no thread of its own to take
    along), which answers with the findings. Without fork (not Linux), and in a run sharing
    its label cache with its caller (review: what the check reads, the page reads again from
    the cache), they are checked here."""
    if sys.platform != "linux" or job.labels is not None:
        for learnt in _facts_read(names, job, progress):
            facts.learn(*learnt)
        return deliveries, _check_learnt_here(deliveries)
    context = multiprocessing.get_context("fork")
    facts_out, facts_in = context.Pipe(duplex=False)
    answer_in, answer_out = context.Pipe(duplex=False)
    checker = context.Process(target=_check_learnt, args=(deliveries, facts_out, answer_out), daemon=True)
    checker.start()
    facts_out.close()
    answer_out.close()
    reading = _facts_read(names, job, progress)
    try:
        for learnt in reading:
            facts_in.send(learnt)
        facts_in.send(None)
        pending, taken = answer_in.recv()
        return _CheckedDeliveries(pending), taken
    except (EOFError, OSError):  # the checking process died: checked here, reading the labels again
        reading.close()  # the workers stopped: nothing else takes names from `names` now
        for _ in names:  # the names they had not taken, spooled too: every file is still validated
            pass
        return deliveries, frozenset()
    finally:
        facts_in.close()
        answer_in.close()
        checker.join()


def _facts_read(names: Iterator[Item], job: ValidationJob,
                progress: Callable[[int, int], None] | None) -> Generator[tuple[str, dict[str, bytes]], None, None]:
    """What the job's workers read of each file for the checks across files (facts.made); closing
    it stops the workers."""
    with _workers(job, shared_engine=False) as on_workers:
        for done, learnt in enumerate(on_workers(_facts_of, facts_of_partition, names), 1):
            if progress:
                progress(done, 0)
            yield learnt


def _check_learnt(deliveries: DeliveryChecks, facts_out: Any, answer_out: Any) -> None:
    """The checking process of _checked_apart: learn every file's facts, then check."""
    try:
        while (learnt := facts_out.recv()) is not None:
            facts.learn(*learnt)
    except EOFError:  # the run stopped before the last file
        return
    answer_out.send((deliveries.pending, _check_learnt_here(deliveries)))


def _check_learnt_here(deliveries: DeliveryChecks) -> frozenset[str]:
    """Check the deliveries over the facts learnt in this process: the readers the check used."""
    _ = deliveries.pending  # checked now, its findings kept by file
    return facts.asked()


class _CheckedDeliveries(DeliveryChecks):
    """Deliveries already checked (their findings by file), handed out as DeliveryChecks hands them."""

    def __init__(self, pending: dict[str, list[Finding]]) -> None:
        super().__init__([], labels_only=False)
        self._checked = pending

    @property
    def pending(self) -> dict[str, list[Finding]]:
        return self._checked


OnWorkers = Callable[[Callable[[Item], Any], Callable[..., list[Any]], Iterator[Item]], Iterator[Any]]


@contextlib.contextmanager
def _workers(job: ValidationJob, shared_engine: bool = True, skip: frozenset[str] = frozenset()) -> Iterator[OnWorkers]:
    """on_workers(one, partition, items): one(item) for each item in a pool of job.jobs
    processes, or partition(items, job, cwd=...) for each partition on job.cluster's workers -
    the results in the items' order. The baseline is applied here, in this process.
    shared_engine: the pool's workers share this process's Schematron engine; skip: the fact
    readers they need not apply."""
    if job.cluster is not None:
        from .partitions import in_partitions  # a Dask cluster's run only: a plain run never loads it

        cwd, cluster_job = os.getcwd(), _cluster_job(job)
        yield lambda one, partition, items: in_partitions(job.cluster, functools.partial(partition, cwd=cwd), items,
                                                          cluster_job)
        return
    from .pds4.schematron import SharedEngine

    context = multiprocessing.get_context("fork" if sys.platform == "linux" else "spawn")
    # forked workers share this process's Saxon child (one compiled Schematron, not one per worker)
    with SharedEngine() if shared_engine else contextlib.nullcontext(), \
            context.Pool(job.jobs, _init_worker, (replace(job, baseline=None), skip)) as pool:
        yield lambda one, partition, items: pool.imap(one, items, chunksize=8)


def _spooled(names: Iterator[Item], spool: Any, found: list[int]) -> Iterator[Item]:
    """The names, each also written to the spool (and counted in found[0])."""
    for item in names:
        pickle.dump(item, spool, pickle.HIGHEST_PROTOCOL)
        found[0] += 1
        yield item


def _unspooled(spool: Any) -> Iterator[Item]:
    while True:
        try:
            yield pickle.load(spool)  # written by _spooled in this run
        except EOFError:
            return


def _forgetting(reports: Iterator[FileReport]) -> Iterator[FileReport]:
    """The reports; what workers read of a file for the checks across files is dropped once its
    report has passed them all, and everything when the run ends."""
    try:
        for report in reports:
            facts.drop(report.path)
            yield report
    finally:
        facts.forget()


def _with_deliveries(reports: Iterator[FileReport], deliveries: DeliveryChecks,
                     job: ValidationJob) -> Iterator[FileReport]:
    """Delivery hook: each file's DLV findings beside its own; files with no report of their own
    (an index table, the manifest) get one at the end. With workers, the delivery is checked
    before the first file is validated, over what the workers read of every file (_run)."""
    for report in reports:
        report.findings.extend(_kept(report.path, deliveries.take(report.path), job))
        yield report
    for path, findings in deliveries.rest():
        kept = _kept(path, findings, job)
        if kept:
            yield FileReport(path, kept)


def _kept(path: str, findings: list[Finding], job: ValidationJob) -> list[Finding]:
    """Findings made after a file's own report (across files), as configured and not in the baseline."""
    return _after_baseline(FileReport(path, job.settings.filter(findings)), job.baseline).findings


def _with_run_checks(reports: Iterator[FileReport], job: ValidationJob) -> Iterator[FileReport]:
    """The rules with a `run_check` (see registry.py): each sees every file of its target, in
    report order, from the first such file on; their findings join the file's report."""
    checks = [rule for rule in rules().values() if rule.run_check is not None]
    observers: dict[str, Callable[[str], Iterable[Hit]]] = {}
    for report in reports:
        target = target_of(Path(report.path)) if checks else None
        found: list[Finding] = []
        for rule in checks:
            if rule.target != target or rule.run_check is None:
                continue
            try:
                observe = observers.get(rule.id) or observers.setdefault(rule.id, rule.run_check(job.labels))
                found += [Finding(rule.id, hit.severity or rule.severity, hit.file or report.path, hit.message,
                                  hit.line, hit.keyword) for hit in observe(report.path)]
            except Exception as exc:  # never a traceback, whatever the files hold
                found.append(Finding(rule.id, "error", report.path,
                                     f"run check could not run ({type(exc).__name__}: {exc})"))
        report.findings.extend(_kept(report.path, found, job))
        yield report


def _cluster_job(job: ValidationJob) -> ValidationJob:
    """The job a cluster's workers take: what it names as absolute paths (a worker's directory
    is not the client's), nothing that stays here (baseline, label cache, the cluster)."""
    absolute = os.path.abspath
    return replace(job, baseline=None, cluster=None, labels=None, dictionaries=tuple(map(absolute, job.dictionaries)),
                   schemas=tuple(map(absolute, job.schemas)), root=absolute(job.root) if job.root else None,
                   schema_cache=absolute(job.schema_cache) if job.schema_cache else None)


def _given_tree(path: Path, given: list[Path]) -> str | None:
    """The widest directory given on the command line that holds `path` (None: the file was named)."""
    from ..storage.containment import contained

    return min((str(d) for d in given if contained(path, d) is not None), key=len, default=None)


def _collect(results: Iterator[Checked], groups: _SetGroups,
             progress: Callable[[int, int], None] | None, baseline: Baseline | None) -> Iterator[FileReport]:
    done = 0
    for report, summary, made in results:
        facts.learn(report.path, made)
        done += 1
        if progress:
            progress(done, 0)
        for ready in groups.add(report, summary):
            yield _after_baseline(ready, baseline)
    for ready in groups.finish():
        yield _after_baseline(ready, baseline)


def _after_baseline(report: FileReport, baseline: Baseline | None) -> FileReport:
    if baseline is not None:
        report.findings = [f for f in report.findings if not baseline.known(f)]
    return report


class _SetGroups:
    """Holds one directory's reports until its set checks have run (see iter_reports)."""

    def __init__(self, settings: RuleSettings) -> None:
        self.settings = settings
        self.directory: str | None = None
        self.group: list[tuple[FileReport, LabelSummary | None]] = []
        self.waiting: list[tuple[FileReport, LabelSummary]] = []  # labels describing no data (SET-005)
        self.referenced: set[str] = set()

    def add(self, report: FileReport, summary: LabelSummary | None) -> list[FileReport]:
        directory = os.path.dirname(report.path)
        ready = self._flush() if directory != self.directory else []
        self.directory = directory
        self.group.append((report, summary))
        if summary is not None:
            self.referenced.update(summary.referenced)
        return ready

    def _flush(self) -> list[FileReport]:
        group, self.group = self.group, []
        summaries = [s for _, s in group if s is not None]
        by_path = {r.path: r for r, _ in group}
        self._run(DIRECTORY_SET_RULES, summaries, by_path)
        ready = []
        for report, summary in group:
            if summary is not None and summary.describes_nothing:
                self.waiting.append((report, summary))
            else:
                ready.append(report)
        return ready

    def finish(self) -> list[FileReport]:
        ready = self._flush()
        waiting, self.waiting = self.waiting, []
        by_path = {r.path: r for r, _ in waiting}
        self._run(RUN_SET_RULES, [s for _, s in waiting], by_path)
        return ready + [r for r, _ in waiting]

    def _run(self, rule_ids: tuple[str, ...], summaries: list[LabelSummary], by_path: dict[str, FileReport]) -> None:
        for rule_id in rule_ids:
            rule = rules()[rule_id]
            if rule.set_check is None or not summaries or not self.settings.keeps(rule_id):
                continue
            try:
                found = [Finding(rule.id, hit.severity or rule.severity, hit.file or summaries[0].path,
                                 hit.message, hit.line, hit.keyword)
                         for hit in rule.set_check(summaries, self.referenced)]
            except Exception as exc:  # never a traceback, whatever the labels hold
                found = [Finding(rule.id, "error", summaries[0].path,
                                 f"set check could not run ({type(exc).__name__}: {exc})")]
            for finding in self.settings.filter(found):
                by_path[finding.file].findings.append(finding)


# SET rules that compare the files of one directory, and those that need the whole run
DIRECTORY_SET_RULES = ("SET-001", "SET-003", "SET-004")
RUN_SET_RULES = ("SET-005",)


def validate_paths(paths: Iterable[str | os.PathLike[str]], job: ValidationJob | None = None,
                   progress: Callable[[int, int], None] | None = None, **options: Any) -> ValidationReport:
    """Validate label files and directories of them; the API behind `pdsgen validate`.

    `job` says what to check and how; or give its fields by keyword (strict, jobs,
    labels_only, dictionaries, settings, baseline, schemas, skip_non_labels, schema_cache,
    download_schemas, root: see ValidationJob), e.g. `validate_paths(["out/"], strict=True)`.
    progress(done, total) is called as files are checked.

    Raises PdsgenError when the paths hold no label at all (an empty or wrong directory):
    checking nothing is a usage error, not a pass.
    """
    job = ValidationJob.of(job, options)
    reports = list(iter_reports(paths, job, progress))
    return ValidationReport(reports, fail_on=job.fail_on,
                            baseline_suppressed=job.baseline.suppressed if job.baseline else 0,
                            dictionary=dictionary_version())
