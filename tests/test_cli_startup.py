"""Start-up cost: listing, completing and converting load only what they use.

Each command path has an import budget, measured with `python -X importtime` on the
real command: the number of modules it imports (pdsgen's own and all) and modules it
must not import. Module counts, unlike times on a shared machine, are the same on
every run, and each module is start-up time; a change that makes a path import more
fails here and must raise the budget on purpose.
"""

from __future__ import annotations

import ast
import os
import subprocess
import sys

import click

from pdsgen.cli import COMMANDS, main

_LOADED = ("import sys; from pdsgen.cli import main; {action}; "
           "print(sorted(m for m in sys.modules if m.startswith('pdsgen.') or m in ('jinja2', 'pvl')))")


def _loaded_after(action: str, env: dict[str, str] | None = None) -> list[str]:
    result = subprocess.run([sys.executable, "-c", _LOADED.format(action=action)], capture_output=True,
                            text=True, env={**os.environ, **(env or {})}, check=True)
    return ast.literal_eval(result.stdout.strip().splitlines()[-1])  # the printed list of module names


def test_help_and_completion_import_no_command_module():
    command_modules = {f"pdsgen.cli.{name}" for name in COMMANDS}
    listed = _loaded_after("main.get_help(click.Context(main))".replace("click.", "__import__('click')."))
    assert not command_modules & set(listed)
    completed = _loaded_after(
        "from click.shell_completion import ShellComplete; "
        "print([i.value for i in ShellComplete(main, {}, 'pdsgen', '_PDSGEN_COMPLETE').get_completions([], '')])"
    )
    assert not command_modules & set(completed)


def test_the_listed_help_is_each_commands_own():
    context = click.Context(main)
    for name, text in COMMANDS.items():
        command = main.get_command(context, name)
        assert command is not None and command.name == name
        assert command.get_short_help_str(200) == text
    listing = main.get_help(context)
    assert all(f"  {name}" in listing and text in listing for name, text in COMMANDS.items())


def test_a_jp2_conversion_does_not_load_other_missions_or_pds4():
    """`pdsgen ortho` (generic/HiRISE) starts encoding without the HRSC/iMars writers, PDS4, jinja2 or pvl."""
    loaded = _loaded_after("import pdsgen.cli.ortho")
    assert not {"pdsgen.products.hrsc", "pdsgen.products.imars", "pdsgen.pds4.products", "jinja2", "pvl"} & set(loaded)


def test_an_orthoimage_is_checked_without_the_pvl_reader_or_the_pds4_validator(tmp_path):
    """The writer's label check runs the PDS3 rules only: iMars (pvl) and PDS4 (lxml) code stays unloaded."""
    import numpy as np

    from helpers import ORIGINS, write_raster

    crs, transform = ORIGINS["equirectangular"]
    source = write_raster(tmp_path / "in.tif", np.arange(64 * 48, dtype=np.uint8).reshape(64, 48), crs, transform)
    script = tmp_path / "convert.py"
    script.write_text(
        "import sys\nfrom pdsgen.cli import main\n"
        f"try:\n    main(['ortho', {str(source)!r}, '-o', {str(tmp_path / 'out')!r}, '-q'])\n"
        "except SystemExit:\n    pass\n"
        "print(sorted(sys.modules))\n"
    )
    result = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, check=True)
    loaded = ast.literal_eval(result.stdout.strip().splitlines()[-1])
    assert [p.name for p in sorted((tmp_path / "out").iterdir())] == ["IN.JP2", "IN.LBL", "JP2INFO.TXT"]
    assert "pdsgen.validate.families.dict_rules" in loaded  # the label was checked
    assert not {"pvl", "pdsgen.validate.pds4.label_checks", "pdsgen.validate.pds4.schematron"} & set(loaded)


def test_numpy_blas_threads_default_to_one_and_a_users_setting_wins():
    """pdsgen does no linear algebra; OpenBLAS's spinning threads would take CPU from the encoders."""
    code = ("import os, pdsgen.cli as cli; cli.main = lambda **_: print(os.environ['OPENBLAS_NUM_THREADS']); "
            "cli.run()")  # the command's process sets it (importing pdsgen.cli does not)
    env = {k: v for k, v in os.environ.items() if k != "OPENBLAS_NUM_THREADS"}
    unset = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, check=True)
    chosen = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                            env={**env, "OPENBLAS_NUM_THREADS": "4"})
    assert (unset.stdout.strip(), chosen.stdout.strip()) == ("1", "4")


# command line -> (most pdsgen modules, most modules in all, modules it must not import).
# Measured when set (pdsgen modules / all): --version 6/114, --help 6/121, a 64 x 64
# DTM conversion 47/393, validate of one .IMG 48/381 (Python 3.11, numpy 2, rasterio 1.4).
# The DTM path grew from 52 to 54 on purpose (issue 42): pdsgen.results (the one result
# protocol every command returns) and pdsgen.products.opening (the writers' shared opening steps).
VALIDATOR_BEYOND_DICTIONARY = {"pdsgen.validate.runner", "pdsgen.validate.report", "pdsgen.validate.config",
                               "pdsgen.validate.families.map_rules", "pdsgen.validate.families.geo_rules",
                               "pdsgen.validate.families.image_rules", "pdsgen.validate.families.set_rules"}
