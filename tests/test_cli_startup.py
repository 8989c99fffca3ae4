"""Start-up cost: listing, completing and converting load only what they use."""

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
    assert "pdsgen.validate.runner" in loaded  # the label was checked
    assert not {"pvl", "pdsgen.pds4.validate", "pdsgen.pds4.schematron"} & set(loaded)


def test_numpy_blas_threads_default_to_one_and_a_users_setting_wins():
    """pdsgen does no linear algebra; OpenBLAS's spinning threads would take CPU from the encoders."""
    code = "import os, pdsgen.cli; print(os.environ['OPENBLAS_NUM_THREADS'])"
    env = {k: v for k, v in os.environ.items() if k != "OPENBLAS_NUM_THREADS"}
    unset = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, check=True)
    chosen = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                            env={**env, "OPENBLAS_NUM_THREADS": "4"})
    assert (unset.stdout.strip(), chosen.stdout.strip()) == ("1", "4")
