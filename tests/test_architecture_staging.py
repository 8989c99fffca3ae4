"""One home for write-then-rename (storage/staging.py), and its helpers' promises.

A file that appears under its final name must be complete: every module that writes one
does so through storage/staging.py, so the temporary's clean-up on failure and on Ctrl-C
is written (and tested) once.
"""

from __future__ import annotations

import ast
import os
from pathlib import Path

import pytest

import pdsgen
from pdsgen.storage.staging import replace_directory, staged_file, staged_files

SRC = Path(pdsgen.__file__).parent
RENAMING_HOME = "storage/staging.py"
_RENAMES = {"rename", "replace", "renames"}


def _renames_in(tree: ast.AST) -> list[int]:
    """Lines that rename a file: os.rename/os.replace/os.renames (also imported by name),
    shutil.move, and Path.rename/Path.replace - a `.rename(...)` call on anything but self, a
    `.replace(target)` call with one argument (str.replace takes two, dataclasses.replace
    and datetime.replace take keywords)."""
    lines = []
    imported = {alias.asname or alias.name for node in ast.walk(tree) if isinstance(node, ast.ImportFrom)
                and node.module in ("os", "shutil") for alias in node.names if alias.name in _RENAMES | {"move"}}
    for node in ast.walk(tree):
        if not isinstance(node, ast.Call):
            continue
        function = node.func
        if isinstance(function, ast.Name) and function.id in imported:
            lines.append(node.lineno)
        elif isinstance(function, ast.Attribute):
            owner = function.value.id if isinstance(function.value, ast.Name) else None
            if owner == "os" and function.attr in _RENAMES or owner == "shutil" and function.attr == "move":
                lines.append(node.lineno)
            elif function.attr == "rename" and owner != "self":  # self.rename: a class's own method
                lines.append(node.lineno)
            elif function.attr == "replace" and (len(node.args) == 1 and not node.keywords or owner == "Path"):
                lines.append(node.lineno)
    return lines


def _renaming_modules() -> dict[str, list[int]]:
    found = {}
    for path in sorted(SRC.rglob("*.py")):
        lines = _renames_in(ast.parse(path.read_text(encoding="utf-8")))
        if lines:
            found[path.relative_to(SRC).as_posix()] = lines
    return found


def test_files_are_renamed_into_place_only_by_storage_staging():
    found = _renaming_modules()
    assert RENAMING_HOME in found  # the check sees renames
    elsewhere = {module: lines for module, lines in found.items() if module != RENAMING_HOME}
    assert elsewhere == {}, f"rename files through storage.staging: {elsewhere}"


def test_the_rename_check_tells_paths_from_text():
    calls = ("os.replace(a, b)", "os.rename(a, b)", "path.rename(b)", "tmp.replace(final)",
             "Path.replace(a, b)", "shutil.move(a, b)")
    not_renames = ('text.replace("a", "b")', "dataclasses.replace(x, y=1)", "value.replace(tzinfo=None)",
                   "options.replace(product_id=p)", "self.rename(text)")
    for code in calls:
        assert _renames_in(ast.parse(code)) == [1], code
    for code in not_renames:
        assert _renames_in(ast.parse(code)) == [], code
    assert _renames_in(ast.parse("from os import replace\nreplace(a, b)")) == [2]


# -- staged_file / staged_files --------------------------------------------------------------------

def test_a_staged_file_appears_whole_under_its_final_name(tmp_path):
    final = tmp_path / "report.txt"
    final.write_text("old")
    with staged_file(final) as temporary:
        assert temporary.parent == tmp_path and temporary.name == f".report.txt.{os.getpid()}.part"
        temporary.write_text("new")
        assert final.read_text() == "old"  # not yet
    assert final.read_text() == "new" and sorted(p.name for p in tmp_path.iterdir()) == ["report.txt"]


@pytest.mark.parametrize("failure", [OSError(28, "No space left on device"), KeyboardInterrupt()])
def test_a_failed_staged_file_leaves_no_partial_file_and_the_old_one_untouched(tmp_path, failure):
    final = tmp_path / "report.txt"
    final.write_text("old")
    with pytest.raises(type(failure)):
        with staged_file(final, tmp_path / ".report.txt.partial") as temporary:
            temporary.write_text("half")
            raise failure
    assert final.read_text() == "old" and sorted(p.name for p in tmp_path.iterdir()) == ["report.txt"]


def test_a_staged_file_never_written_is_no_error_on_failure(tmp_path):
    with pytest.raises(OSError):
        with staged_file(tmp_path / "x.txt"):
            raise OSError("cannot open")
    assert list(tmp_path.iterdir()) == []


