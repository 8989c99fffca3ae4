"""Read a batch manifest (TOML) and check all of it before any cluster starts.

A manifest entry is one product command written as a TOML table: its keys are the
command's long option names with `_` for `-` (`product_id`, `source_product_id`,
`params` ...), `input` (or `inputs`) for the positional argument. The keys, their
types and how often they may appear are not written down here a second time: they
are read from the click commands themselves (`click.Command.params`), and the values
are parsed by those commands (`make_context`), so a manifest accepts exactly what the
command line accepts, with the same checks and defaults. Each problem found is
collected, so a user sees every mistake of a manifest in one run.
"""

from __future__ import annotations

import importlib
import os
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import click

from ..bounded import load_toml
from ..errors import PdsgenError
from ..storage.containment import name_problem
from ..storage.locations import internal, is_remote

# The commands a manifest's tables run (a job's `kind`), in the order their jobs are listed.
JOB_COMMANDS = ("dtm", "ortho", "mosaic", "extras", "validate", "migrate")
# Keys that only the batch knows: how to schedule a job, not what it makes.
JOB_KEYS = ("id", "after", "memory", "threads", "timeout", "retries")
BATCH_KEYS = ("outdir", "memory", "threads", "timeout", "retries")
# Command options that are not a job's business: they print something and exit.
REFUSED_OPTIONS = {"list_rules"}
# Options naming outputs: relative values are taken from the batch output directory.
OUTPUT_OPTIONS = {"outdir", "output"}
# Flags that make a command write beside its input rather than where -o says: a batch job
# writes only inside the batch's output directory, so a manifest may not set them.
WRITES_BESIDE_INPUT = {"in_place"}
JOB_ID = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.-]*\Z")
DEFAULT_MEMORY = 1 << 30
DEFAULT_THREADS = 1


class ManifestError(PdsgenError):
    """Every problem of one manifest, one line each."""

    def __init__(self, path: Path, problems: Sequence[str]) -> None:
        self.problems = list(problems)
        super().__init__(path, "\n".join(self.problems))

    def lines(self) -> list[str]:
        """One line per problem, each naming the manifest."""
        return [f"{self.path}: {p}" for p in self.problems]


@dataclass(frozen=True)
class Job:
    """One product command to run: the command's parameters as click parsed them."""

    id: str
    kind: str
    params: dict[str, Any]
    after: tuple[str, ...] = ()
    memory: int = DEFAULT_MEMORY
    threads: int = DEFAULT_THREADS
    timeout: float | None = None
    retries: int = 0
    # extras/validate without inputs of their own take the products of the jobs they follow
    inputs_from_after: bool = False

    @property
    def argument(self) -> str:
        """Name of the command's positional parameter (the input or inputs)."""
        return next(p.name for p in command(self.kind).params if isinstance(p, click.Argument) and p.name)


@dataclass
class Manifest:
    path: Path
    outdir: Path
    jobs: list[Job] = field(default_factory=list)


def command(kind: str) -> click.Command:
    """The click command behind `pdsgen KIND`: `pdsgen.cli.KIND`'s, the module the CLI loads for it.

    Named, not imported, as a mission names its writers: the CLI runs batch, so batch/ sits
    below cli/ in the import graph; the commands parse a manifest's entries at run time."""
    found = getattr(importlib.import_module(f"pdsgen.cli.{kind}"), kind)
    assert isinstance(found, click.Command), kind
    return found


def manifest_keys(param: click.Parameter) -> list[str]:
    """The manifest keys of a command parameter: `input`/`inputs`, or each long option name, the
    longest first (`output`, then the older `outdir` or `out`: manifests written with them still work)."""
    if isinstance(param, click.Argument):
        return ["input" if param.nargs == 1 else "inputs"]
    long_names = sorted((opt for opt in param.opts if opt.startswith("--")), key=len, reverse=True)
    return [opt.lstrip("-").replace("-", "_") for opt in long_names or [max(param.opts, key=len)]]


def command_keys(kind: str) -> dict[str, click.Parameter]:
    """Manifest key -> parameter for every option a job of KIND may set."""
    return {key: p for p in command(kind).params if p.name not in REFUSED_OPTIONS for key in manifest_keys(p)}


def load_manifest(path: str | Path, outdir: str | Path | None = None,
                  overrides: Mapping[str, Any] | None = None) -> Manifest:
    """Parse and check the manifest at PATH; ManifestError lists every problem found.

    `outdir` (the command line's -o) overrides the manifest's `[batch] outdir`, and
    `overrides` its other `[batch]` keys (a job's own keys still win).
    Relative input paths are taken from the manifest's directory, relative output
    paths from the batch output directory.
    """
    path = Path(path)
    data = load_toml(path, what="manifest")
    return _Checker(path, data, outdir, overrides or {}).manifest()


