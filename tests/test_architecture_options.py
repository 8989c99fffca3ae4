"""The option vocabulary's structure (issue 42, options): one declaration per option, checked
once, read by the CLI and by batch alike, batch below cli."""

from __future__ import annotations

import ast
from pathlib import Path

import pdsgen

SRC = Path(pdsgen.__file__).parent

# batch/ imports of cli/ still there, each with the change that removes it: keep_boto3_from_rasterio
# is hidden process state the staging change moves out of cli/__init__.py.
BATCH_TO_CLI_LEFT = {("batch/child.py", "pdsgen.cli.keep_boto3_from_rasterio")}


def _imported_names(path: Path) -> set[str]:
    """Every `module.name` a module imports, at any depth (function-level imports included)."""
    package = ("pdsgen", *path.relative_to(SRC).parent.parts)
    names = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            base = package[: len(package) - node.level + 1] if node.level else ()
            module = ".".join((*base, *(node.module.split(".") if node.module else ())))
            names |= {f"{module}.{alias.name}" for alias in node.names}
        elif isinstance(node, ast.Import):
            names |= {alias.name for alias in node.names}
    return names


def test_batch_imports_nothing_from_cli():
    """cli/ runs batch (`pdsgen batch`); batch's job calls come from the vocabulary (products/options.py,
    mosaic/options.py), never from cli/, so the two folders import each other one way."""
    reaching_up = {(path.relative_to(SRC).as_posix(), name)
                   for path in sorted((SRC / "batch").glob("*.py"))
                   for name in _imported_names(path) if name.startswith("pdsgen.cli")}
    assert ("batch/child.py", "pdsgen.cli.keep_boto3_from_rasterio") in reaching_up or \
        "keep_boto3_from_rasterio" not in (SRC / "cli" / "__init__.py").read_text()  # the walker sees it
    assert reaching_up <= BATCH_TO_CLI_LEFT


# -- -o/--output: one flag name for "where the command writes" -------------------------------------

OUTPUT_COMMANDS = {"dtm": "--outdir", "ortho": "--outdir", "mosaic": "--outdir", "extras": "--outdir",
                   "migrate": "--outdir", "batch": "--outdir", "deliver": "--out", "review": "--out",
                   "validate": None}


def test_every_command_shows_o_as_output_and_still_takes_its_old_spelling():
    import click

    from pdsgen.cli import main

    context = click.Context(main)
    for name, old in OUTPUT_COMMANDS.items():
        command = main.get_command(context, name)
        assert command is not None
        shown = command.get_help(click.Context(command, info_name=name))
        assert "  -o, --output " in shown, name
        assert old is None or f"{old} " not in shown, name
        option = next(p for p in command.params if "-o" in p.opts)
        if old is not None:  # the old spelling sets the same parameter
            parsed = command.make_context(name, [old, "somewhere", *_required_rest(name)], resilient_parsing=True)
            assert parsed.params[option.name] == "somewhere", name


def _required_rest(name: str) -> list[str]:
    """The other words a command needs to parse (its positional arguments)."""
    return {"dtm": ["in.tif"], "ortho": ["in.tif"], "mosaic": ["a.tif"], "extras": ["a.IMG"],
            "migrate": ["a.IMG"], "batch": [], "deliver": ["dir"], "review": ["dir"]}[name]


def test_a_manifest_written_with_the_old_key_still_loads(tmp_path):
    from pdsgen.batch import load_manifest

    (tmp_path / "in.tif").write_bytes(b"")
    for key in ("outdir", "output"):
        (tmp_path / "m.toml").write_text(f'[[dtm]]\ninput = "in.tif"\n{key} = "made"\n', encoding="utf-8")
        manifest = load_manifest(tmp_path / "m.toml", tmp_path / "out")
        assert manifest.jobs[0].params["outdir"] == str(tmp_path / "out" / "made")


# -- Extras: one vocabulary, one call for the CLI and batch ----------------------------------------

def _keyword_calls(path: Path, function: str) -> list[list[str]]:
    """The keywords written out in each call of `function` in a module (** spreads not counted)."""
    return [[k.arg for k in node.keywords if k.arg] for node in ast.walk(ast.parse(path.read_text()))
            if isinstance(node, ast.Call) and getattr(node.func, "id", getattr(node.func, "attr", "")) == function]


def test_the_extras_call_is_made_from_its_vocabulary_in_the_cli_and_in_batch():
    """make_extras's keywords come from extras/options.py's entries, not from a list written per caller."""
    from pdsgen.extras.options import EXTRAS_OPTIONS, library_options

    for caller in ("cli/extras.py", "batch/calls.py"):
        calls = _keyword_calls(SRC / caller, "make_extras")
        assert calls and all(set(keywords) <= {"report"} for keywords in calls), (caller, calls)
    params = {spec.param: spec.param for spec in EXTRAS_OPTIONS} | {"profile": "p"}
    assert set(library_options(params)) == {spec.library_keyword for spec in EXTRAS_OPTIONS} | {"profile"}


# -- one declaration per option: ProductOptions and the message table follow the vocabulary ---------

# Fields whose default is not the command line's, and why: a DTM's vertical datum left unset is its
# kind's (the command line says "sphere", HRSC's own default); a DTM's byte order left unset is lsb
# (the command line leaves it unset, for HRSC's msb to apply).
LIBRARY_OWN_DEFAULTS = {"vertical_datum": None, "byte_order": "lsb"}


