"""The architecture's promises: one home per mission fact, dispatch by profile, no import cycles,
and a new mission is one registration (README "Adding a mission")."""

from __future__ import annotations

import ast
import re
import sys
from pathlib import Path

import numpy as np
import pytest
from affine import Affine

import pdsgen
from pdsgen.errors import InputError, OutputError, ParamsError, PdsgenError
from pdsgen.missions import (
    LabelFacts,
    Mission,
    ProductIdRequest,
    detect_mission,
    get_mission,
    mission_names,
    register_mission,
    unregister_mission,
)
from pdsgen.products.dtm import DtmProduct, write_dtm
from pdsgen.products.hrsc import HrscDtmProduct, HrscImageProduct
from pdsgen.products.imars import ImarsProduct
from pdsgen.products.ortho import OrthoProduct, write_ortho
from pdsgen.products.result import ProductResult

from helpers import CRS_EQUIRECTANGULAR, elevation_array, write_raster

SRC = Path(pdsgen.__file__).parent
HRSC_SINUSOIDAL = "+proj=sinu +lon_0=70 +R=3396000 +units=m +no_defs"

# Mission facts that may appear only in pdsgen/missions/: numbers and text fragments.
MISSION_NUMBERS = {3396.0, 3396000.0, -32768, -1e32}
MISSION_TEXT = ("_ucl.pvl", "ESA/DLR/FU Berlin", "University of Arizona", "MEX-M-HRSC", "MRO-M-HIRISE",
                r"h(?P<orbit>", r"h\d{4", r"_d[at]4", "UNIVERSITY OF ARIZONA", "DLR / FREIE",
                "PSP|ESP", "DT[EP]")
# No known leftovers: validate/ and extras/ import their mission facts from pdsgen.missions.
KNOWN_EXCEPTIONS: set[tuple[str, str]] = set()


def _module_constants(tree: ast.AST) -> list[object]:
    """Every literal in a module except docstrings."""
    docstrings = {id(node.body[0].value) for node in ast.walk(tree)
                  if isinstance(node, (ast.Module, ast.FunctionDef, ast.ClassDef, ast.AsyncFunctionDef))
                  and node.body and isinstance(node.body[0], ast.Expr)
                  and isinstance(node.body[0].value, ast.Constant)}
    found: list[object] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub) and isinstance(node.operand, ast.Constant):
            if isinstance(node.operand.value, (int, float)):
                found.append(-node.operand.value)
        elif isinstance(node, ast.Constant) and id(node) not in docstrings:
            found.append(node.value)
    return found


def test_mission_facts_live_only_in_missions():
    offenders = []
    for path in sorted(SRC.rglob("*.py")):
        relative = path.relative_to(SRC).as_posix()
        if relative.startswith("missions/"):
            continue
        for value in _module_constants(ast.parse(path.read_text())):
            if isinstance(value, (int, float)) and not isinstance(value, bool) and value in MISSION_NUMBERS:
                offenders.append((relative, repr(value)))
            elif isinstance(value, str):
                offenders += [(relative, text) for text in MISSION_TEXT if text in value]
    assert set(offenders) - KNOWN_EXCEPTIONS == set()


def _imports(path: Path, module: str, modules: set[str], everywhere: bool = False) -> set[str]:
    """Modules a module imports at import time (not under TYPE_CHECKING, not inside functions),
    or with `everywhere` also those inside functions and under TYPE_CHECKING."""
    tree = ast.parse(path.read_text())
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    names: set[str] = set()
    # `if TYPE_CHECKING:` blocks do not run
    nodes = ast.walk(tree) if everywhere else (node for node in tree.body if not isinstance(node, ast.If))
    for node in nodes:
        if isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")
                parts = parts[: len(parts) - node.level + 1]
                base = ".".join(parts + ([base] if base else []))
            for alias in node.names:  # `from p import m` imports the module p.m when there is one, else p
                names.add(f"{base}.{alias.name}" if f"{base}.{alias.name}" in modules else base)
        elif isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
    return {n for n in names if n.startswith("pdsgen")}


def _module_graph() -> dict[str, set[str]]:
    modules = {}
    for path in SRC.rglob("*.py"):
        parts = ("pdsgen", *path.relative_to(SRC).with_suffix("").parts)
        name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        modules[name] = path
    known = set(modules)
    return {name: {i for i in _imports(path, name, known) if i in known and i != name}
            for name, path in modules.items()}


def test_no_import_cycles():
    graph = _module_graph()
    state: dict[str, int] = {}
    cycles: list[list[str]] = []

    def visit(node: str, trail: list[str]) -> None:
        state[node] = 1
        for target in sorted(graph[node]):
            if state.get(target) == 1:
                cycles.append(trail[trail.index(target):] + [target] if target in trail else [node, target])
            elif target not in state:
                visit(target, trail + [target])
        state[node] = 2

    sys.setrecursionlimit(max(sys.getrecursionlimit(), 5000))
    for name in sorted(graph):
        if name not in state:
            visit(name, [name])
    assert cycles == []


def test_public_api_from_the_top_level_and_error_hierarchy():
    assert pdsgen.write_dtm is write_dtm and pdsgen.write_ortho is write_ortho
    assert callable(pdsgen.make_extras) and callable(pdsgen.validate_paths)
    assert issubclass(InputError, PdsgenError) and issubclass(InputError, ValueError)
    assert issubclass(OutputError, PdsgenError) and issubclass(OutputError, OSError)
    assert issubclass(ParamsError, PdsgenError) and pdsgen.PdsgenError is PdsgenError
    assert str(OutputError("out/x.IMG", "exists")) == "out/x.IMG: exists"