LIBRARIES = {"numpy", "rasterio", "glymur", "jinja2", "lxml.etree", "pvl", "distributed"}
BUDGETS = {
    "--version": (8, 135, LIBRARIES | {"pdsgen.validate"}),
    "--help": (8, 140, LIBRARIES | {"pdsgen.validate"}),
    # 55: the DTM, made without a params file, warns that its identification is "UNK" (issue 44),
    # and a warning is written through cli._messages.one_line; 59: pdsgen.encode, the output
    # encoders every label value and printed line passes, and the shipped keyword table and
    # dictionary read by the bounded reader (bounded.py), a label's files looked up by the
    # containment rule (storage/containment.py), issue 48; the input's kind is checked
    # (formats.kind: a DTM of image DNs is refused, issue 52)
    "dtm {dtm} -o {out} -q": (59, 430, {"pdsgen.pds4.products", "lxml.etree", "glymur", "pvl", "distributed"}
                              | VALIDATOR_BEYOND_DICTIONARY),
    # 62: pdsgen.encode, which every report line passes; bounded.py and storage/containment.py (issue 48);
    # the IDN rule family (validate/families/identity_rules.py, issue 49) and the clock its "now" reads
    # (pdsgen/clock.py, issue 53); validate/facts.py, the per-file facts the checks across files join
    # (issue 51: read by the workers of a -j run, by the run itself otherwise); 63: pdsgen.params, whose
    # IDENTIFICATION_KEYWORDS DLV-007 reads of a product left UNK, now checked alone too (issue 49); 64:
    # pdsgen.label.mapping, whose utc_datetime is the one reader of PDS times the IDN rules compare
    "validate {out}/DTM.IMG -q": (64, 430, {"jinja2", "glymur", "pdsgen.products.dtm", "distributed"}),
}


def _imports(args: list[str]) -> dict[str, int]:
    """module -> its cumulative import time in microseconds, for `python -m pdsgen ARGS`."""
    result = subprocess.run([sys.executable, "-X", "importtime", "-m", "pdsgen", *args], capture_output=True,
                            text=True, env={k: v for k, v in os.environ.items() if k != "PYTHONPATH"})
    assert result.returncode == 0, result.stderr[-2000:]
    imported = {}
    for line in result.stderr.splitlines():
        if line.startswith("import time:") and "|" in line and not line.endswith("imported package"):
            _, cumulative, name = (part.strip() for part in line.split("|"))
            imported[name] = int(cumulative)
    return imported


def test_each_command_stays_within_its_import_budget(tmp_path):
    import numpy as np

    from helpers import ORIGINS, elevation_array, write_raster

    crs, transform = ORIGINS["equirectangular"]
    write_raster(tmp_path / "dtm.tif", elevation_array(64, 64, seed=3).astype(np.float32), crs, transform)
    for command, (own_budget, all_budget, forbidden) in BUDGETS.items():
        imported = _imports(command.format(dtm=tmp_path / "dtm.tif", out=tmp_path / "out").split())
        own = [m for m in imported if m == "pdsgen" or m.startswith("pdsgen.")]
        slowest = ", ".join(f"{m} {t / 1000:.0f} ms" for m, t in sorted(imported.items(), key=lambda i: -i[1])[:6])
        where = f"`pdsgen {command}` (slowest imports: {slowest})"
        assert not forbidden & set(imported), f"{where} imports {sorted(forbidden & set(imported))}"
        assert len(own) <= own_budget, f"{where} imports {len(own)} pdsgen modules, budget {own_budget}"
        assert len(imported) <= all_budget, f"{where} imports {len(imported)} modules, budget {all_budget}"
    assert (tmp_path / "out" / "DTM.IMG").is_file()  # the conversion and the validation ran


def test_the_label_check_of_a_writer_is_the_validators_dictionary_verdict(tmp_path):
    """The writer runs the DICT rules alone; they find what `pdsgen validate --strict` finds."""
    from pdsgen.products.agreement import dictionary_errors
    from pdsgen.validate import validate_file

    label = (tmp_path / "X.LBL")
    label.write_text("PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = UNDEFINED\r\nPRODUCT_ID = \"X\"\r\n"
                     f"PRODUCER_FULL_NAME = \"{'N' * 74}\"\r\nMAP_RESOLUTION = \"abc\"\r\nLINES = -3\r\n"
                     "FOO_BAR = 1\r\nEND\r\n",
                     encoding="ascii")
    report, _ = validate_file(label, labels_only=True, strict=True)
    expected = [(f.rule, f.line, f.message) for f in report.findings
                if f.severity == "error" and f.rule.startswith("DICT-")]
    found = [(rule, hit.line, hit.message) for rule, hit in dictionary_errors(label.read_text(), "X.LBL")]
    assert [rule for rule, _, _ in found] == ["DICT-006", "DICT-002", "DICT-003"] and found == expected
