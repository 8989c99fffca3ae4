"""Schematron (ISO, queryBinding xslt2) for PDS4 labels, run by Saxon-HE (`saxonche`).

PDS4 Schematron files use a small part of ISO Schematron: `ns`, `pattern`, `rule`
(context), `let`, `assert` (test, role) and `value-of` in messages. We translate
them into one XSLT 3.0 stylesheet ourselves, compile it once per set of files and
reuse the compiled stylesheet for every label (compiling is the expensive part).

Semantics kept from Schematron: within a pattern a node is handled by the first
rule whose context matches it (later rules of that pattern skip it); patterns are
independent; a pattern's own `let`s are evaluated at the document root.

Saxon is optional (the pds4 extra: `pip install '.[pds4]'` in pdsgen's checkout); `available()` says whether it is here.

Schematron is code: its XPath runs in Saxon, and XPath 3.1 can read files, environment
variables and URLs, and run nested transforms. A Schematron is trusted only as far as its
source (shipped, PDS's schema site, `--schemas`), and a mission dictionary given with
`--schemas` may still be hostile, so two walls stand around every one that runs: each
XPath expression it holds is read before compiling and a file calling any function that
reaches outside the label (`forbidden_calls`) is not run at all; and Saxon itself is
configured to open no URI of any scheme, should an expression find another way.

XPath can also run for ever or fill memory without reaching outside (`count(1 to
10000000000)`), and Saxon has no limit of its own for that. So the validator runs its
Schematron (`bounded`) in a child process of its own, which keeps the compiled stylesheets
for the labels that follow: the parent waits for each label's answer at most `TIME_LIMIT`
seconds while the child stays under `MEMORY_LIMIT` bytes, else stops the child (a fresh one
answers the next label) and the label's finding says which Schematron was not run and why.
"""

from __future__ import annotations

import os
import pickle
import re
import subprocess
import sys
import time
from collections import OrderedDict
from collections.abc import Sequence
from dataclasses import dataclass
from multiprocessing.connection import Connection
from typing import Any

from lxml import etree

from ...pds4.model import SCHEMATRON_NS
from .catalog import SchemaFile

_XSL = "http://www.w3.org/1999/XSL/Transform"
_S = f"{{{SCHEMATRON_NS}}}"
_X = f"{{{_XSL}}}"
_REPORT_NS = "urn:pdsgen:schematron-report"

# XPath/XSLT functions that reach outside the label: files and URLs, environment
# variables, system properties, nested transforms and queries, and the ways to call any
# function by name at run time; and `function(...)`, an inline function, the one way an
# expression can recurse (unbounded recursion kills the engine's process, not just the
# label's check). A Schematron naming one is not run.
FORBIDDEN_FUNCTIONS = frozenset({
    "function",
    "unparsed-text", "unparsed-text-lines", "unparsed-text-available", "doc", "doc-available", "document",
    "collection", "uri-collection", "json-doc", "parse-xml", "parse-xml-fragment", "environment-variable",
    "available-environment-variables", "system-property", "available-system-properties", "transform",
    "load-xquery-module", "function-lookup", "unparsed-entity-uri", "unparsed-entity-public-id",
})
# A forbidden name used as a call or a function reference (`doc(`, `fn:doc (: c :) (`,
# `Q{...}doc#1`); anything but a letter or `_` may precede it, so `- doc(` is caught too.
_FORBIDDEN_CALL = re.compile(
    r"(?<![^\W\d])(" + "|".join(sorted(map(re.escape, FORBIDDEN_FUNCTIONS), key=len, reverse=True))
    + r")(?![\w.\-])\s*[(#]")
# Namespaces of engine extensions (Saxon's, Java binding): no Schematron of PDS needs them.
_FORBIDDEN_NAMESPACES = ("saxon.sf.net", "java:", "saxonica.com")
# Attributes of Schematron elements that are XPath (or XSLT patterns) run by Saxon.
_XPATH_ATTRIBUTES = {"rule": ("context",), "let": ("value",), "assert": ("test",), "report": ("test",),
                     "value-of": ("select",), "name": ("path",)}
# No URI of any scheme may be opened by a running Schematron (Saxon's own wall).
_ALLOWED_PROTOCOLS = "http://saxon.sf.net/feature/allowedProtocols"


@dataclass(frozen=True)
class SchematronFailure:
    """One failed assertion: its role (error/warning), message and where (an XPath)."""

    role: str
    message: str
    location: str
    rule_context: str