@pytest.fixture(scope="module")
def inputs(tmp_path_factory):
    root = tmp_path_factory.mktemp("profiles")
    heights = elevation_array(24, 20, seed=3)
    image = np.linspace(0.05, 0.25, 24 * 20, dtype=np.float32).reshape(24, 20)
    eqc = Affine(1.0, 0, 6123456.0, 0, -1.0, -563210.0)
    sinu = Affine(50.0, 0, -10000.0, 0, -50.0, -1000000.0)
    return {
        "dtm": write_raster(root / "dtm.tif", heights, CRS_EQUIRECTANGULAR, eqc),
        "ortho": write_raster(root / "ortho.tif", image, CRS_EQUIRECTANGULAR, eqc),
        "hrsc_dtm": write_raster(root / "h_dtm.tif", heights, HRSC_SINUSOIDAL, sinu),
        "hrsc_ortho": write_raster(root / "h_ortho.tif", image, HRSC_SINUSOIDAL, sinu),
    }


DTM_CASES = {
    "generic": ("dtm", {}, DtmProduct),
    "hirise": ("dtm", {"source_product_ids": ["PSP_008669_1705", "PSP_009025_1705"], "institution": "U"},
               DtmProduct),
    "hrsc": ("hrsc_dtm", {"product_id": "h1234_0000", "precision": 0.5}, HrscDtmProduct),
    "imars": ("hrsc_dtm", {"product_id": "h1234_0000", "kind": "dt4"}, ImarsProduct),
}
ORTHO_CASES = {
    "generic": ("ortho", {}, OrthoProduct),
    "hirise": ("ortho", {"observation_id": "PSP_008669_1705"}, OrthoProduct),
    "hrsc": ("hrsc_ortho", {"product_id": "h1234_0000"}, HrscImageProduct),
    "imars": ("hrsc_ortho", {"product_id": "h1234_0000"}, ImarsProduct),
}


@pytest.mark.parametrize(("product", "profile"), [(p, m) for p in ("dtm", "ortho") for m in sorted(DTM_CASES)])
def test_write_dtm_and_write_ortho_dispatch_to_every_profile(tmp_path, inputs, product, profile):
    writer, cases = (write_dtm, DTM_CASES) if product == "dtm" else (write_ortho, ORTHO_CASES)
    source, options, kind = cases[profile]
    result = writer(inputs[source], tmp_path, profile=profile, **options)
    assert isinstance(result, kind) and isinstance(result, ProductResult) and result.product_id
    assert result.files and all(path.is_file() for path in result.files)


def test_an_option_the_profile_does_not_use_is_refused(tmp_path, inputs):
    with pytest.raises(ParamsError, match="the generic profile does not use precision"):
        write_dtm(inputs["dtm"], tmp_path, profile="generic", precision=0.5)
    assert list(tmp_path.iterdir()) == []


def test_adding_a_mission(tmp_path, inputs):
    """The README's "Adding a mission" how-to, followed step by step."""
    toy = Mission(
        name="toy",
        dtm_keywords={**get_mission("generic").dtm_keywords, "INSTRUMENT_ID": "TOYCAM", "DATA_SET_ID": "TOY-DTM"},
        dtm_note="Toy heights in meters.",
        credit="Toy Space Agency",
        dtm_product_id=lambda request: f"TOY_{request.stem.upper()}_{request.geometry.lines}",
    )
    register_mission(toy)
    try:
        assert "toy" in mission_names()
        product = write_dtm(inputs["dtm"], tmp_path, profile="toy")
        assert product.product_id == "TOY_DTM_24"
        label = product.label_text
        assert 'DATA_SET_ID' in label and '"TOY-DTM"' in label
        assert "TOYCAM" in label and "Toy heights in meters." in label
        with pytest.raises(PdsgenError, match="toy profile writes orthoimages in its own form"):
            write_ortho(inputs["ortho"], tmp_path, profile="toy")
        assert toy.dtm_product_id is not None
        assert toy.dtm_product_id(ProductIdRequest("x", product.geometry)) == "TOY_X_24"
    finally:
        unregister_mission("toy")
    with pytest.raises(PdsgenError, match="unknown profile 'toy'"):
        write_dtm(inputs["dtm"], tmp_path, profile="toy")


@pytest.mark.parametrize(("facts", "expected"), [
    (LabelFacts(instrument_id="HRSC"), "hrsc"),
    (LabelFacts(data_set_id="MEX-M-HRSC-5-REFDR-DTM-V1.0"), "hrsc"),
    (LabelFacts(group_names=frozenset({"MEX:DTM"})), "hrsc"),
    (LabelFacts(file_name="h1234_0000_dt4.img"), "hrsc"),
    (LabelFacts(file_name="h1234_0000_nd3.img"), None),  # level 3 names alone do not say level-4 HRSC
    (LabelFacts(instrument_id="HIRISE"), "hirise"),
    (LabelFacts(data_set_id="MRO-M-HIRISE-5-DTM-V1.0"), "hirise"),
    (LabelFacts(instrument_id="MOLA", file_name="megt90n000cb.lbl"), None),
])
def test_one_mission_detection_for_extras_and_validator(facts, expected):
    """Extras and the validator both ask `detect_mission`, so they cannot disagree again."""
    assert detect_mission(facts) == expected


# -- the validator: rule families are modules in validate/families/, tied by one registry ---------

VALIDATE = SRC / "validate"


