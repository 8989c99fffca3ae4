"""One result contract for every command (issue 42): each command's library call returns a
`CommandResult`, the CLI and `pdsgen batch` render any result through that contract only, and
`--json` has one shape across commands."""

from __future__ import annotations

import ast
import importlib
import json
import typing
from dataclasses import dataclass
from pathlib import Path

import pytest
from click.testing import CliRunner

import pdsgen
from pdsgen.results import CommandResult

from helpers import CRS_EQUIRECTANGULAR, ORIGINS, elevation_array, write_raster

SRC = Path(pdsgen.__file__).parent
COMMON = ["command", "files", "warnings"]

# The library call behind each command that prints a result ("module:function").
COMMAND_CALLS = {
    "dtm": "pdsgen.products.dtm:write_dtm",
    "ortho": "pdsgen.products.ortho:write_ortho",
    "mosaic": "pdsgen.mosaic.write:write_mosaic",
    "migrate": "pdsgen.migrate.product:migrate_products",
    "deliver": "pdsgen.deliver.build:make_delivery",
    "review": "pdsgen.review:write_review",
    "demo": "pdsgen.demo:run_demo",
}
# Results a command builds from what its library call returns (make_extras returns its list of
# paths; a mosaic is told by its directory and files).
WRAPPERS = ("pdsgen.extras.result:ExtrasResult", "pdsgen.products.result:ListedProduct")
# What a result says through the contract: reading these is reading the contract.
CONTRACT = {name for name in dir(CommandResult) if not name.startswith("_")} | {"warnings"}


def _named(target: str) -> object:
    module, _, name = target.partition(":")
    return getattr(importlib.import_module(module), name)


def _command_result_classes() -> dict[str, type]:
    """CommandResult and every class deriving from it, once every command's module is loaded."""
    for target in (*COMMAND_CALLS.values(), *WRAPPERS):
        _named(target)
    for name in ("pdsgen.products.hrsc", "pdsgen.products.imars", "pdsgen.products.hrsc_ax"):
        importlib.import_module(name)
    found: dict[str, type] = {"CommandResult": CommandResult}
    pending: list[type] = [CommandResult]
    while pending:
        for sub in pending.pop().__subclasses__():
            if sub.__module__.startswith("pdsgen."):
                found[sub.__name__] = sub
                pending.append(sub)
    return found


@pytest.mark.parametrize("command", sorted(COMMAND_CALLS))
def test_every_command_call_returns_a_command_result(command):
    declared = typing.get_type_hints(_named(COMMAND_CALLS[command]))["return"]
    assert isinstance(declared, type) and issubclass(declared, CommandResult), f"{command}: {declared!r}"


def test_wrapped_results_keep_the_contract_too():
    for target in WRAPPERS:
        kind = _named(target)
        assert isinstance(kind, type) and issubclass(kind, CommandResult), target
    for name, kind in _command_result_classes().items():
        if name not in ("CommandResult", "ProductResult", "HrscProduct"):  # the contracts, HRSC's shared fields
            assert not getattr(kind, "__abstractmethods__", None), f"{name} leaves {kind.__abstractmethods__} open"


def _output_commands(tree: ast.Module) -> list[ast.FunctionDef]:
    """The functions decorated with output_options (under any name it is imported as)."""
    return [node for node in tree.body if isinstance(node, ast.FunctionDef)
            and any("output_options" in ast.unparse(decorator) for decorator in node.decorator_list)]


def test_the_cli_builds_no_output_of_its_own():
    """Each command hands its result to `told`; no command body writes a JSON document (a dict
    with a "command" member, a json.dumps) or a summary line of its own."""
    offenders, commands = [], 0
    for path in sorted((SRC / "cli").glob("*.py")):
        if path.name == "_output.py":
            continue
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.Dict) and any(isinstance(key, ast.Constant) and key.value == "command"
                                                  for key in node.keys):
                offenders.append(f"cli/{path.name}:{node.lineno}: a JSON document of its own")
            elif isinstance(node, ast.Call) and ast.unparse(node.func) == "json.dumps":
                offenders.append(f"cli/{path.name}:{node.lineno}: json.dumps")
        for function in _output_commands(tree):
            commands += 1
            returns = [node for node in ast.walk(function) if isinstance(node, ast.Return)]
            if not returns or not all(isinstance(r.value, ast.Call) and ast.unparse(r.value.func) == "told"
                                      for r in returns):
                offenders.append(f"cli/{path.name}: {function.name} returns something other than told(result)")
    assert commands >= 8 and offenders == []