class _Checker:
    """Builds the jobs of one manifest, collecting problems instead of stopping at the first."""

    def __init__(self, path: Path, data: dict[str, Any], outdir: str | Path | None,
                 overrides: Mapping[str, Any]) -> None:
        self.path = path
        self.base = path.resolve().parent
        self.data = data
        self.problems: list[str] = []
        self.batch = self._table(data.get("batch", {}), "[batch]")
        self._check_keys(self.batch, BATCH_KEYS, "[batch]")
        self.batch = {**self.batch, **overrides}
        given = outdir if outdir is not None else self.batch.get("outdir")
        if given is None:
            self.problems.append("no output directory: give -o OUTDIR or `outdir` in [batch]")
            self.outdir = self.base
        elif not isinstance(given, str | Path):
            self.problems.append("[batch] outdir: must be a string")
            self.outdir = self.base
        elif is_remote(given):  # s3://bucket/prefix: kept in its internal /vsis3/ form, which paths join onto
            self.outdir = Path(internal(given))
        else:
            self.outdir = (Path.cwd() if outdir is not None else self.base) / given
        self.defaults = self._table(data.get("defaults", {}), "[defaults]")

    def manifest(self) -> Manifest:
        for key in self.data:
            if key not in ("batch", "defaults", *JOB_COMMANDS):
                self.problems.append(f"unknown table [{key}] (expected [batch], [defaults.KIND], "
                                     + ", ".join(f"[[{k}]]" for k in JOB_COMMANDS) + ")")
        for kind in self.defaults:
            if kind not in JOB_COMMANDS:
                self.problems.append(f"unknown table [defaults.{kind}] (kinds: {', '.join(JOB_COMMANDS)})")
        jobs = [job for kind in JOB_COMMANDS for job in self._jobs(kind)]
        self._check_graph(jobs)
        if not jobs and not self.problems:
            self.problems.append("no jobs: add [[dtm]], [[ortho]], [[mosaic]], [[extras]] or [[validate]] entries")
        if self.problems:
            raise ManifestError(self.path, self.problems)
        outdir = self.outdir if is_remote(self.outdir) else self.outdir.resolve()
        return Manifest(self.path, outdir, jobs)

    def _table(self, value: Any, where: str) -> dict[str, Any]:
        if isinstance(value, dict):
            return value
        self.problems.append(f"{where} must be a table")
        return {}

    def _check_keys(self, table: Mapping[str, Any], allowed: Sequence[str], where: str) -> bool:
        unknown = [k for k in table if k not in allowed]
        for key in unknown:
            self.problems.append(f"{where}: unknown key {key!r} (allowed: {', '.join(sorted(allowed))})")
        return not unknown

    def _jobs(self, kind: str) -> list[Job]:
        entries = self.data.get(kind, [])
        if not isinstance(entries, list):
            self.problems.append(f"{kind} must be an array of tables: write [[{kind}]]")
            return []
        defaults = self._table(self.defaults.get(kind, {}), f"[defaults.{kind}]")
        jobs = []
        for number, entry in enumerate(entries, 1):
            where = f"[[{kind}]] #{number}"
            if not isinstance(entry, dict):
                self.problems.append(f"{where} must be a table")
                continue
            job = self._job(kind, number, {**defaults, **entry}, where)
            if job is not None:
                jobs.append(job)
        return jobs

    def _job(self, kind: str, number: int, entry: dict[str, Any], where: str) -> Job | None:
        keys = command_keys(kind)
        if "id" in entry or "product_id" in entry:
            where = f"{where} ({entry.get('id', entry.get('product_id'))})"
        if not self._check_keys(entry, [*keys, *JOB_KEYS], where):
            return None
        after = entry.get("after", [])
        if not (isinstance(after, list) and all(isinstance(a, str) for a in after)):
            self.problems.append(f"{where}: after must be a list of job ids")
            return None
        argument = next(k for k, p in keys.items() if isinstance(p, click.Argument))
        from_after = argument == "inputs" and argument not in entry and bool(after)
        if from_after:  # stands in for the products of `after` until they exist
            entry = {**entry, "inputs": list(after)}
        params = self._parse(kind, keys, entry, where)
        if params is None:
            return None
        job_id = entry.get("id") or params.get("product_id") or self._default_id(kind, number, params)
        if not (isinstance(job_id, str) and JOB_ID.match(job_id)):
            self.problems.append(f"{where}: id {job_id!r} must be letters, digits, '_', '.', '-'")
            return None
        scheduling = self._scheduling(entry, where)
        if scheduling is None:
            return None
        return Job(job_id, kind, params, tuple(after), inputs_from_after=from_after, **scheduling)

    def _default_id(self, kind: str, number: int, params: Mapping[str, Any]) -> str:
        single = params.get("input_path")
        return Path(single).stem if isinstance(single, str) else f"{kind}-{number}"

    def _parse(self, kind: str, keys: Mapping[str, click.Parameter], entry: Mapping[str, Any],
               where: str) -> dict[str, Any] | None:
        """The command's own parse of the entry, as if its values were typed on the command line."""
        entry = dict(entry)
        outdir_keys = [key for key, param in keys.items() if param.name == "outdir"]
        if "outdir" in keys and not any(key in entry for key in outdir_keys):
            entry["outdir"] = "."
        args: list[str] = []
        positional: list[str] = []
        for key, value in entry.items():
            param = keys.get(key)
            if param is None:
                continue
            words = self._words(param, key, value, where)
            if words is None:
                return None
            if isinstance(param, click.Argument):
                positional += words
            else:
                args += words
        cmd = command(kind)
        try:
            ctx = cmd.make_context(kind, [*args, "--", *positional])  # refuses an option the profile does not use
        except click.UsageError as exc:
            self.problems.append(f"{where}: {_usage_message(exc, keys)}")
            return None
        except PdsgenError as exc:
            self.problems.append(f"{where}: {exc}")
            return None
        return dict(ctx.params)

    def _words(self, param: click.Parameter, key: str, value: Any, where: str) -> list[str] | None:
        """VALUE as command-line words for PARAM, or None (problem recorded) if its TOML type is wrong."""
        flag = max(param.opts, key=len)
        if isinstance(param, click.Option) and param.is_flag:
            if not isinstance(value, bool):
                self.problems.append(f"{where}: {key} must be true or false")
                return None
            if value and param.name in WRITES_BESIDE_INPUT:
                self.problems.append(f"{where}: {key} = true writes beside the job's input, outside the batch's "
                                     f"output directory {self.outdir}; a batch job writes only inside it")
                return None
            return [flag] if value else []
        several = param.multiple or param.nargs != 1
        items = value if several else [value]
        if not isinstance(items, list) or (several and not isinstance(value, list)):
            self.problems.append(f"{where}: {key} must be " + ("a list" if several else "a single value"))
            return None
        if param.nargs > 1 and len(items) != param.nargs:
            self.problems.append(f"{where}: {key} must be a list of {param.nargs} values")
            return None
        words = []
        for item in items:
            word = self._word(param, key, item, where)
            if word is None:
                return None
            words.append(word)
        if isinstance(param, click.Argument):
            return words
        if param.nargs > 1:
            return [flag, *words]
        return [f"{flag}={w}" for w in words]

    def _word(self, param: click.Parameter, key: str, item: Any, where: str) -> str | None:
        """One TOML scalar as the word a user would type; strings stay strings (1.10 is not 1.1)."""
        numeric = isinstance(param.type, click.types._NumberParamTypeBase)
        choices = getattr(param.type, "choices", ())
        if isinstance(item, bool) or not isinstance(item, str | int | float):
            self.problems.append(f"{where}: {key} must be " + ("a number" if numeric else "a string"))
            return None
        if not isinstance(item, str) and not numeric and str(item) not in choices:
            self.problems.append(f"{where}: {key} must be a string (write it in quotes)")
            return None
        if isinstance(param.type, click.Path):
            if is_remote(str(item)):  # an object or prefix (s3://, /vsis3/, https://) is where it says
                return internal(str(item))
            if param.name in OUTPUT_OPTIONS:
                return self._output_word(key, str(item), where)
            return str(self.base / str(item))
        return str(item)

    def _output_word(self, key: str, item: str, where: str) -> str | None:
        """A job's output `item`, inside the batch's output directory (-o or [batch] outdir),
        or None (problem recorded): as a job id cannot name a path, a job's output cannot
        leave the directory the batch was given (`../../X`, an absolute path, s3://)."""
        relative = os.path.normpath(item)  # "a/./b/../c" is "a/c": what remains must be a name inside
        if is_remote(item) or relative != os.curdir and name_problem(relative) is not None:
            self.problems.append(f"{where}: {key} {item!r} is outside the batch's output directory "
                                 f"{self.outdir} (give a path inside it)")
            return None
        return os.path.normpath(self.outdir / relative)

    def _scheduling(self, entry: Mapping[str, Any], where: str) -> dict[str, Any] | None:
        """memory, threads, timeout and retries of one job: its own, else [batch]'s, else defaults."""
        values: dict[str, Any] = {"memory": DEFAULT_MEMORY, "threads": DEFAULT_THREADS, "timeout": None,
                                  "retries": 0}
        rules = {"memory": ("a whole number of bytes or a size such as '2 GB'", 1, True),
                 "threads": ("a whole number > 0", 1, True),
                 "timeout": ("a number of seconds > 0", 0.001, False),
                 "retries": ("a whole number >= 0", 0, True)}
        ok = True
        for key, (wanted, least, whole) in rules.items():
            value = entry.get(key, self.batch.get(key, values[key]))
            if value is None:
                continue
            if key == "memory" and isinstance(value, str):
                value = parse_size(value)
            number = isinstance(value, int | float) and not isinstance(value, bool)
            if not (number and value >= least and (not whole or value == int(value))):
                self.problems.append(f"{where}: {key} must be {wanted}")
                ok = False
                continue
            values[key] = int(value) if whole else float(value)
        return values if ok else None

    def _check_graph(self, jobs: Sequence[Job]) -> None:
        ids: dict[str, Job] = {}
        for job in jobs:
            if job.id in ids:
                self.problems.append(f"job id {job.id!r} is used twice; give one of them another `id`")
            ids[job.id] = job
        for job in jobs:
            for needed in job.after:
                if needed not in ids:
                    self.problems.append(f"job {job.id!r}: after names {needed!r}, which is no job id")
        if not self.problems:
            cycle = _find_cycle(jobs)
            if cycle:
                self.problems.append("jobs wait for each other in a circle: " + " -> ".join(cycle))
            self._check_shared_readmes(jobs)

    def _check_shared_readmes(self, jobs: Sequence[Job]) -> None:
        """Two Extras jobs writing one directory's README.TXT at once would lose entries."""
        by_dir: dict[str, list[Job]] = {}
        for job in jobs:
            if job.kind == "extras":
                by_dir.setdefault(str(job.params["outdir"]), []).append(job)
        for outdir, sharing in by_dir.items():
            for first, second in zip(sharing, sharing[1:], strict=False):
                if not (_needs(second, first.id, jobs) or _needs(first, second.id, jobs)):
                    self.problems.append(
                        f"extras jobs {first.id!r} and {second.id!r} both write {outdir}/README.TXT: "
                        "give them different outdir, or make one `after` the other")