def test_every_rule_family_is_one_module_in_validate_families_registering_its_rules():
    from pdsgen.validate import rules

    assert sorted(p.name for p in VALIDATE.glob("*_rules.py")) == []  # no family outside families/
    assert not (VALIDATE / "rules.py").exists()  # nothing shadowed by the public rules() function
    family_modules = sorted(p for p in (VALIDATE / "families").glob("*.py") if p.name != "__init__.py")
    for path in family_modules:
        tree = ast.parse(path.read_text())
        registrations = [node for node in ast.walk(tree) if isinstance(node, ast.Call)
                         and isinstance(node.func, ast.Name) and node.func.id == "register"]
        assert len(registrations) == 1, f"{path.name} registers its rules in one register() call"
    owners = {rule.check.__module__ for rule in rules().values() if rule.check is not None}
    owners |= {rule.set_check.__module__ for rule in rules().values() if rule.set_check is not None}
    assert owners <= {f"pdsgen.validate.families.{path.stem}" for path in family_modules}


def test_a_rule_family_registered_at_run_time_is_listed_configured_and_run(tmp_path):
    from click.testing import CliRunner

    from pdsgen.cli import main
    from pdsgen.validate import rules, validate_paths
    from pdsgen.validate.model import Hit
    from pdsgen.validate.registry import Rule, families, register, unregister

    def check_product_id_is_toy(ctx):
        product_id = ctx.root.text("PRODUCT_ID")
        if product_id and not product_id.startswith("TOY"):
            yield Hit(f"PRODUCT_ID {product_id} does not start with TOY", keyword="PRODUCT_ID")

    label = tmp_path / "A.LBL"
    label.write_bytes(b'PDS_VERSION_ID = PDS3\r\nPRODUCT_ID = "A"\r\nEND\r\n')
    register(Rule("TOY-001", "warning", "PRODUCT_IDs start with TOY", check_product_id_is_toy))
    try:
        assert families()[-1] == "TOY" and list(rules())[-1] == "TOY-001"
        listed = CliRunner().invoke(main, ["validate", "--list-rules"])
        assert "TOY-001" in listed.output and "PRODUCT_IDs start with TOY" in listed.output
        found = [f for f in validate_paths([label]).findings if f.rule == "TOY-001"]
        assert [(f.severity, f.keyword) for f in found] == [("warning", "PRODUCT_ID")]
        ignored = CliRunner().invoke(main, ["validate", "--ignore", "TOY", "--format", "json", str(label)])
        assert "TOY-001" not in ignored.output
        with pytest.raises(ValueError, match="already registered"):
            register(Rule("TOY-001", "error", "again", check_product_id_is_toy))
    finally:
        unregister("TOY")
    assert "TOY-001" not in rules() and "TOY" not in families()
    assert not [f for f in validate_paths([label]).findings if f.rule == "TOY-001"]
    with pytest.raises(ValueError, match="built-in"):
        unregister("MAP")


# -- a product result is a contract (issue 34 item 5); one import path per thing (item 6) -----------

RESULT_MODULES = ("pdsgen.products.dtm", "pdsgen.products.ortho", "pdsgen.products.hrsc", "pdsgen.products.imars",
                  "pdsgen.products.hrsc_ax", "pdsgen.mosaic.write")


def _result_classes() -> dict[str, type]:
    """ProductResult and every class deriving from it, once the writers' modules are loaded."""
    import importlib

    for name in RESULT_MODULES:
        importlib.import_module(name)
    found: dict[str, type] = {"ProductResult": ProductResult}
    pending = [ProductResult]
    while pending:
        for sub in pending.pop().__subclasses__():
            found[sub.__name__] = sub
            pending.append(sub)
    return found


def _declared_return(function) -> object:
    """A function's declared return type, resolved in its module (and the result classes, which
    a module may import only for type checking)."""
    import importlib

    annotation = function.__annotations__.get("return")
    if not isinstance(annotation, str):
        return annotation
    namespace = {**vars(importlib.import_module(function.__module__)), **_result_classes()}
    return eval(annotation, namespace)  # an annotation in our own source


def test_every_writer_declares_a_product_result_not_any():
    import importlib
    import inspect

    writers = [function for name in RESULT_MODULES
               for function_name, function in vars(importlib.import_module(name)).items()
               if function_name.startswith("write_") and inspect.isfunction(function)
               and function.__module__ == name]
    writers += [writer for name in mission_names() for kind in ("dtm", "ortho")
                if (writer := get_mission(name).writer(kind)) is not None]
    assert len(writers) >= 11
    for writer in writers:
        declared = _declared_return(writer)
        assert isinstance(declared, type) and issubclass(declared, ProductResult), \
            f"{writer.__module__}.{writer.__name__} returns {declared!r}, not a ProductResult"
    from pdsgen.products.dispatch import call_mission_writer

    assert _declared_return(call_mission_writer) is ProductResult


def test_every_result_class_states_its_summary_line_and_files():
    for name, kind in _result_classes().items():
        if name in ("ProductResult", "HrscProduct"):  # the contract and HRSC's shared fields
            continue
        assert not getattr(kind, "__abstractmethods__", None), f"{name} leaves {kind.__abstractmethods__} open"
        assert {"product_id", "geometry", "warnings"} <= set(kind.__dataclass_fields__), name


def test_a_mission_writer_that_breaks_the_contract_is_refused(tmp_path, inputs):
    def untyped_writer(input_path, outdir, options):
        return {"product_id": "LOOSE"}

    register_mission(Mission(name="loose", dtm_keywords=get_mission("generic").dtm_keywords, dtm_note="",
                             credit="", dtm_writer=untyped_writer))
    try:
        with pytest.raises(TypeError, match="untyped_writer returned a dict, not a ProductResult"):
            write_dtm(inputs["dtm"], tmp_path, profile="loose")
    finally:
        unregister_mission("loose")


