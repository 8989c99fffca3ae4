"""The rule registry: stable id -> family, severity, summary, check function.

Ids never change meaning once published (CI configurations refer to them). Each
family is one module under `families/` that declares its rules with `register()`
when it is imported; `families/__init__.py` names the built-in ones (its `load()`
imports them all, which `rules()` and `families()` do before first use), so a new
family is one module plus one name there (or, from outside pdsgen, one `register()`
call). `rules()` is the table every part of the validator reads, and what
`pdsgen validate --list-rules` prints.

Rules run on what their `target` names: "label" rules take a FileContext (PDS3
labels), "imars" rules an ImarsContext (iMars `*_ucl.pvl` metadata, PVL rather
than PDS3), "pds4" rules a Pds4LabelContext (PDS4 XML labels, see families/pds4_rules.py).
Rules with a `set_check` compare the PDS3 labels of a directory or run with each other
(the SET family); rules with a `run_check` see every file of their target in report
order, in the parent process (PDS4-007, PDS4-060); rules with no check at all are
reported by the runner itself (FILE-012, FILE-013).
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Generic, TypeVar

from .model import Hit
from .summary import LabelSummary

if TYPE_CHECKING:
    from ..label.read import LabelCache

# The built-in families in --list-rules order; families registered later follow them.
FAMILIES = ("FILE", "SYNTAX", "DICT", "PTR", "REC", "IMG", "MAP", "GEO", "HRSC", "SET", "IMARS", "PDS4")
TARGETS = ("label", "imars", "pds4")

ContextT = TypeVar("ContextT")  # FileContext for "label" rules, ImarsContext "imars", Pds4LabelContext "pds4"
# A run check: called once per run with the run's label cache (None when the run keeps none), it
# gives the function that takes each file's path in turn; a label it reads through the cache is
# the one the file's own checks parsed, not parsed again.
RunCheck = Callable[["LabelCache | None"], Callable[[str], Iterable[Hit]]]


@dataclass(frozen=True)
class Rule(Generic[ContextT]):
    id: str
    severity: str
    summary: str
    check: Callable[[ContextT], Iterable[Hit]] | None  # per-file check
    needs_data: bool = False
    set_check: Callable[[list[LabelSummary], set[str]], Iterable[Hit]] | None = None  # across files (SET)
    target: str = "label"  # what `check` takes: see the module docstring
    note: str = ""  # when a finding of this rule takes another severity, and why
    run_check: RunCheck | None = None  # across the files of the run, one by one

    @property
    def family(self) -> str:
        return self.id.split("-")[0]


_REGISTERED: dict[str, Rule[Any]] = {}
_FAMILY_ORDER: list[str] = list(FAMILIES)
_TABLE: dict[str, Rule[Any]] = {}  # _REGISTERED in --list-rules order, rebuilt after a change
_BUILTIN_LOADED: list[bool] = []  # set once every built-in family has been imported


def _load_builtin() -> None:
    """Import the built-in families once, before the table is first read (a product writer
    imports the one family it runs, and only that)."""
    if not _BUILTIN_LOADED:
        _BUILTIN_LOADED.append(True)
        importlib.import_module(f"{__package__}.families").load()


def register(*new: Rule[Any]) -> None:
    """Add rules to the table. An id is registered once: ids never change meaning."""
    for rule in new:
        if rule.id in _REGISTERED:
            raise ValueError(f"rule {rule.id} is already registered")
        if rule.severity not in ("error", "warning", "info"):
            raise ValueError(f"rule {rule.id}: severity {rule.severity!r} is not error, warning or info")
        if rule.target not in TARGETS:
            raise ValueError(f"rule {rule.id}: target {rule.target!r} is not one of {', '.join(TARGETS)}")
    for rule in new:
        _REGISTERED[rule.id] = rule
        if rule.family not in _FAMILY_ORDER:
            _FAMILY_ORDER.append(rule.family)
    _TABLE.clear()


def unregister(family: str) -> None:
    """Remove a family registered from outside pdsgen (built-in families stay)."""
    if family in FAMILIES:
        raise ValueError(f"{family} is a built-in rule family")
    for rule_id in [i for i, rule in _REGISTERED.items() if rule.family == family]:
        del _REGISTERED[rule_id]
    if family in _FAMILY_ORDER:
        _FAMILY_ORDER.remove(family)
    _TABLE.clear()


def families() -> tuple[str, ...]:
    """Family names in --list-rules order (the built-in ones, then registered ones)."""
    _load_builtin()
    return tuple(_FAMILY_ORDER)


def registered(family: str) -> list[Rule[Any]]:
    """The rules of FAMILY registered so far, without loading the other families."""
    return sorted((r for r in _REGISTERED.values() if r.family == family), key=lambda r: r.id)


def rules() -> dict[str, Rule[Any]]:
    """The rule table: every registered rule by id, in family order, then id order."""
    _load_builtin()
    if not _TABLE:
        ordered = sorted(_REGISTERED.values(), key=lambda r: (_FAMILY_ORDER.index(r.family), r.id))
        _TABLE.update((rule.id, rule) for rule in ordered)
    return _TABLE
