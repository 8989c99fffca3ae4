"""Issue 42, labels: one way to read a PDS3 label file and one mapping over its tree.

Counted over src/pdsgen with the AST (function-level imports included): one function named
read_pds3_label; no label mapping (a Mapping subclass) and no quantity class outside label/;
pointers classified in label/ only; the first-bytes test of a PDS3 label written once; and
deliver, review and validate import each other one way (what all three read is archive/)."""

from __future__ import annotations

import ast
from functools import cache
from pathlib import Path

SRC = Path(__file__).resolve().parents[1] / "src" / "pdsgen"
LABEL = SRC / "label"


@cache
def _trees() -> dict[str, ast.Module]:
    return {path.relative_to(SRC).as_posix(): ast.parse(path.read_text()) for path in sorted(SRC.rglob("*.py"))}


def _outside_label(where: str) -> bool:
    return not where.startswith("label/")


def _functions_named(name: str) -> list[str]:
    return [where for where, tree in _trees().items() for node in ast.walk(tree)
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and node.name == name]


def _base_names(node: ast.ClassDef) -> set[str]:
    names = set()
    for base in node.bases:
        target = base.value if isinstance(base, ast.Subscript) else base
        names.add(target.attr if isinstance(target, ast.Attribute) else getattr(target, "id", ""))
    return names


def test_one_function_reads_a_pds3_label_file():
    assert _functions_named("read_pds3_label") == ["label/read.py"]
    assert _functions_named("read_label_head") == ["label/parser.py"]


def _reads_label_trees(tree: ast.Module) -> bool:
    """The module imports from label/ (a mapping elsewhere, of command options, is no label's)."""
    return any(isinstance(node, ast.ImportFrom) and "label" in (node.module or "").split(".")
               for node in ast.walk(tree))


def test_no_label_mapping_and_no_quantity_class_outside_label():
    mappings, quantities = [], []
    for where, tree in _trees().items():
        for node in ast.walk(tree):
            if isinstance(node, ast.ClassDef) and _outside_label(where):
                if _base_names(node) & {"Mapping", "MutableMapping"} and _reads_label_trees(tree):
                    mappings.append(f"{where}:{node.name}")
                if "quantity" in node.name.lower():
                    quantities.append(f"{where}:{node.name}")
    assert mappings == [] and quantities == []


def test_pointers_are_classified_in_label_only():
    assert _functions_named("parse_pointer") == ["label/tree.py"]


def test_the_first_bytes_of_a_pds3_label_are_tested_in_one_place():
    """b"PDS_VERSION_ID", b"CCSD3", b"ODL_VERSION_ID" (what a label file starts with) only in label/."""
    heads = {b"PDS_VERSION_ID", b"CCSD3", b"ODL_VERSION_ID"}
    found = sorted({where for where, tree in _trees().items() for node in ast.walk(tree)
                    if isinstance(node, ast.Constant) and isinstance(node.value, bytes)
                    and any(node.value.startswith(h) for h in heads) and _outside_label(where)})
    assert found == []
    assert _functions_named("is_pds3_head") == ["label/parser.py"]


def _folder_imports(folder: str) -> set[str]:
    """The folders of pdsgen a folder's modules import (at any level of the module)."""
    found = set()
    for where, tree in _trees().items():
        if not where.startswith(folder + "/"):
            continue
        depth = where.count("/")
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and node.level:
                if node.level > depth:  # ..x from pdsgen/<folder>/m.py: another folder
                    parts = (node.module or "").split(".")
                    found.add(parts[0] if parts[0] else node.names[0].name)
            elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("pdsgen."):
                found.add(node.module.split(".")[1])
            elif isinstance(node, ast.Import):
                found |= {a.name.split(".")[1] for a in node.names if a.name.startswith("pdsgen.")}
    return found - {folder}


def test_deliver_review_and_validate_import_one_way():
    """deliver -> review (the page a delivery carries), review -> validate (its findings); the
    layout's names and the grouping of files into products, which all three read, are archive/,
    below them."""
    deliver, review, validate = (_folder_imports(f) for f in ("deliver", "review", "validate"))
    assert "review" in deliver and "validate" in review
    assert "deliver" not in review and "deliver" not in validate and "validate" not in deliver
    assert {"archive"} <= deliver & review & validate
    assert not _folder_imports("archive") & {"deliver", "review", "validate"}