# Fields of the results: asking an object for one of them is asking which product it is.
def _result_attributes() -> set[str]:
    names: set[str] = set()
    for kind in _result_classes().values():
        names |= {n for n in vars(kind) if not n.startswith("_")} | set(getattr(kind, "__dataclass_fields__", ()))
    return names


def test_cli_and_batch_read_results_through_the_contract_only():
    """No isinstance/issubclass against a result class, no getattr/hasattr of a result's field:
    each result says its own summary line, warnings and files."""
    classes, attributes = set(_result_classes()), _result_attributes()
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
                    offenders += [(where, name) for name in named & classes]
                elif node.func.id in ("getattr", "hasattr") and isinstance(node.args[1], ast.Constant) \
                        and node.args[1].value in attributes:
                    offenders.append((where, node.args[1].value))
    assert offenders == []


def test_the_top_level_re_export_modules_are_gone():
    """Version 0.1 has one import path per thing: `pdsgen.<name>` for the public API (the lazy
    table of pdsgen/__init__.py), else the module that defines it."""
    import importlib
    import importlib.util

    for name in ("dtm", "ortho", "hrsc", "imars"):
        assert importlib.util.find_spec(f"pdsgen.{name}") is None, f"pdsgen/{name}.py is back"
    for path in sorted(SRC.glob("*.py")):
        if path.name in ("__init__.py", "__main__.py"):
            continue
        module = importlib.import_module(f"pdsgen.{path.stem}")
        for name in getattr(module, "__all__", ()):
            home = getattr(getattr(module, name), "__module__", module.__name__)
            assert home == module.__name__, f"pdsgen.{path.stem} re-exports {name} of {home}"
    if importlib.util.find_spec("pdsgen.profiles") is not None:
        assert not hasattr(importlib.import_module("pdsgen.profiles"), "Profile")
    for name in pdsgen.__all__:  # the public API itself resolves
        assert getattr(pdsgen, name) is not None


# -- one option vocabulary: a mission declares its options; cli/ derives flags, tables and refusals ---


def test_a_mission_declaring_an_option_gets_the_flag_and_the_refusal_with_no_cli_edit(tmp_path, inputs):
    """A toy mission that uses --institution (in its product IDs) and not --byte-order: the
    command line passes the one to the library and refuses the other, as the library does."""
    from click.testing import CliRunner

    from pdsgen.cli import dtm as dtm_cli
    from pdsgen.cli import main
    from pdsgen.missions import STANDARD_OPTIONS, OptionUse

    toy = Mission(
        name="toy",
        dtm_keywords={**get_mission("generic").dtm_keywords, "INSTRUMENT_ID": "TOYCAM"},
        dtm_product_id=lambda request: f"TOY_{request.institution or 'X'}_{request.geometry.lines}",
        options=OptionUse(dtm=frozenset({"institution", "label"}), ortho=STANDARD_OPTIONS.ortho,
                          mosaic=STANDARD_OPTIONS.mosaic),
    )
    register_mission(toy)  # after pdsgen.cli.dtm was imported: nothing in cli/ knows of it
    try:
        assert "institution" in dtm_cli.USED_BY_PROFILE["toy"] and "byte_order" not in dtm_cli.USED_BY_PROFILE["toy"]
        assert "toy" in CliRunner().invoke(main, ["dtm", "--help"]).output
        made = CliRunner().invoke(main, ["dtm", str(inputs["dtm"]), "-o", str(tmp_path / "cli"), "--profile", "toy",
                                         "--institution", "U"])
        assert made.exit_code == 0, made.output
        assert (tmp_path / "cli" / "TOY_U_24.IMG").is_file()
        refused = CliRunner().invoke(main, ["dtm", str(inputs["dtm"]), "-o", str(tmp_path / "refused"),
                                            "--profile", "toy", "--byte-order", "msb"])
        assert refused.exit_code == 2 and "--byte-order does not apply to --profile toy" in refused.output
        assert not (tmp_path / "refused").exists()
        with pytest.raises(ParamsError, match="the toy profile does not use byte_order"):
            write_dtm(inputs["dtm"], tmp_path / "api", profile="toy", byte_order="msb")
        assert write_dtm(inputs["dtm"], tmp_path / "api", profile="toy", institution="V").product_id == "TOY_V_24"
    finally:
        unregister_mission("toy")
    gone = CliRunner().invoke(main, ["dtm", str(inputs["dtm"]), "-o", str(tmp_path / "gone"), "--profile", "toy"])
    assert gone.exit_code == 2 and "toy" not in dtm_cli.USED_BY_PROFILE


def test_every_declared_option_is_one_the_missions_writer_takes():
    """A declaration naming an option the writer lacks would pass the CLI's check and then fail
    in the writer: every declared option is one the writers' options object carries, and the
    writers take that object (`writer(input_path, outdir, options)`)."""
    import dataclasses
    import inspect

    from pdsgen.products.dtm import write_pds3_dtm
    from pdsgen.products.options import DTM_OPTIONS, ORTHO_OPTIONS, ProductOptions, library_keywords
    from pdsgen.products.ortho import write_jp2_ortho

    standard = {"dtm": write_pds3_dtm, "ortho": write_jp2_ortho}
    for name in mission_names():
        mission = get_mission(name)
        for kind, vocabulary in (("dtm", DTM_OPTIONS), ("ortho", ORTHO_OPTIONS)):
            writer = mission.writer(kind) or standard[kind]
            assert list(inspect.signature(writer).parameters)[:3] == ["input_path", "outdir", "options"], name
            takes = {field.name for field in dataclasses.fields(ProductOptions)}
            declared = library_keywords(kind, mission, vocabulary)
            # bits: write_ortho itself checks a mission's own 8-bit forms; threads: library-only
            assert declared - takes - {"bits", "threads"} == set(), (name, kind)