def test_staged_files_appear_together_in_order_or_not_at_all(tmp_path):
    with staged_files() as stage:
        stage(tmp_path / "A.IMG").write_text("a")
        stage(tmp_path / "A.LBL", tmp_path / ".A.LBL.migrating").write_text("l")
        assert sorted(p.name for p in tmp_path.iterdir()) == [f".A.IMG.{os.getpid()}.part", ".A.LBL.migrating"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["A.IMG", "A.LBL"]

    with pytest.raises(KeyboardInterrupt):
        with staged_files() as stage:
            stage(tmp_path / "A.IMG").write_text("new a")
            stage(tmp_path / "A.LBL").write_text("new l")
            raise KeyboardInterrupt
    assert sorted(p.name for p in tmp_path.iterdir()) == ["A.IMG", "A.LBL"]
    assert (tmp_path / "A.IMG").read_text() == "a"


def test_a_rename_that_fails_part_way_leaves_no_temporary(tmp_path):
    (tmp_path / "B").mkdir()  # a directory: a file cannot be renamed onto it
    with pytest.raises(OSError):
        with staged_files() as stage:
            stage(tmp_path / "A").write_text("a")
            stage(tmp_path / "B").write_text("b")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["A", "B"] and (tmp_path / "B").is_dir()


# -- replace_directory -----------------------------------------------------------------------------

def _tree(root: Path, text: str) -> Path:
    root.mkdir()
    (root / "f.txt").write_text(text)
    return root


def test_a_directory_takes_the_place_of_a_missing_or_previous_one(tmp_path):
    target = tmp_path / "delivery"
    replace_directory(_tree(tmp_path / ".work1", "first"), target)
    assert (target / "f.txt").read_text() == "first"
    replace_directory(_tree(tmp_path / ".work2", "second"), target)
    assert (target / "f.txt").read_text() == "second"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["delivery"]  # the old tree and the work are gone


def test_the_previous_directory_is_put_back_when_the_new_one_cannot_take_its_place(tmp_path, monkeypatch):
    target = _tree(tmp_path / "delivery", "old")
    work = _tree(tmp_path / ".work", "new")
    real_rename = os.rename

    def refuse_the_work(source, destination):
        if Path(source) == work:
            raise OSError(18, "Invalid cross-device link")
        real_rename(source, destination)

    monkeypatch.setattr(os, "rename", refuse_the_work)
    with pytest.raises(OSError):
        replace_directory(work, target)
    assert (target / "f.txt").read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == [".work", "delivery"]  # no .delivery.old-PID left


# -- process-wide state ------------------------------------------------------------------------------

# module -> what it may change for the whole process, and why: the command's entry point sets
# OPENBLAS_NUM_THREADS for its own process; the S3 client's module keeps boto3 from rasterio
# while a pdsgen command or batch job runs.
PROCESS_STATE_HOMES = {"cli/__init__.py": "os.environ", "storage/objects.py": "sys.modules"}
_MUTATORS = {"setdefault", "update", "pop", "popitem", "clear", "__setitem__", "__delitem__"}


def _process_state_changes(tree: ast.AST) -> set[str]:
    """'os.environ' / 'sys.modules' for each that the code assigns, deletes or mutates an entry of
    (os.putenv/os.unsetenv count as os.environ)."""
    def named(node: ast.AST) -> str | None:
        if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name):
            name = f"{node.value.id}.{node.attr}"
            return name if name in ("os.environ", "sys.modules") else None
        return None

    changed = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Subscript) and isinstance(node.ctx, ast.Store | ast.Del) and named(node.value):
            changed.add(named(node.value))
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute):
            if node.func.attr in _MUTATORS and named(node.func.value):
                changed.add(named(node.func.value))
            elif named(node.func) is None and isinstance(node.func.value, ast.Name) and node.func.value.id == "os" \
                    and node.func.attr in ("putenv", "unsetenv"):
                changed.add("os.environ")
    return {name for name in changed if name is not None}


def test_only_the_entry_point_and_the_s3_client_change_process_wide_state():
    found = {}
    for path in sorted(SRC.rglob("*.py")):
        changes = _process_state_changes(ast.parse(path.read_text(encoding="utf-8")))
        if changes:
            found[path.relative_to(SRC).as_posix()] = changes
    assert found == {module: {state} for module, state in PROCESS_STATE_HOMES.items()}, (
        f"process-wide state changed outside its homes: {found}")


def test_the_process_state_check_sees_each_kind_of_change():
    for code in ('os.environ["X"] = "1"', 'os.environ.setdefault("X", "1")', 'del os.environ["X"]',
                 'os.putenv("X", "1")', 'os.environ.update(X="1")'):
        assert _process_state_changes(ast.parse(code)) == {"os.environ"}, code
    for code in ('sys.modules["boto3"] = None', 'del sys.modules["boto3"]', 'sys.modules.pop("boto3")'):
        assert _process_state_changes(ast.parse(code)) == {"sys.modules"}, code
    for code in ('os.environ.get("X")', '{**os.environ, "X": "1"}', '"boto3" in sys.modules'):
        assert _process_state_changes(ast.parse(code)) == set(), code