def available() -> bool:
    try:
        import saxonche  # noqa: F401
    except ImportError:
        return False
    return True


class UnsafeSchematron(RuntimeError):
    """A Schematron file whose XPath reaches outside the label; it is not run."""


def forbidden_calls(schematron_file: SchemaFile) -> tuple[str, ...]:
    """Functions reaching outside the label that a Schematron file's XPath calls (or
    engine-extension namespaces it names), in order met; empty for a file safe to run.
    Read once per file and process."""
    key = str(schematron_file)
    if key not in _CHECKED:
        _CHECKED[key] = _forbidden_calls(schematron_file.read_bytes())
    return _CHECKED[key]


_CHECKED: dict[str, tuple[str, ...]] = {}  # Schematron file -> its forbidden calls


def _forbidden_calls(data: bytes) -> tuple[str, ...]:
    """Forbidden calls of one Schematron file's text; a file that does not parse has none
    (compiling it reports it)."""
    try:
        root = etree.fromstring(data,
                                etree.XMLParser(no_network=True, resolve_entities=False))
    except etree.XMLSyntaxError:
        return ()
    found: list[str] = []
    for element in root.iter():
        if not isinstance(element.tag, str):
            continue
        local = etree.QName(element).localname
        if element.tag == f"{_S}ns":
            found += [f"namespace {element.get('uri')}" for _ in _extension_namespaces(element.get("uri") or "")]
        for attribute in _XPATH_ATTRIBUTES.get(local, ()) if element.tag.startswith(_S) else ():
            found += _forbidden_in(element.get(attribute) or "")
    return tuple(dict.fromkeys(found))


def _forbidden_in(expression: str) -> list[str]:
    """Forbidden calls and extension namespaces in one XPath expression."""
    calls = [f"{match[1]}()" for match in _FORBIDDEN_CALL.finditer(expression)]
    return calls + [f"namespace {name}" for name in _extension_namespaces(expression)]


def _extension_namespaces(text: str) -> list[str]:
    return [name for name in _FORBIDDEN_NAMESPACES if name in text]


def compile_to_xslt(schematron_files: Sequence[SchemaFile]) -> str:
    """One XSLT 3.0 stylesheet that reports every failed assertion of all the files.

    One pass over the label: every element and attribute is matched against templates
    (Saxon indexes match patterns by name, so each node meets only the rules that can
    fire on it). Each rule is a template, in Schematron order by priority; it checks,
    then hands the node on with `xsl:next-match` so rules of other patterns see it too,
    carrying the patterns already fired so a pattern's later rules skip it.
    """
    namespaces: dict[str, str] = {}
    parts: list[etree._Element] = []
    rules = 0
    patterns = []
    for path in schematron_files:
        root = etree.fromstring(path.read_bytes(), etree.XMLParser(no_network=True, resolve_entities=False))
        for ns in root.iter(f"{_S}ns"):
            namespaces[ns.get("prefix")] = ns.get("uri")
        patterns.extend(root.iter(f"{_S}pattern"))
    total = sum(len(list(p.iter(f"{_S}rule"))) for p in patterns)
    for number, pattern in enumerate(patterns):
        renames = {let.get("name"): f"p{number}_{let.get('name')}" for let in pattern.iterchildren(f"{_S}let")}
        for let in pattern.iterchildren(f"{_S}let"):  # pattern variables: global, at the document root
            parts.append(etree.Element(f"{_X}variable", name=renames[let.get("name")],
                                       select=_renamed(let.get("value"), renames)))
        for rule in pattern.iter(f"{_S}rule"):
            if rule.get("context"):
                parts.append(_rule_template(rule, number, total - rules, renames))
                rules += 1
    nsmap = {"xsl": _XSL, "r": _REPORT_NS, **namespaces}
    sheet = etree.Element(f"{_X}stylesheet", nsmap=nsmap, version="3.0",
                          attrib={"exclude-result-prefixes": " ".join(p for p in nsmap if p != "r")})
    etree.SubElement(sheet, f"{_X}output", method="xml", indent="no")
    etree.SubElement(sheet, f"{_X}mode", name="check", attrib={"on-no-match": "deep-skip"})
    start = etree.SubElement(sheet, f"{_X}template", match="/")
    report = etree.SubElement(start, f"{{{_REPORT_NS}}}report")
    etree.SubElement(report, f"{_X}apply-templates", select="//(*|@*)", mode="check")
    sheet.extend(parts)
    return etree.tostring(sheet, encoding="unicode")