def test_no_profile_name_in_cli():
    """cli/ names no mission: its flags, per-profile tables and help come from the declarations."""
    import re

    names = sorted(mission_names(), key=len, reverse=True)
    pattern = re.compile(r"(?<![\w-])(" + "|".join(map(re.escape, names)) + r")(?![\w-])")
    found = []
    for path in sorted((SRC / "cli").glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Constant) and isinstance(node.value, str) and pattern.search(node.value):
                found.append(f"{path.name}:{node.lineno}: {pattern.search(node.value).group(0)}")
    assert found == []


def test_no_profile_name_in_the_mosaic_writer():
    """write_mosaic asks the mission (Mission.mosaic_reader / mosaic_writer / mosaic_product_id)
    instead of comparing profile names; the HRSC-AX reader and the iMars form are modules of
    their own that those missions name."""
    import re

    names = sorted(mission_names(), key=len, reverse=True)
    pattern = re.compile(r"(?<![\w-])(" + "|".join(map(re.escape, names)) + r")(?![\w-])")
    found = []
    for name in ("write.py", "plan.py", "vrt.py", "options.py"):
        for node in ast.walk(ast.parse((SRC / "mosaic" / name).read_text())):
            if isinstance(node, ast.Compare) and any(isinstance(c, ast.Constant) and isinstance(c.value, str)
                                                     and pattern.fullmatch(c.value) for c in node.comparators):
                found.append(f"{name}:{node.lineno}")
    assert found == []


# -- no circle even through imports made late: inside functions, under TYPE_CHECKING ----------------


def _every_import(path: Path, module: str, modules: set[str]) -> set[str]:
    """Modules a module imports anywhere: at the top, inside functions (made on first call, to
    keep start-up light) and under `if TYPE_CHECKING:` (read by mypy). A circle through any of
    them is still a circle: the two modules cannot be understood, tested or moved apart."""
    return {n for n in _imports(path, module, modules, everywhere=True) if n in modules and n != module}


def _full_module_graph() -> dict[str, set[str]]:
    modules = {}
    for path in SRC.rglob("*.py"):
        parts = ("pdsgen", *path.relative_to(SRC).with_suffix("").parts)
        modules[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    return {name: _every_import(path, name, set(modules)) for name, path in modules.items()}


def _circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected groups of more than one module (Tarjan), each sorted."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    groups: list[list[str]] = []

    def visit(node: str) -> None:
        index[node] = low[node] = len(index)
        stack.append(node)
        for target in sorted(graph[node]):
            if target not in index:
                visit(target)
                low[node] = min(low[node], low[target])
            elif target in stack:
                low[node] = min(low[node], index[target])
        if low[node] == index[node]:
            group = []
            while True:
                member = stack.pop()
                group.append(member)
                if member == node:
                    break
            if len(group) > 1:
                groups.append(sorted(group))

    sys.setrecursionlimit(max(sys.getrecursionlimit(), 5000))
    for name in sorted(graph):
        if name not in index:
            visit(name)
    return groups


def test_no_import_circle_through_function_level_or_type_checking_imports():
    graph = _full_module_graph()
    # imported inside a function
    assert "pdsgen.validate.pds4.label_checks" in graph["pdsgen.validate.families.pds4_rules"]
    assert _circles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]  # the finder finds
    assert _circles(graph) == []


def test_no_two_classes_in_pdsgen_share_a_name():
    """A name says what a thing is: two `Report`s (a validation run, one PDS4 label's hits) or two
    `Settings` made readers and imports guess which one is meant."""
    homes: dict[str, list[str]] = {}
    for path in sorted(SRC.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ClassDef):
                homes.setdefault(node.name, []).append(path.relative_to(SRC).as_posix())
    assert "ValidationReport" in homes and "RuleSettings" in homes and "LabelSummary" in homes
    assert {name: where for name, where in homes.items() if len(where) > 1} == {}


# -- floors: imports run down, no two folders import each other (issue 42) -------------------------

# The folders of src/pdsgen, lowest floor first, each with why it stands there. A module imports
# from its own folder and the floors below; the top-level modules (errors.py, resources.py,
# params.py ...) are the ground under every floor and not counted.
FLOORS = (
    ("storage", "where files live, on disk or in an object store, and how they are written whole: "
                "imports no folder"),
    ("label", "the PDS3 label grammar, reader and writer: imports no folder"),
    ("geo", "geometry both ways, its conventions and the label -> CRS reading: imports no folder"),
    ("formats", "file formats (IMG, JP2, VICAR, footprints, staging): geometry, labels, storage"),
    ("missions", "every mission fact, stated over geo's MapGeometry and projection names"),
    ("pds4", "PDS4 facts and label writers, over formats, geometry and mission facts"),
    ("archive", "an archive's layout (its file names) and the scan of a tree for products and their labels"),
    ("validate", "the validator, PDS4 checks included: labels, data, PDS4 facts, mission conventions"),
    ("products", "the DTM/ortho writers: check their labels with the validator, write PDS4 labels"),
    ("extras", "browse images and READMEs made from a product and its label"),
    ("mosaic", "mosaics: the writers of products/, extras' reading of a product's source"),
    ("migrate", "PDS3 -> PDS4: pds4's writers, the validator's judgement of a label's offsets"),
    ("review", "the review page: validation reports, extras' renderings, footprints"),
    ("deliver", "a delivery: migrates, validates, writes the review page"),
    ("batch", "many products in worker processes"),
    ("cli", "the command line over all of it"),
)
# The top-level modules every floor may import: they import no folder (params.py, read by pds4's
# label writers and by products/, is one of them so that pds4 need not import products).
GROUND = ("pdsgen.errors", "pdsgen.resources", "pdsgen.dialect", "pdsgen.params", "pdsgen._compat", "pdsgen.encode",
          "pdsgen.progress", "pdsgen.clock", "pdsgen.bounded")
