"""One encoder per output format, and nothing written around it (issue 48).

Each format pdsgen writes has one home that encodes a value for it (or refuses it with
EncodeError); templates write through an output hook (jinja2 finalize) of their format, and no
template output or hand-written PVL statement bypasses it - as far as a static look can tell.
The property-based suite (test_security_encoders_property.py) checks what each home writes."""

from __future__ import annotations

import ast
import importlib
import re
from pathlib import Path

import jinja2
import pytest
from jinja2 import nodes

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "src" / "pdsgen"
TEMPLATES = ROOT / "templates"

# format -> (module, function): the one home of its encoding.
HOMES = {
    "PVL value (PDS3 labels, VOLDESC.CAT, INDEX.LBL)": ("pdsgen.label.values", "format_value"),
    "PVL quoted string": ("pdsgen.label.values", "format_string"),
    "PVL string rule (params, delivery text, iMars .pvl)": ("pdsgen.encode", "check_pvl_string"),
    "PVL keyword (iMars .pvl)": ("pdsgen.encode", "check_pvl_keyword"),
    "PDS3 label template output hook": ("pdsgen.label.render", "_finalize"),
    "XML text (PDS4 labels)": ("pdsgen.encode", "xml_text"),
    "XML attribute": ("pdsgen.encode", "xml_attribute"),
    "PDS4 label template output hook": ("pdsgen.encode", "xml_finalize"),
    "table field (INDEX.TAB)": ("pdsgen.encode", "table_field"),
    "HTML (review page, validate --format html)": ("pdsgen.encode", "html_finalize"),
    "terminal and report text (validate reports, annotations, CLI lines)": ("pdsgen.encode", "shown"),
    "plain ASCII text file (Extras README.TXT)": ("pdsgen.encode", "ascii_text"),
}
# Filters that encode for PVL: the only way a PDS3 label template may write a value.
PVL_FILTERS = {"pds", "symbol", "keyword", "comments"}
# `| safe` where the value is pdsgen's own shipped file, never a value from outside.
SAFE_ALLOWED = {("review/page.html.j2", "style"), ("review/page.html.j2", "script")}
# Modules that write PVL text by hand (not through a template): each quotes through the encoder.
PVL_WRITERS = ("deliver/index.py", "deliver/volume.py")


@pytest.mark.parametrize("what", sorted(HOMES))
def test_each_format_has_its_one_home(what):
    module, function = HOMES[what]
    assert callable(getattr(importlib.import_module(module), function))


def _calls(path: Path) -> list[ast.Call]:
    return [node for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))) if isinstance(node, ast.Call)]


def _callee(call: ast.Call) -> str:
    return ast.unparse(call.func)


def test_every_template_environment_has_its_formats_output_hook():
    """jinja2.Environment(...) and every .overlay(...) that changes escaping name a finalize."""
    found = []
    for path in SRC.rglob("*.py"):
        for call in _calls(path):
            callee = _callee(call)
            keywords = {k.arg for k in call.keywords}
            if callee.endswith("jinja2.Environment") or (callee.endswith(".overlay") and "autoescape" in keywords):
                found.append((path.relative_to(SRC).as_posix(), "finalize" in keywords))
    assert found and all(hook for _, hook in found), found
    assert {name for name, _ in found} >= {"label/render.py", "pds4/label.py", "deliver/bundle.py",
                                           "review/page.py", "extras/readme_txt.py"}


