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
from pdsgen.dtm import DtmProduct, write_dtm
from pdsgen.errors import InputError, OutputError, ParamsError, PdsgenError
from pdsgen.hrsc import HrscDtmProduct, HrscImageProduct
from pdsgen.imars import ImarsProduct
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
from pdsgen.ortho import OrthoProduct, write_ortho
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


def _imports(path: Path, module: str, modules: set[str]) -> set[str]:
    """Modules a module imports at import time (not under TYPE_CHECKING, not inside functions)."""
    tree = ast.parse(path.read_text())
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    names: set[str] = set()
    for node in tree.body:
        if isinstance(node, ast.If):  # `if TYPE_CHECKING:` blocks do not run
            continue
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