def _renamed(expression: str | None, renames: dict[str, str]) -> str:
    """An XPath expression with the pattern's variables under their global names."""
    text = expression or "()"
    for old, new in renames.items():
        text = re.sub(rf"\${re.escape(old)}(?![\w.-])", f"${new}", text)
    return text


def _rule_template(rule: etree._Element, pattern: int, priority: int, renames: dict[str, str]) -> etree._Element:
    context = rule.get("context", "")
    template = etree.Element(f"{_X}template", match=context, mode="check", priority=str(priority))
    etree.SubElement(template, f"{_X}param", name="fired", select="()", tunnel="yes")
    check = etree.SubElement(template, f"{_X}if", test=f"not({pattern} = $fired)")
    for let in rule.iter(f"{_S}let"):
        etree.SubElement(check, f"{_X}variable", name=let.get("name"), select=_renamed(let.get("value"), renames))
    inherited = rule.get("role") or _pattern_role(rule)
    for assertion in rule.iterchildren(f"{_S}assert", f"{_S}report"):
        check.append(_assertion(assertion, context, renames, inherited))
    handed_on = etree.SubElement(template, f"{_X}next-match")
    etree.SubElement(handed_on, f"{_X}with-param", name="fired", select=f"($fired, {pattern})", tunnel="yes")
    return template


def _pattern_role(rule: etree._Element) -> str | None:
    """The role of the pattern holding a rule, if it states one."""
    parent = rule.getparent()
    while parent is not None and parent.tag != f"{_S}pattern":
        parent = parent.getparent()
    return parent.get("role") if parent is not None else None


def _assertion(assertion: etree._Element, context: str, renames: dict[str, str],
               inherited: str | None = None) -> etree._Element:
    """An `assert` fires when its test is false, a `report` when it is true. Its role is
    its own, else its rule's, else its pattern's (`inherited`): PDS's .sch files put
    role="warning" on the rule (deprecated elements), not on each assert. Without any,
    error for asserts, warning for reports."""
    test = _renamed(assertion.get("test"), renames)
    is_report = assertion.tag == f"{_S}report"
    check = etree.Element(f"{_X}if", test=test if is_report else f"not({test})")
    default_role = "warning" if is_report else "error"
    failure = etree.SubElement(check, f"{{{_REPORT_NS}}}failed",
                               role=(assertion.get("role") or inherited or default_role).lower(), context=context)
    etree.SubElement(failure, f"{_X}attribute", name="location", select="path()")
    text = etree.SubElement(failure, f"{_X}text")
    text.text = assertion.text or ""
    for child in assertion:
        if child.tag == f"{_S}value-of":
            etree.SubElement(failure, f"{_X}value-of", select=_renamed(child.get("select"), renames))
        elif child.tag == f"{_S}name":
            etree.SubElement(failure, f"{_X}value-of", select=f"name({child.get('path') or '.'})")
        # other children (PDS puts a <title> in each assert) are not part of the message
        tail = etree.SubElement(failure, f"{_X}text")
        tail.text = child.tail or ""
    return check


class Schematron:
    """Compiled Schematron for one set of .sch files, reusable for many labels."""

    def __init__(self, schematron_files: Sequence[SchemaFile]) -> None:
        from saxonche import PySaxonApiError

        for file in schematron_files:
            calls = forbidden_calls(file)
            if calls:
                raise UnsafeSchematron(f"Schematron {file.name} reaches outside the label "
                                       f"({', '.join(calls)}): not run")
        self._processor = _processor()
        compiler = self._processor.new_xslt30_processor()
        try:
            self._executable = compiler.compile_stylesheet(stylesheet_text=compile_to_xslt(schematron_files))
        except (PySaxonApiError, ValueError) as exc:  # ValueError: lxml refusing a prefix or name
            names = ", ".join(p.name for p in schematron_files)
            raise RuntimeError(f"Schematron {names} does not compile: {exc}") from None

    def check(self, label_text: str) -> list[SchematronFailure]:
        """Failed assertions of one label (its text, as UTF-8 XML)."""
        node = self._processor.parse_xml(xml_text=label_text)
        result = self._executable.transform_to_string(xdm_node=node)
        report = etree.fromstring(result.encode("utf-8"))
        return [
            SchematronFailure(f.get("role", "error"), " ".join((f.text or "").split()),
                              f.get("location", ""), f.get("context", ""))
            for f in report.iter(f"{{{_REPORT_NS}}}failed")
        ]


