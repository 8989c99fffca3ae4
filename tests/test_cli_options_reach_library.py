"""Every option of `pdsgen dtm` / `pdsgen ortho` reaches the library call for some profile.

An option that --help lists but that no profile's library call receives would be
accepted and silently dropped - the merge of two branches once did exactly that to
`ortho --source-label`, `--offset-convention` and `--allow-dictionary-deviations`.
"""

from __future__ import annotations

import click
import pytest

from pdsgen.cli import dtm as dtm_cli
from pdsgen.cli import ortho as ortho_cli
from pdsgen.cli._profile_options import _CLI_NAMES
from pdsgen.missions import mission_names as profile_names

NOT_LIBRARY_KEYWORDS = {"input_path", "outdir", "profile"}  # positional arguments of the call itself


@pytest.mark.parametrize("module", [dtm_cli, ortho_cli], ids=["dtm", "ortho"])
def test_every_used_option_is_passed_to_the_library(module):
    command: click.Command = getattr(module, module.__name__.rsplit(".", 1)[1])
    names = [param.name for param in command.params if param.name]
    params = {name: ("x",) if getattr(param, "multiple", False) else "1"
              for name, param in zip(names, command.params, strict=True)}
    params["value_range"] = (0.0, 1.0) if "value_range" in params else None
    cli_name = {library: cli for library, cli in _CLI_NAMES.items()}
    for profile in profile_names():
        used = module.USED_BY_PROFILE.get(profile, module.USED_BY_PROFILE["generic"])
        passed = {cli_name.get(keyword, keyword) for keyword in module.library_options({**params, "profile": profile})}
        missing = used - passed - NOT_LIBRARY_KEYWORDS
        assert not missing, f"--profile {profile}: {sorted(missing)} accepted but never passed to the library"