# Folder pairs allowed to import each other: none. A pair that appears must be taken apart (or
# named here with the reason, which review then weighs).
TWO_WAY_ALLOWED: dict[frozenset[str], str] = {}
# The import allowed to run back up a floor, (importer, imported) -> why: at most one, none today
# (the delivery's file names, which the DELIVERY rules read, live in archive/ below validate/).
BACK_UP: dict[tuple[str, str], str] = {}


def _folder(module: str) -> str | None:
    """The folder of src/pdsgen a module is in (None for a top-level module)."""
    parts = module.split(".")
    is_package = (SRC.joinpath(*parts[1:]) / "__init__.py").is_file()
    return parts[1] if len(parts) > 2 or (len(parts) == 2 and is_package) else None


def _cross_folder_imports(graph: dict[str, set[str]]) -> set[tuple[str, str]]:
    """(importer, imported) module pairs in different folders, from any import (top level,
    inside functions, under TYPE_CHECKING)."""
    return {(module, target) for module, targets in graph.items() for target in targets
            if _folder(module) and _folder(target) and _folder(module) != _folder(target)}


def _two_way_pairs(imports: set[tuple[str, str]]) -> set[frozenset[str]]:
    arrows = {(_folder(a), _folder(b)) for a, b in imports}
    return {frozenset(arrow) for arrow in arrows if arrow[::-1] in arrows}


def _back_up(imports: set[tuple[str, str]]) -> set[tuple[str, str]]:
    """Imports from a folder to one on a higher floor."""
    floor = {name: n for n, (name, _) in enumerate(FLOORS)}
    return {(a, b) for a, b in imports if floor[_folder(a) or ""] < floor[_folder(b) or ""]}


def test_every_folder_stands_on_one_floor():
    folders = sorted(path.parent.name for path in SRC.glob("*/__init__.py"))
    names = [name for name, _ in FLOORS]
    assert sorted(names) == folders and len(set(names)) == len(names)


def test_the_ground_under_the_floors_imports_no_folder():
    graph = _full_module_graph()
    assert {module: sorted(target for target in graph[module] if _folder(target))
            for module in GROUND} == dict.fromkeys(GROUND, [])


def test_no_two_folders_import_each_other():
    """pds4 <-> validate, pds4 <-> products, formats <-> geo, geo <-> missions once did (issue 42)."""
    imports = _cross_folder_imports(_full_module_graph())
    assert _two_way_pairs({("pdsgen.geo.x", "pdsgen.formats.y"), ("pdsgen.formats.z", "pdsgen.geo.x")}) \
        == {frozenset({"formats", "geo"})}  # the check sees a pair through different modules
    assert _two_way_pairs(imports) == set(TWO_WAY_ALLOWED)  # each pending pair still there, none new


def test_imports_run_down_the_floors_but_one():
    imports = _cross_folder_imports(_full_module_graph())
    upward = _back_up(imports)
    assert len(BACK_UP) <= 1 and set(BACK_UP) <= upward  # the excused import is still made
    outside_pending = {(a, b) for a, b in upward if frozenset({_folder(a), _folder(b)}) not in TWO_WAY_ALLOWED}
    assert outside_pending - set(BACK_UP) == set()


# -- geometry: geo/ owns both directions and the facts they rest on (issue 34 item 2) ------------

# The validator's own formulas, independent of geo/ on purpose (a check must not share the
# computation it checks); each entry must still hold what it is excused for (so the list
# cannot outlive the code).
VALIDATOR_OWN_OFFSET_INVERSE = {"validate/map_offsets.py", "validate/families/geo_rules.py",
                                "validate/families/hrsc_rules.py"}
VALIDATOR_OWN_LONGITUDE_WRAP = {"validate/projection.py", "validate/map_offsets.py",
                                "validate/families/geo_rules.py", "validate/pds4/cart_checks.py"}
VALIDATOR_OWN_WEST_FLIP = {"validate/map_offsets.py", "validate/families/geo_rules.py"}
_OFFSET_NAMES = ("offset", "spo", "lpo")


def _source_modules():
    """(path relative to pdsgen/, parsed module) of every module outside geo/."""
    for path in sorted(SRC.rglob("*.py")):
        relative = path.relative_to(SRC).as_posix()
        if not relative.startswith("geo/"):
            yield relative, ast.parse(path.read_text())


def _names(node: ast.AST) -> set[str]:
    return {n.id.lower() for n in ast.walk(node) if isinstance(n, ast.Name)} | \
        {n.attr.lower() for n in ast.walk(node) if isinstance(n, ast.Attribute)}


def _is_half_pixel(node: ast.AST) -> bool:
    return (isinstance(node, ast.Constant) and node.value == 0.5) or \
        (isinstance(node, ast.Name) and node.id == "PIXEL_CENTRE")


