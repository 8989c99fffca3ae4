"""The writers' promises: they open, check, describe, scan and stage their input one way
(products/opening.py, with the mission's hooks), and a label's statement (a mosaic's sources,
an HRSC-AX tile's heights) reaches a writer as one `statement` argument, never as a rewritten
mission."""

from __future__ import annotations

import ast
import inspect
from pathlib import Path

import pdsgen
from pdsgen.missions import get_mission, mission_names

SRC = Path(pdsgen.__file__).parent
WRITERS = ("dtm.py", "ortho.py", "hrsc.py", "imars.py", "hrsc_ax.py")
# The opening steps, written once in products/opening.py.
OPENING_STEPS = {"open_raster", "describe_geometry", "scan_band", "prepare_output_dir", "StagedOutputs"}
# rasterio.open in a writer: only for the files it writes itself (iMars' GeoTIFF, written and read back).
OWN_OUTPUT_OPENS = {("imars.py", "_write_geotiff"), ("imars.py", "write_imars_dtm"), ("imars.py", "write_imars_ori")}


def _called_name(call: ast.Call) -> str | None:
    func = call.func
    if isinstance(func, ast.Name):
        return func.id
    if isinstance(func, ast.Attribute):
        owner = func.value.id if isinstance(func.value, ast.Name) else ""
        return f"{owner}.{func.attr}" if owner else func.attr
    return None


def _calls_by_function(path: Path):
    """(function name, called name) of every call in a module, the function being the outermost one."""
    tree = ast.parse(path.read_text())
    for top in tree.body:
        name = top.name if isinstance(top, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)) else "<module>"
        for node in ast.walk(top):
            if isinstance(node, ast.Call):
                called = _called_name(node)
                if called:
                    yield name, called, node


def test_writers_open_check_describe_scan_and_stage_through_the_shared_opening():
    found = []
    for module in WRITERS:
        for function, called, node in _calls_by_function(SRC / "products" / module):
            if called.split(".")[-1] in OPENING_STEPS:
                found.append(f"{module}:{node.lineno} {called}")
            if called == "rasterio.open" and (module, function) not in OWN_OUTPUT_OPENS:
                found.append(f"{module}:{node.lineno} rasterio.open")
    assert found == []


def test_the_opening_module_holds_the_opening_steps():
    called = {name.split(".")[-1] for _, name, _ in _calls_by_function(SRC / "products" / "opening.py")}
    assert OPENING_STEPS <= called


def _rewrites_a_mission(call: ast.Call) -> bool:
    if _called_name(call) not in ("dataclasses.replace", "replace") or not call.args:
        return False
    first = call.args[0]
    named = first.id if isinstance(first, ast.Name) else first.attr if isinstance(first, ast.Attribute) else ""
    return "mission" in named.lower()


def test_no_writer_or_mosaic_rewrites_a_mission():
    """A label's own words travel as a `ProductStatement`: the mission a writer reads is the registered one."""
    found = [f"{folder}/{path.name}:{node.lineno}"
             for folder in ("products", "mosaic") for path in sorted((SRC / folder).glob("*.py"))
             for _, _, node in _calls_by_function(path) if _rewrites_a_mission(node)]
    assert found == []


def test_every_writer_a_mosaic_reaches_takes_the_statement_as_one_parameter():
    from pdsgen.products.dtm import write_pds3_dtm
    from pdsgen.products.hrsc import write_hrsc_dtm, write_hrsc_nd4
    from pdsgen.products.imars import write_imars_dtm, write_imars_ori
    from pdsgen.products.ortho import write_jp2_ortho

    for writer in (write_pds3_dtm, write_jp2_ortho, write_hrsc_dtm, write_hrsc_nd4, write_imars_dtm,
                   write_imars_ori):
        parameter = inspect.signature(writer).parameters.get("statement")
        assert parameter is not None and parameter.kind is inspect.Parameter.KEYWORD_ONLY, writer.__name__


def test_no_mission_takes_a_mosaic_statement_as_an_option():
    """The statement is the writer's parameter, not an option a mission declares (a second way)."""
    for name in mission_names():
        options = get_mission(name).options
        for kind in ("dtm", "ortho", "mosaic"):
            assert "mosaic_statement" not in options.of(kind), (name, kind)