def test_product_options_carry_every_vocabulary_entry_with_its_default():
    """ProductOptions states no default the vocabulary states otherwise (a new option's default is
    written once, in its OptionSpec; a field that disagrees fails here)."""
    import dataclasses

    from pdsgen.products.options import DTM_OPTIONS, NOT_GIVEN, ORTHO_OPTIONS, ProductOptions

    fields = {field.name: field.default for field in dataclasses.fields(ProductOptions)}
    for spec in (*DTM_OPTIONS, *ORTHO_OPTIONS):
        assert spec.library_keyword in fields, spec.library_keyword
        default = fields[spec.library_keyword]
        if spec.library_keyword in LIBRARY_OWN_DEFAULTS:
            assert default == LIBRARY_OWN_DEFAULTS[spec.library_keyword]
        elif spec.default not in (NOT_GIVEN, None):
            value = spec.convert(spec.default) if spec.convert else spec.default
            assert default == value, (spec.library_keyword, default, value)


def test_the_message_table_is_the_vocabularies_flags():
    """Each entry's library keyword becomes its own flag in a message on the command line."""
    from pdsgen.cli._messages import LIBRARY_TO_OPTION
    from pdsgen.extras.options import EXTRAS_OPTIONS
    from pdsgen.mosaic.options import MOSAIC_OPTIONS
    from pdsgen.products.options import DTM_OPTIONS, ORTHO_OPTIONS

    for spec in (*DTM_OPTIONS, *ORTHO_OPTIONS, *MOSAIC_OPTIONS, *EXTRAS_OPTIONS):
        assert LIBRARY_TO_OPTION[spec.library_keyword] == f"--{spec.flag}"
    source = (SRC / "cli" / "_messages.py").read_text()
    assert '"--product-id"' not in source and '"--source-label"' not in source  # not written by hand


def test_mission_defaults_name_options_of_the_vocabulary():
    import dataclasses

    from pdsgen.missions import get_mission, mission_names
    from pdsgen.products.options import ProductOptions

    fields = {field.name for field in dataclasses.fields(ProductOptions)}
    for name in mission_names():
        assert set(get_mission(name).options.defaults) <= fields, name


# -- choices: checked once, where ProductOptions is built, in one wording --------------------------

# Checks of choices still written elsewhere, each with why: the mosaic's own keywords (kind, order,
# resampling) and an HRSC-AX tile read for a mosaic reach no ProductOptions.build;
# Dialect.of and make_delivery's dialect are no product command's option.
CHOICE_CHECKS_LEFT = {"products/hrsc_ax.py", "mosaic/plan.py", "mosaic/write.py",
                      "dialect.py", "deliver/build.py"}


def test_choices_are_checked_once_in_one_wording():
    import re

    import pytest

    from pdsgen.errors import ParamsError
    from pdsgen.missions import get_mission, mission_names
    from pdsgen.products.options import DTM_OPTIONS, ORTHO_OPTIONS, ProductOptions, used_options

    checked = set()
    for kind, vocabulary in (("dtm", DTM_OPTIONS), ("ortho", ORTHO_OPTIONS)):
        for name in mission_names():
            mission = get_mission(name)
            for spec in used_options(kind, mission, vocabulary):
                if spec.choices is None:
                    continue
                with pytest.raises(ParamsError, match=rf"^`{spec.library_keyword}` must be one of .*, not 'nonsense'$"):
                    ProductOptions.build(kind, mission, {spec.library_keyword: "nonsense"})
                checked.add(spec.library_keyword)
    assert {"byte_order", "kind", "bits", "offset_convention", "vicar_offsets", "label"} <= checked
    wording = re.compile(r"must be (one of|da \(areoid)")
    elsewhere = {path.relative_to(SRC).as_posix() for path in SRC.rglob("*.py")
                 if wording.search(path.read_text()) and path.name != "options.py"}
    assert elsewhere <= CHOICE_CHECKS_LEFT, elsewhere - CHOICE_CHECKS_LEFT


# -- the product kind: one type ---------------------------------------------------------------------

def test_the_product_kind_is_one_type_that_every_list_of_kinds_agrees_with():
    """dtm/ortho is ProductKind; the lists of kinds still written in extras/ and mosaic/ name the
    same kinds in the same order (until those modules take PRODUCT_KINDS), and the options take it."""
    from pdsgen.extras.options import KIND
    from pdsgen.formats.kind import KINDS as EXTRAS_KINDS
    from pdsgen.missions import PRODUCT_KINDS, ProductKind, get_mission
    from pdsgen.mosaic.options import MOSAIC_OPTIONS
    from pdsgen.mosaic.write import KINDS as MOSAIC_KINDS
    from pdsgen.products.options import ProductOptions

    assert PRODUCT_KINDS == ("dtm", "ortho") == EXTRAS_KINDS == MOSAIC_KINDS
    assert next(spec for spec in MOSAIC_OPTIONS if spec.param == "kind").choices == PRODUCT_KINDS
    assert KIND.choices is not None and KIND.choices[:2] == PRODUCT_KINDS
    for kind in ProductKind:
        assert ProductOptions.build(kind, get_mission("generic"), {}) == ProductOptions.build(
            kind.value, get_mission("generic"), {})