def _offset_inverses(tree: ast.AST) -> list[int]:
    """Lines adding or taking half a pixel to or from a projection offset (the PDS3 convention's
    corner <-> offset arithmetic, geo/conventions.py's)."""
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Add, ast.Sub)):
            for half, other in ((node.left, node.right), (node.right, node.left)):
                if _is_half_pixel(half) and any(key in name for name in _names(other) for key in _OFFSET_NAMES):
                    found.append(node.lineno)
    return found


def _is_number(node: ast.AST, values: tuple[float, ...]) -> bool:
    return isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) \
        and not isinstance(node.value, bool) and node.value in values


def _is_full_turn(node: ast.AST) -> bool:
    return _is_number(node, (360,)) or (isinstance(node, ast.Name) and node.id == "FULL_TURN")


def _longitude_wraps(tree: ast.AST) -> list[int]:
    """Lines taking an angle modulo a full turn (geo/conventions.py's wrap_360 / wrap_180)."""
    return [node.lineno for node in ast.walk(tree)
            if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Mod) and _is_full_turn(node.right)]


def _west_flips(tree: ast.AST) -> list[int]:
    """Lines comparing with "WEST" (a label's POSITIVE_LONGITUDE_DIRECTION: geo/conventions.py)."""
    return [node.lineno for node in ast.walk(tree) if isinstance(node, ast.Compare)
            and any(isinstance(side, ast.Constant) and side.value == "WEST" for side in [node.left, *node.comparators])]


def test_the_offset_inverse_lives_in_geo():
    found = {relative: lines for relative, tree in _source_modules() if (lines := _offset_inverses(tree))}
    assert set(found) - VALIDATOR_OWN_OFFSET_INVERSE == set(), found
    assert VALIDATOR_OWN_OFFSET_INVERSE <= set(found)  # the detector sees the validator's own copies


def test_longitude_wraps_and_the_west_flip_live_in_geo():
    wraps = {relative: lines for relative, tree in _source_modules() if (lines := _longitude_wraps(tree))}
    assert set(wraps) - VALIDATOR_OWN_LONGITUDE_WRAP == set(), wraps
    assert VALIDATOR_OWN_LONGITUDE_WRAP <= set(wraps)
    flips = {relative: lines for relative, tree in _source_modules() if (lines := _west_flips(tree))}
    assert set(flips) - VALIDATOR_OWN_WEST_FLIP == set(), flips
    assert VALIDATOR_OWN_WEST_FLIP <= set(flips)


def test_utm_constants_live_in_geo_utm():
    """0.9996, 500 km, 10,000 km and the 6-degree zone arithmetic: geo/utm.py alone."""
    offenders = []
    for path in sorted(SRC.rglob("*.py")):
        relative = path.relative_to(SRC).as_posix()
        if relative == "geo/utm.py":
            continue
        tree = ast.parse(path.read_text())
        offenders += [(relative, value) for value in _module_constants(tree)
                      if isinstance(value, (int, float)) and not isinstance(value, bool)
                      and value in (0.9996, 500000, 10000000)]
        offenders += [(relative, node.lineno) for node in ast.walk(tree) if isinstance(node, ast.BinOp)
                      and isinstance(node.op, ast.Mod) and _is_number(node.right, (6,))]
    assert offenders == []


def test_the_folded_transverse_mercator_note_has_one_wording():
    """The label template renders geo/transverse_mercator.py's note, which the label reader parses;
    no template or other module spells the grid statement itself."""
    from pdsgen.geo.label_georef import transverse_mercator_grid
    from pdsgen.geo.transverse_mercator import TransverseMercatorGrid, grid_note
    from pdsgen.resources import templates_dir

    for template in sorted(Path(templates_dir()).rglob("*.j2")):
        text = template.read_text()
        while "{#" in text:  # template comments may name the note; its wording may not be there
            start = text.index("{#")
            text = text[:start] + text[text.index("#}", start) + 2:]
        assert "scale factor" not in text and "false easting" not in text, template.name
    for relative, tree in _source_modules():
        strings = [v for v in _module_constants(tree) if isinstance(v, str)]
        assert not any("false northing" in s for s in strings), relative
    note = "\r\n".join(grid_note(0.9996, 500000.0, 10000000.0))
    assert transverse_mercator_grid(note) == TransverseMercatorGrid(0.9996, 500000.0, 10000000.0)


# -- one home each (issue 34): the label reader's END rule, file checksums, the file beside a label --

# The label reader, label/parser.py, reads END as a token and holds the END rule (a pattern on
# bytes) every reader of a label file stops at. Nowhere else may a pattern look for a label's END.
LABEL_READER = {"label/parser.py"}
_END_PATTERN = re.compile(r"(?:\\n|\\r|\n|\r|\^|\*|\\s|\])[ \t]*END(?![A-Za-z_])"
                          r"|(?<![A-Za-z_])END(?:\\r|\\n|\r|\n|\[|\\s|\$|\\b)")
_SEARCHES = {"compile", "search", "match", "fullmatch", "finditer", "findall", "index", "rindex", "find",
             "rfind", "split", "rsplit", "partition", "rpartition", "count", "startswith", "endswith"}


def _texts_searched_for(tree: ast.AST) -> list[tuple[int, str]]:
    """String and bytes literals a module looks for: patterns compiled or searched with, texts
    found, split on or tested with `in`."""
    found: list[ast.expr] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and isinstance(node.func, (ast.Attribute, ast.Name)):
            name = node.func.attr if isinstance(node.func, ast.Attribute) else node.func.id
            if name in _SEARCHES:
                found += node.args
        elif isinstance(node, ast.Compare) and any(isinstance(op, (ast.In, ast.NotIn)) for op in node.ops):
            found.append(node.left)
    texts = []
    for expr in found:
        for node in ast.walk(expr):
            if isinstance(node, ast.Constant) and isinstance(node.value, (str, bytes)):
                value = node.value.decode("latin-1") if isinstance(node.value, bytes) else node.value
                texts.append((node.lineno, value))
    return texts