_PROCESSORS: dict[int, object] = {}
KEPT_STYLESHEETS = 16  # compiled Schematron sets kept per process, most recently used
_COMPILED: OrderedDict[tuple, Schematron] = OrderedDict()


def _processor():  # noqa: ANN202 - saxonche ships no type information
    """One Saxon processor per process (a forked worker must not reuse its parent's)."""
    from saxonche import PySaxonProcessor

    pid = os.getpid()
    if pid not in _PROCESSORS:
        _PROCESSORS.clear()
        _COMPILED.clear()
        processor = PySaxonProcessor(license=False)
        processor.set_configuration_property(_ALLOWED_PROTOCOLS, "")  # doc(), unparsed-text(): nothing
        _PROCESSORS[pid] = processor
    return _PROCESSORS[pid]


def compiled(schematron_files: Sequence[SchemaFile]) -> Schematron:
    """The compiled Schematron for these files, compiled once per process."""
    _processor()
    key = tuple(str(p) for p in schematron_files)
    if key in _COMPILED:
        _COMPILED.move_to_end(key)
        return _COMPILED[key]
    compiled_set = _COMPILED[key] = Schematron(schematron_files)
    while len(_COMPILED) > KEPT_STYLESHEETS:  # a run over many IM versions must not hold them all
        _COMPILED.popitem(last=False)
    return compiled_set


# One step of an XPath 3.1 `path()`: /Q{uri}local[n] for elements (URIs hold slashes), else /@attr etc.
_STEP = re.compile(r"/(?:Q\{(?P<uri>[^}]*)\}(?P<local>[^/\[]+)\[(?P<n>\d+)\]|(?P<other>[^/]*))")


def location_line(tree: etree._ElementTree, location: str) -> int | None:
    """Source line of the element a Saxon `path()` names (an attribute: its element)."""
    element: etree._Element | None = None
    for match in _STEP.finditer(location):
        if match["local"] is None:  # an attribute or text step: report the element holding it
            break
        tag = f"{{{match['uri']}}}{match['local']}" if match["uri"] else match["local"]
        if element is None:
            candidates = [tree.getroot()] if tree.getroot().tag == tag else []
        else:
            candidates = [child for child in element if child.tag == tag]
        index = int(match["n"]) - 1
        if index >= len(candidates):
            break
        element = candidates[index]
    return element.sourceline if element is not None else None


# -- bounded runs: a child process with a wall-clock and a memory limit -------------------------------

TIME_LIMIT = 60.0  # seconds one label's Schematron may run (PDS's core rules: well under one, after compiling)
MEMORY_LIMIT = 768 * 2**20  # bytes the Saxon child may hold (PDS's core rules compiled: about 150 MB)
_POLL = 0.05  # seconds between looks at the child while it works


class SchematronStopped(RuntimeError):
    """A Schematron run stopped at a limit (time or memory); its rules were not checked."""


def bounded(schematron_files: Sequence[SchemaFile], label_text: str) -> list[SchematronFailure]:
    """`compiled(files).check(label_text)` in the validator's Saxon child process, within
    TIME_LIMIT and MEMORY_LIMIT. SchematronStopped when a limit stopped it, RuntimeError
    with the engine's first line when it failed. A stopped child is reaped by `ask`, and the
    next call starts another (`_worker`). In a worker forked while a `SharedEngine` is open,
    the question goes to the engine's owner, whose one Saxon child answers every worker."""
    shared = _SHARED.get("engine")
    if shared is not None and shared.owner != os.getpid():
        return shared.ask(tuple(schematron_files), label_text)
    return _worker().ask(tuple(schematron_files), label_text)


def bounded_each(schematron_files: Sequence[SchemaFile], label_text: str
                 ) -> tuple[list[SchematronFailure], list[tuple[SchemaFile, str]]]:
    """The failures of the files' rules, run together within the limits, and the files a limit
    stopped with why. When the set is stopped, each file runs alone so that only the one at
    fault goes unchecked; a file stopped once runs alone for the rest of the process."""
    alone = [file for file in schematron_files if str(file) in _STOPPED]
    together = [file for file in schematron_files if str(file) not in _STOPPED]
    failures: list[SchematronFailure] = []
    stopped: list[tuple[SchemaFile, str]] = []
    if together:
        try:
            failures += bounded(together, label_text)
        except SchematronStopped as exc:
            if len(together) == 1:
                _STOPPED.add(str(together[0]))
                stopped.append((together[0], str(exc)))
            else:
                alone += together
    for file in alone:
        try:
            failures += bounded([file], label_text)
        except SchematronStopped as exc:
            _STOPPED.add(str(file))
            stopped.append((file, str(exc)))
    return failures, stopped


