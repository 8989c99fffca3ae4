"""`pdsgen --version` names the data dictionary the validator checks against, without
loading the validator to say so."""

from __future__ import annotations

import json
import subprocess
import sys

from pdsgen import __version__
from pdsgen.validate import validate_paths
from pdsgen.validate.dictionary import version as validator_dictionary_version

from helpers import run_cli


def test_version_states_pdsgen_and_the_validators_dictionary(tmp_path):
    result = run_cli("--version")
    assert result.returncode == 0, result.stderr
    first, second = result.stdout.splitlines()
    assert first == f"pdsgen, version {__version__}"
    dictionary = validator_dictionary_version()
    assert second == f"PDS3 data dictionary (PSDD): {dictionary}"
    assert dictionary.startswith("pdscat1r102 (generated 2017-")  # the PSDD shipped (issue 9)
    # the same text a validation report states
    label = tmp_path / "X.LBL"
    label.write_text("PDS_VERSION_ID = PDS3\r\nRECORD_TYPE = UNDEFINED\r\nEND\r\n")
    assert validate_paths([label]).dictionary == dictionary
    report = run_cli("validate", "--no-config", "--format", "json", str(label))
    assert json.loads(report.stdout)["summary"]["dictionary"] == dictionary


def test_version_does_not_load_the_validator():
    code = ("import sys\nfrom click.testing import CliRunner\nfrom pdsgen.cli import main\n"
            "out = CliRunner().invoke(main, ['--version']).output\n"
            "print('pdscat1r102' in out, any(m.startswith('pdsgen.validate') for m in sys.modules))")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert result.stdout.split() == ["True", "False"], result.stderr


def test_the_dictionary_date_is_read_only_when_it_is_a_date():
    from pdsgen.label.data_dictionary import version_text

    assert version_text({"version": "v1", "generated": "Mon Sep 25 14:04:29 2017"}) == "v1 (generated 2017-09-25)"
    assert version_text({"version": "v1", "generated": "Fri Feb 29 00:00:00 2008"}) == "v1 (generated 2008-02-29)"
    for stamp in ("Mon Sep 99 14:04:29 2017", "Mon Sep 0 14:04:29 2017", "Mon Foo 25 14:04:29 2017", "2017-09-25"):
        assert version_text({"version": "v1", "generated": stamp}) == f"v1 (generated {stamp})"