def test_cli_and_batch_read_every_command_result_through_the_contract_only():
    """As tests/test_architecture.py holds it for product results, for every command's result: no
    isinstance/issubclass against a result class, no getattr/hasattr of a field beyond the contract."""
    classes = _command_result_classes()
    fields: set[str] = set()
    for kind in classes.values():
        fields |= {n for n in vars(kind) if not n.startswith("_")} | set(getattr(kind, "__dataclass_fields__", ()))
    fields -= CONTRACT
    offenders = []
    for folder in ("cli", "batch"):
        for path in sorted((SRC / folder).glob("*.py")):
            for node in ast.walk(ast.parse(path.read_text())):
                if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and len(node.args) >= 2):
                    continue
                where = f"{folder}/{path.name}:{node.lineno}"
                if node.func.id in ("isinstance", "issubclass"):
                    named = {n.id if isinstance(n, ast.Name) else n.attr for n in ast.walk(node.args[1])
                             if isinstance(n, ast.Name | ast.Attribute)}
                    offenders += [(where, name) for name in named & set(classes)]
                elif node.func.id in ("getattr", "hasattr") and isinstance(node.args[1], ast.Constant) \
                        and node.args[1].value in fields:
                    offenders.append((where, node.args[1].value))
    assert offenders == []


def test_a_result_may_not_redefine_a_common_member():
    @dataclass(frozen=True)
    class Loose(CommandResult):
        warnings: tuple[str, ...] = ()
        files: tuple[Path, ...] = ()  # type: ignore[assignment]
        summary_lines: tuple[str, ...] = ()  # type: ignore[assignment]

        def details(self):
            return {"files": 3}

    with pytest.raises(ValueError, match="Loose.details\\(\\) names common member"):
        Loose().as_json("loose")
    assert Loose().exit_code == 0


def _json(*args: object) -> dict:
    from pdsgen.cli import main

    result = CliRunner().invoke(main, [str(a) for a in args], catch_exceptions=False)
    assert result.exit_code in (0, 2), result.output
    return json.loads(result.stdout)


def _one_shape(document: dict, command: str) -> None:
    assert document["files"], command
    _one_shape_written_or_not(document, command)


def _one_shape_written_or_not(document: dict, command: str) -> None:
    assert list(document)[:3] == COMMON and document["command"] == command
    assert isinstance(document["warnings"], list) and all(isinstance(w, str) for w in document["warnings"])
    for entry in document["files"]:
        assert set(entry) == {"path", "bytes"} and Path(entry["path"]).stat().st_size == entry["bytes"], entry


def test_json_has_one_shape_across_commands(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    source = write_raster(tmp_path / "dtm.tif", elevation_array(24, 20, seed=3), CRS_EQUIRECTANGULAR,
                          ORIGINS["equirectangular"][1])
    dtm = _json("dtm", source, "-o", "products", "--json")
    _one_shape(dtm, "dtm")
    img = dtm["files"][0]["path"]
    _one_shape(_json("extras", img, "-o", "products/extras", "--browse-width", "16", "--json"), "extras")
    (tmp_path / "products" / "stray.dat").write_text("x")
    delivered = _json("deliver", "products", "-o", "volume", "--volume-id", "V1", "--json")
    _one_shape(delivered, "deliver")
    assert delivered["warnings"] == ["products/stray.dat: no label names it and no Extras rule claims it; "
                                     "not delivered"]
    assert {"volume/MD5SUMS.TXT", "volume/REVIEW.html", "volume/DATA/DTM.IMG"} <= \
        {entry["path"] for entry in delivered["files"]}
    assert delivered["file_count"] == len(delivered["files"]) - 1  # the review page is not in the manifest
    review = _json("review", "volume", "-o", "page.html", "--json")
    _one_shape(review, "review")
    assert review["files"][0]["path"] == "page.html" and set(review["finding_counts"]) == {"error", "warning", "info"}
    assert not {"errors", "info", "findings"} & set(review)  # each count once, under one name
    checked = _json("validate", "volume", "--json")  # validate's --json as every other command's
    _one_shape_written_or_not(checked, "validate")
    assert checked["finding_counts"] == review["finding_counts"] and checked["warnings"] == []
    assert all(isinstance(f, dict) and f["rule"] for f in checked["findings"])
    report = _json("validate", "volume", "--format", "json", "-o", "report.json", "--json")
    assert [entry["path"] for entry in report["files"]] == ["report.json"]
    migrated = _json("migrate", img, "dtm.tif", "-o", "pds4", "--json")
    _one_shape(migrated, "migrate")
    assert [entry["path"] for entry in migrated["files"]] == ["pds4/DTM.xml", "pds4/DTM.IMG"]
    assert len(migrated["refused"]) == 1 and migrated["migrated"][0]["label"] == "pds4/DTM.xml"