def parse_size(text: str) -> int | None:
    """'2 GB' -> 2000000000 (Dask's own reading of sizes); None if it is no size."""
    from dask.utils import parse_bytes

    try:
        return int(parse_bytes(text))
    except ValueError:
        return None


def _usage_message(exc: click.UsageError, keys: Mapping[str, click.Parameter]) -> str:
    """click's message with option flags turned into the manifest's key names."""
    message = exc.format_message()
    for key, param in keys.items():
        for opt in param.opts:
            if opt.startswith("--"):
                message = message.replace(f"'{opt}'", f"{key!r}")
        if isinstance(param, click.Argument):
            message = message.replace(f"'{(param.metavar or param.name or '').upper()}'", f"{key!r}")
    return message


def _needs(job: Job, other_id: str, jobs: Sequence[Job]) -> bool:
    """Whether JOB waits, directly or not, for the job OTHER_ID."""
    by_id = {j.id: j for j in jobs}
    stack, seen = list(job.after), set()
    while stack:
        current = stack.pop()
        if current == other_id:
            return True
        if current not in seen and current in by_id:
            seen.add(current)
            stack += by_id[current].after
    return False


def _find_cycle(jobs: Sequence[Job]) -> list[str]:
    """Job ids forming a cycle of `after` links, or [] when the jobs can be ordered."""
    by_id = {j.id: j for j in jobs}
    state: dict[str, int] = {}  # 1 on the current path, 2 finished

    def visit(job_id: str, path: list[str]) -> list[str]:
        state[job_id] = 1
        for needed in by_id[job_id].after:
            if state.get(needed) == 1:
                return [*path[path.index(needed):], needed] if needed in path else [job_id, needed]
            if needed not in state:
                found = visit(needed, [*path, needed])
                if found:
                    return found
        state[job_id] = 2
        return []

    for job in jobs:
        if job.id not in state:
            cycle = visit(job.id, [job.id])
            if cycle:
                return cycle
    return []