_STOPPED: set[str] = set()  # Schematron files a limit stopped in this process


class _Worker:
    """The Saxon child of one validating process, spoken to over a pipe of pickled frames."""

    def __init__(self) -> None:
        from_parent, to_child = os.pipe()  # (read end, write end)
        from_child, to_parent = os.pipe()
        code = ("import sys; from pdsgen.validate.pds4.schematron import serve; "
                "serve(int(sys.argv[1]), int(sys.argv[2]))")
        self.process = subprocess.Popen([sys.executable, "-c", code, str(from_parent), str(to_parent)],
                                        pass_fds=(from_parent, to_parent), stdin=subprocess.DEVNULL,
                                        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                        env=_child_environment())
        os.close(from_parent)
        os.close(to_parent)
        self.send = Connection(to_child, readable=False)
        self.receive = Connection(from_child, writable=False)

    def ask(self, files: tuple[SchemaFile, ...], label_text: str) -> list[SchematronFailure]:
        try:
            self.send.send_bytes(pickle.dumps((files, label_text)))
        except OSError:
            self.stop()
            raise SchematronStopped("its engine had stopped") from None
        started = time.monotonic()
        while not self.receive.poll(_POLL):
            if self.process.poll() is not None:
                self.stop()
                raise SchematronStopped("its engine stopped (exit status "
                                        f"{self.process.returncode})")
            if time.monotonic() - started > TIME_LIMIT:
                self.stop()
                raise SchematronStopped(f"it ran past the time limit of {TIME_LIMIT:g} s")
            if _resident_bytes(self.process.pid) > MEMORY_LIMIT:
                self.stop()
                raise SchematronStopped(f"it took more than the memory limit of {MEMORY_LIMIT // 2**20} MB")
        kind, value = pickle.loads(self.receive.recv_bytes())
        if kind == "error":
            raise RuntimeError(value)
        return value

    def stop(self) -> None:
        """The child killed and reaped (it may be in the middle of an endless expression)."""
        self.process.kill()
        self.process.wait()
        self.send.close()
        self.receive.close()


_WORKERS: dict[int, _Worker] = {}  # the validating process -> its Saxon child

# What the child needs of the environment to start Python and Saxon; nothing else of the
# validating process (a CI job's secrets) reaches the engine that runs a delivery's rules.
_CHILD_ENVIRONMENT = ("PATH", "PYTHONPATH", "PYTHONHOME", "VIRTUAL_ENV", "HOME", "TMPDIR", "LANG", "LC_ALL",
                      "LC_CTYPE", "SYSTEMROOT")


def _child_environment() -> dict[str, str]:
    return {name: os.environ[name] for name in _CHILD_ENVIRONMENT if name in os.environ}


def _worker() -> _Worker:
    """This process's Saxon child, started when there is none (or it has stopped). It is started
    from one long-lived thread of the process: Linux ties a child's parent-death signal to the
    thread that started it, and a check run from a short-lived thread must not take it along."""
    pid = os.getpid()
    worker = _WORKERS.get(pid)
    if worker is None or worker.process.poll() is not None:
        if _SPAWNER.get(pid) is None:
            from concurrent.futures import ThreadPoolExecutor

            _SPAWNER.clear()  # a forked process's copy of its parent's is not its own
            _SPAWNER[pid] = ThreadPoolExecutor(max_workers=1, thread_name_prefix="pdsgen-saxon-spawner")
        worker = _WORKERS[pid] = _SPAWNER[pid].submit(_Worker).result()
    return worker


_SPAWNER: dict[int, Any] = {}  # the process -> the one thread its Saxon children are started from