def raw_outputs(name: str, source: str) -> list[str]:
    """The `{{ }}` outputs of a template that bypass its format's encoder: in a PDS3 label template,
    any not ending in a PVL filter; in any template, `| safe` (autoescape and the hook skipped)."""
    tree = jinja2.Environment().parse(source)
    raw = []
    for output in tree.find_all(nodes.Output):
        for expression in output.nodes:
            if isinstance(expression, nodes.TemplateData):
                continue
            text = f"line {expression.lineno}"
            if name.endswith(".lbl.j2") and not (isinstance(expression, nodes.Filter)
                                                  and expression.name in PVL_FILTERS):
                raw.append(f"{text}: a value without | pds")
            for used in [expression, *expression.find_all(nodes.Filter)]:
                if not isinstance(used, nodes.Filter):
                    continue
                if used.name == "safe" and (name, getattr(used.node, "name", "")) not in SAFE_ALLOWED:
                    raw.append(f"{text}: | safe")
            for called in [expression, *expression.find_all(nodes.Call)]:
                if isinstance(called, nodes.Call) and getattr(called.node, "name", "") == "Markup":
                    raw.append(f"{text}: Markup()")
    return raw


def test_the_raw_output_check_finds_a_raw_output():
    assert raw_outputs("x.lbl.j2", "KEY = {{ value }}\nOTHER = {{ value | pds }}\n") \
        == ["line 1: a value without | pds"]
    assert raw_outputs("x.xml.j2", "<a>{{ value | safe }}</a>") == ["line 1: | safe"]
    assert raw_outputs("x.lbl.j2", "{{ ns }}:KEY = 1") == ["line 1: a value without | pds"]


@pytest.mark.parametrize("template", sorted(p.relative_to(TEMPLATES).as_posix() for p in TEMPLATES.rglob("*.j2")))
def test_no_template_writes_a_raw_value(template):
    assert raw_outputs(template, (TEMPLATES / template).read_text(encoding="utf-8")) == []


def _quoted_values(path: Path) -> list[str]:
    """f-strings that put a value between double quotes by hand (`KEY = "{value}"`)."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.JoinedStr):
            parts = node.values
            for before, value, after in zip(parts, parts[1:], parts[2:], strict=False):
                if (isinstance(value, ast.FormattedValue) and isinstance(before, ast.Constant)
                        and isinstance(after, ast.Constant) and str(before.value).endswith('"')
                        and str(after.value).startswith('"')):
                    found.append(f"line {node.lineno}: {ast.unparse(node)}")
    return found


@pytest.mark.parametrize("module", PVL_WRITERS)
def test_hand_written_pvl_quotes_through_the_encoder(module):
    path = SRC / module
    assert _quoted_values(path) == []
    assert "format_string" in {name for call in _calls(path) for name in [_callee(call)]}


def test_the_quoted_value_check_finds_one(tmp_path):
    sample = tmp_path / "sample.py"
    sample.write_text("line = f'VOLUME_ID = \"{volume_id}\"'\n")
    assert len(_quoted_values(sample)) == 1


def test_the_imars_pvl_is_checked_before_pvl_writes_it():
    """pvl.dumps writes a key as given: its one caller checks every keyword and text first."""
    dumps = [(path, call) for path in SRC.rglob("*.py") for call in _calls(path) if _callee(call) == "pvl.dumps"]
    assert [path.relative_to(SRC).as_posix() for path, _ in dumps] == ["products/imars.py"]
    source = (SRC / "products" / "imars.py").read_text(encoding="utf-8")
    body = source[source.index("def imars_pvl_text("):source.index("pvl.dumps(module")]
    assert "_check_pvl(module" in body


# Escaping functions of their own: a character class of controls, or `\x{ord(...)}` written by hand.
_OWN_ESCAPE = re.compile(r"\\\\x\{ord\(|\[\\x00-\\x08|\[\\x00-\\x1f")


def test_no_other_module_escapes_terminal_text_itself():
    own = [path.relative_to(SRC).as_posix() for path in SRC.rglob("*.py")
           if path.name != "encode.py" and _OWN_ESCAPE.search(path.read_text(encoding="utf-8"))]
    assert own == []


def test_report_and_cli_text_leave_through_the_terminal_encoder():
    from pdsgen.cli._messages import one_line
    from pdsgen.validate.report import terminal_safe, xml_safe

    for encoder in (one_line, terminal_safe, xml_safe):
        assert encoder("caf\udce9\u202e\x1b[2J") == "caf\\xe9\\u202e\\x1b[2J"