def test_one_end_rule_in_the_label_reader():
    """Four END patterns once disagreed on `END;` and a trailing comment (issue 34)."""
    offenders = []
    for path in sorted(SRC.rglob("*.py")):
        relative = path.relative_to(SRC).as_posix()
        if relative in LABEL_READER:
            continue
        for line, text in _texts_searched_for(ast.parse(path.read_text())):
            if _END_PATTERN.search(text):
                offenders.append(f"{relative}:{line}")
    assert offenders == []
    old_patterns = ('_END = re.compile(rb"(?:^|\\n)[ \\t]*END[ \\t]*\\r?(?:\\n|$)")\n'
                    'end = text.index("\\r\\nEND\\r\\n")\n')
    assert [line for line, _ in _texts_searched_for(ast.parse(old_patterns))] == [1, 2]
    assert not _END_PATTERN.search("END_OBJECT") and not _END_PATTERN.search("ENDING_LONGITUDE")


# review/page.py hashes inline script text for the page's Content-Security-Policy: not a file checksum.
CHECKSUM_HOME = "formats/checksum.py"
HASHLIB_ELSEWHERE = {"review/page.py"}


def _hashing(tree: ast.AST) -> list[int]:
    """Lines where a module imports hashlib or calls one of its digests."""
    lines = []
    for node in ast.walk(tree):
        imported = ([alias.name for alias in node.names] if isinstance(node, ast.Import)
                    else [node.module or ""] if isinstance(node, ast.ImportFrom) else [])
        if "hashlib" in imported or (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name)
                                     and node.value.id == "hashlib"):
            lines.append(node.lineno)
    return lines


def test_file_checksums_have_one_home():
    """MD5 was computed in six places (issue 34); formats/checksum.py streams every file digest."""
    offenders = [f"{path.relative_to(SRC).as_posix()}:{line}" for path in sorted(SRC.rglob("*.py"))
                 if path.relative_to(SRC).as_posix() not in {CHECKSUM_HOME, *HASHLIB_ELSEWHERE}
                 for line in _hashing(ast.parse(path.read_text()))]
    assert offenders == []
    assert _hashing(ast.parse("import hashlib\ndigest = hashlib.md5(data).hexdigest()")) == [1, 2]


# label/beside.py lists a directory once while it is unchanged and tells an exact name from a
# name differing only in case. No other module lists a directory to match names ignoring case.
BESIDE_HOME = "label/beside.py"
_LISTINGS = {"iterdir", "listdir", "scandir", "glob", "rglob"}
_FOLDS = {"lower", "upper", "casefold"}


def _case_folding_lookups(tree: ast.AST) -> list[int]:
    """Lines where a function that lists a directory compares names ignoring case, or where the
    listing's own folded index is built or asked."""
    lines = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and isinstance(node.func, (ast.Name, ast.Attribute)):
            name = node.func.attr if isinstance(node.func, ast.Attribute) else node.func.id
            if name in ("DirectoryNames", "same_but_case"):
                lines.append(node.lineno)
    for function in ast.walk(tree):
        if not isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef)):
            continue
        calls = {node.func.attr for node in ast.walk(function)
                 if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)}
        if not calls & _LISTINGS:
            continue
        lines += [node.lineno for node in ast.walk(function) if isinstance(node, ast.Compare) and any(
            isinstance(side, ast.Call) and isinstance(side.func, ast.Attribute) and side.func.attr in _FOLDS
            for side in (node.left, *node.comparators))]
    return lines


def test_one_case_aware_look_up_of_a_file_beside_a_label():
    """Three look-ups once differed (issue 34); label/beside.py keeps the per-run cached listing."""
    offenders = [f"{path.relative_to(SRC).as_posix()}:{line}" for path in sorted(SRC.rglob("*.py"))
                 if path.relative_to(SRC).as_posix() != BESIDE_HOME
                 for line in _case_folding_lookups(ast.parse(path.read_text()))]
    assert offenders == []
    old_extras_look_up = ("def sibling(label, name):\n"
                          "    for candidate in label.parent.iterdir():\n"
                          "        if candidate.name.lower() == name.lower():\n"
                          "            return candidate\n")
    assert _case_folding_lookups(ast.parse(old_extras_look_up)) == [3]


def test_the_validator_reads_labels_with_the_label_reader():
    """The parser is not in a lexer module, and validate/ has no reader of its own."""
    assert not (VALIDATE / "lexer.py").exists()
    from pdsgen.label import parser, tree
    from pdsgen.validate import context

    assert context.parse_label is parser.parse_label and context.Block is tree.Block
    assert not list((SRC / "label").glob("lexer.py"))


# -- Ctrl-C: the pools that stream a product wait for every thread they started ------------------


def test_product_streaming_pools_are_interrupt_safe():
    """formats/ and products/ start their worker threads through InterruptSafeExecutor: a plain
    ThreadPoolExecutor interrupted while a thread starts does not wait for that thread, which then
    reads a dataset the interrupted command has closed (pdsgen dtm killed by SIGSEGV)."""
    found = []
    for folder in ("formats", "products"):
        for path in sorted((SRC / folder).glob("*.py")):
            for node in ast.walk(ast.parse(path.read_text())):
                if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) \
                        and node.func.id == "ThreadPoolExecutor":
                    found.append(f"{folder}/{path.name}:{node.lineno}")
    assert found == []