class SharedEngine:
    """One Saxon child for a validating process and the workers it forks (`validate -j N`).

    A compiled PDS4 core Schematron and its engine take about 110 MB; one per worker doubled
    the run's memory with two workers. While a SharedEngine is open, a worker forked from its
    owner sends each label to the owner over a private socket (a directory only this user
    reads, an authentication key the workers inherit); one thread of the owner per worker
    hands it to the owner's Saxon child (`_worker().ask`), one label at a time. The walls
    stay where they were: the child's stripped environment, and the time and memory limits,
    counted from the moment a label reaches the engine (not while it waits for another
    worker's), so a stopped engine is charged to the label that stopped it."""

    def __init__(self) -> None:
        import tempfile
        import threading
        from multiprocessing.connection import Listener

        self.owner = os.getpid()
        self._directory = tempfile.mkdtemp(prefix="pdsgen-saxon-")  # mode 0700
        self._authkey = os.urandom(32)
        self._listener = Listener(os.path.join(self._directory, "engine"), "AF_UNIX", authkey=self._authkey)
        self._one_at_a_time = threading.Lock()
        self._clients: dict[int, Connection] = {}  # a worker's pid -> its connection to the owner
        self._closed = False
        threading.Thread(target=self._accept, name="pdsgen-saxon-shared", daemon=True).start()

    def __enter__(self) -> SharedEngine:
        _SHARED["engine"] = self
        return self

    def __exit__(self, *_: object) -> None:
        from multiprocessing.connection import Client

        _SHARED.pop("engine", None)
        self._closed = True
        Client(self._listener.address, "AF_UNIX", authkey=self._authkey).close()  # wakes the accepting thread
        self._listener.close()  # removes the socket
        os.rmdir(self._directory)

    def ask(self, files: tuple[SchemaFile, ...], label_text: str) -> list[SchematronFailure]:
        """In a worker: the owner's engine's answer for one label (see `bounded`)."""
        from multiprocessing.connection import Client

        pid = os.getpid()
        if pid not in self._clients:
            self._clients[pid] = Client(self._listener.address, "AF_UNIX", authkey=self._authkey)
        connection = self._clients[pid]
        try:
            connection.send((files, label_text))
            kind, value = connection.recv()
        except (OSError, EOFError):
            self._clients.pop(pid, None)
            raise RuntimeError("the shared Schematron engine is gone") from None
        if kind == "stopped":
            raise SchematronStopped(value)
        if kind == "error":
            raise RuntimeError(value)
        return value

    def _accept(self) -> None:
        import threading

        while True:
            try:
                connection = self._listener.accept()
            except Exception:  # a connection that failed to authenticate
                continue
            if self._closed:  # the owner's own call, made to end this loop
                connection.close()
                return
            threading.Thread(target=self._serve, args=(connection,), name="pdsgen-saxon-shared", daemon=True).start()

    def _serve(self, connection: Connection) -> None:
        """One worker's labels, answered one by one until the worker closes its end."""
        with connection:
            while True:
                try:
                    files, label_text = connection.recv()
                except (OSError, EOFError):
                    return
                answer: tuple[str, object]
                try:
                    with self._one_at_a_time:
                        answer = ("ok", _worker().ask(files, label_text))
                except SchematronStopped as exc:
                    answer = ("stopped", str(exc))
                except Exception as exc:  # the worker reports it as the Schematron not running
                    answer = ("error", first_line(exc))
                try:
                    connection.send(answer)
                except OSError:
                    return


_SHARED: dict[str, SharedEngine] = {}  # "engine": the SharedEngine open in this process (inherited by fork)


def _resident_bytes(pid: int) -> int:
    """The child's resident memory (Linux /proc); 0 where it cannot be read."""
    try:
        with open(f"/proc/{pid}/statm", "rb") as statm:
            return int(statm.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, IndexError):
        return 0


def first_line(exc: Exception) -> str:
    """The first line of an engine's error, without the file names and text it may go on to quote."""
    text = str(exc).strip()
    return text.splitlines()[0][:200] if text else type(exc).__name__


def serve(from_parent: int, to_parent: int) -> None:
    """The Saxon child: each request (Schematron files, label text) answered with ("ok",
    failures) or ("error", the engine's first line), until the parent closes the pipe."""
    _die_with_parent()
    receive = Connection(from_parent, writable=False)
    send = Connection(to_parent, readable=False)
    while True:
        try:
            files, label_text = pickle.loads(receive.recv_bytes())
        except EOFError:
            return
        try:
            answer: tuple[str, object] = ("ok", compiled(files).check(label_text))
        except Exception as exc:  # the parent reports it as the Schematron not running
            answer = ("error", first_line(exc))
        send.send_bytes(pickle.dumps(answer))


def _die_with_parent() -> None:
    """On Linux, the child is killed when its parent dies (prctl PR_SET_PDEATHSIG), so a parent
    killed in the middle of an endless expression leaves no Saxon child running it."""
    if not sys.platform.startswith("linux"):
        return
    import ctypes
    import signal

    try:
        ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGKILL)  # 1: PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass
