"""One home for each inbound boundary (issue 48), and what can be seen of them statically.

- the containment rule, from a name someone else wrote to a local path: storage/containment.py;
- the bounded reader of structured input (TOML, JSON, PVL): bounded.py;
- the check of a count read from a file against the bytes there: bounded.checked_count.

Each test below finds what it forbids in a small sample first, so it cannot pass by seeing
nothing.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pdsgen

SRC = Path(pdsgen.__file__).parent
CONTAINMENT_HOME = "storage/containment.py"
READER_HOME = "bounded.py"
COUNT_HOME = "bounded.py"
CONTAINMENT_FUNCTIONS = {"contained", "checked_name", "inside", "name_problem"}
READER_FUNCTIONS = {"read_bytes", "read_text", "load_toml", "load_json", "load_pvl", "parse_toml", "parse_json",
                    "parse_pvl"}

# Structured text pdsgen parses that it wrote itself, in the same run or the same batch: the
# lines its worker processes send, the markers a batch keeps, a spool file of index rows, the
# schema cache's index (each written whole by pdsgen, never a user's file).
OWN_TEXT = {
    "batch/child.py": "a task line from the batch's own parent process",
    "batch/resident.py": "a result line from the batch's own worker process",
    "batch/resume.py": "a done-marker the batch wrote",
    "deliver/index.py": "the index rows this run spooled",
    "validate/pds4/catalog.py": "the schema cache's index, written by the download",
}
# Modules that import pvl to write PVL (iMars .pvl), not to read it.
PVL_WRITERS = {"products/imars.py"}


def _modules():
    for path in sorted(SRC.rglob("*.py")):
        yield path.relative_to(SRC).as_posix(), ast.parse(path.read_text(encoding="utf-8"))


def _attribute_calls(tree: ast.AST) -> set[str]:
    """'json.loads', 'pvl.load', 'tomllib.loads' ... for every call of an attribute of a name."""
    return {f"{node.func.value.id}.{node.func.attr}" for node in ast.walk(tree)
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)
            and isinstance(node.func.value, ast.Name)}


def _imported(tree: ast.AST) -> set[str]:
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names |= {alias.name for alias in node.names}
        elif isinstance(node, ast.ImportFrom):
            names |= {alias.name for alias in node.names} | {node.module or ""}
    return names


def _structured_reads(tree: ast.AST) -> set[str]:
    """What a module does that parses structured text without the bounded reader."""
    found = {call for call in _attribute_calls(tree)
             if call in ("json.load", "json.loads", "pvl.load", "pvl.loads", "tomllib.load", "tomllib.loads",
                         "tomli.load", "tomli.loads")}
    return found | {name for name in _imported(tree) if name in ("tomllib", "tomli")}


def test_structured_input_is_parsed_only_by_the_bounded_reader():
    sample = ast.parse("import json\nfrom pdsgen._compat import tomllib\njson.loads(t)\n")
    assert _structured_reads(sample) == {"json.loads", "tomllib"}
    offenders = {}
    for name, tree in _modules():
        found = _structured_reads(tree)
        if found and name not in (READER_HOME, "_compat.py") and name not in OWN_TEXT:
            offenders[name] = sorted(found)
    assert offenders == {}
    for name in OWN_TEXT:  # each excused module still parses its own text (the list cannot outlive it)
        assert _structured_reads(ast.parse((SRC / name).read_text(encoding="utf-8"))), name


def test_pvl_is_imported_only_by_the_bounded_reader_and_the_iMars_writer():
    importing = {name for name, tree in _modules() if "pvl" in _imported(tree)}
    assert importing == {READER_HOME} | PVL_WRITERS


def _defined(tree: ast.AST) -> set[str]:
    return {node.name for node in ast.walk(tree) if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef)}


def test_each_boundary_has_its_one_home():
    homes = {name: _defined(tree) for name, tree in _modules()}
    assert CONTAINMENT_FUNCTIONS <= homes[CONTAINMENT_HOME]
    assert READER_FUNCTIONS | {"checked_count"} <= homes[READER_HOME]
    for name, functions in homes.items():
        if name != CONTAINMENT_HOME:
            assert not functions & CONTAINMENT_FUNCTIONS, f"{name} defines a second containment rule"
        if name != COUNT_HOME:
            assert "checked_count" not in functions, name


def _second_containment(tree: ast.AST) -> list[int]:
    """Lines deciding containment by hand: is_relative_to, os.path.commonprefix, or a path
    compared with startswith(... os.sep) (the form the one rule takes). os.path.commonpath
    (the review page's common directory of the files it shows) decides no containment."""
    lines = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute):
            if node.func.attr in ("is_relative_to", "commonprefix"):
                lines.append(node.lineno)
            elif node.func.attr == "startswith" and any(
                    isinstance(inner, ast.Attribute) and inner.attr == "sep" for inner in ast.walk(node)):
                lines.append(node.lineno)
    return lines


def test_containment_is_decided_only_in_its_home():
    assert _second_containment(ast.parse("p.is_relative_to(r)\nreal.startswith(top + os.sep)\n")) == [1, 2]
    found = {name: _second_containment(tree) for name, tree in _modules() if name != CONTAINMENT_HOME}
    assert {name: lines for name, lines in found.items() if lines} == {}


def _downloads_not_contained(tree: ast.AST) -> list[int]:
    """Lines downloading an object to a local path not made by containment.inside: every local
    name an object key becomes is checked by the rule."""
    made_inside = {target.id for node in ast.walk(tree) if isinstance(node, ast.Assign | ast.NamedExpr)
                   for target in (node.targets if isinstance(node, ast.Assign) else [node.target])
                   if isinstance(target, ast.Name) and isinstance(node.value, ast.Call)
                   and isinstance(node.value.func, ast.Name) and node.value.func.id == "inside"}
    lines = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "download" \
                and len(node.args) == 2:
            local = node.args[1]
            by_rule = (isinstance(local, ast.Call) and isinstance(local.func, ast.Name) and local.func.id == "inside") \
                or (isinstance(local, ast.Name) and local.id in made_inside)
            if not by_rule:
                lines.append(node.lineno)
    return lines


def test_object_keys_become_local_paths_only_through_the_rule():
    assert _downloads_not_contained(ast.parse("objects.download(item, target / name)\n")) == [1]
    assert _downloads_not_contained(ast.parse("x = inside(t, n, u)\nobjects.download(item, x)\n")) == []
    found = {name: _downloads_not_contained(tree) for name, tree in _modules()}
    assert {name: lines for name, lines in found.items() if lines} == {}
    # and the listing's keys are named locally in one place, the function applying the rule
    storage = ast.parse((SRC / "storage" / "areas.py").read_text(encoding="utf-8"))
    callers = {function.name for function in ast.walk(storage) if isinstance(function, ast.FunctionDef)
               for node in ast.walk(function) if isinstance(node, ast.Call)
               and isinstance(node.func, ast.Attribute) and node.func.attr == "list_objects"}
    assert callers and all(_uses(storage, caller, "staged_names") for caller in callers)


def _uses(tree: ast.AST, function: str, called: str) -> bool:
    body = next(node for node in ast.walk(tree) if isinstance(node, ast.FunctionDef) and node.name == function)
    return any(isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == called
               for node in ast.walk(body))


def _repeated_text(node: ast.AST) -> bool:
    """A string repeated by multiplication within NODE; numbers inside an f-string's {} are not
    text ('<{n}d' states a count in a few characters)."""
    if isinstance(node, ast.FormattedValue):
        return False
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Mult):
        return True
    return any(_repeated_text(child) for child in ast.iter_child_nodes(node))


def _counted_formats(tree: ast.AST) -> list[int]:
    """struct formats built by repeating a code by a count read from a file ('<' + 'd' * n):
    the format string itself grows with the count before anything is checked."""
    return [node.lineno for node in ast.walk(tree)
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)
            and node.func.attr in ("unpack", "unpack_from", "calcsize") and node.args
            and _repeated_text(node.args[0])]


def test_no_struct_format_grows_with_a_count():
    assert _counted_formats(ast.parse("struct.unpack(order + fmt * n, blob)\n")) == [1]
    assert _counted_formats(ast.parse("struct.unpack(f'{order}{n * 2}d', blob)\n")) == []
    found = {name: _counted_formats(tree) for name, tree in _modules()}
    assert {name: lines for name, lines in found.items() if lines} == {}


def test_a_count_read_from_a_file_is_checked_where_it_is_read():
    """The readers that take a count or size from a file ask the one helper before reading."""
    for module in ("formats/geojp2.py", "formats/jp2.py", "formats/vicar.py", "migrate/volume_index.py"):
        tree = ast.parse((SRC / module).read_text(encoding="utf-8"))
        assert any(isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "checked_count"
                   for node in ast.walk(tree)), module
