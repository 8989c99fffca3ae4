"""`pdsgen params`: a params file to fill in, naming every keyword a profile's
products carry from one, with what the profile writes when it is not given.

Why: a product made without a params file says "UNK" for whoever made it, the data set and the
instrument; the keywords and their meaning are listed in schemas/params.toml, but a user should
not have to read a schema to write the file. Every line of the template is a comment, so the
file loads as it is (changing nothing) and each keyword takes effect once uncommented.
"""

from __future__ import annotations

from pathlib import Path

import click

from ..missions import get_mission
from ..params import params_schema
from . import COMMANDS
from ._profile_options import ProfileChoice

# What a params file may override but the profile writes itself (the DTM's NOTE: what its
# pixel values mean); not listed, so a template filled in line by line never replaces it.
_NOT_IDENTIFICATION = frozenset({"DTM_NOTE"})
# Keywords pdsgen fills itself when no params file does, whatever the profile.
_WRITTEN_BY_PDSGEN = {"SOFTWARE_NAME": "pdsgen and its version", "PRODUCT_VERSION_ID": "--version (1.0)",
                      "TARGET_NAME": "the body the input's CRS names, else MARS",
                      "SOURCE_PRODUCT_ID": "--source-product-id (and --observation-id, --source-dtm-id), else N/A"}
# The kinds of product a keyword's `used_by` names that a profile's dtm and ortho commands make.
_PRODUCT_USES = ("dtm", "ortho", "readme", "extras")


def params_template(profile: str) -> str:
    """The commented TOML template of `profile` (an unknown profile: the missions' PdsgenError)."""
    mission = get_mission(profile)
    dtm = dict(mission.dtm_keywords)
    ortho = dict(mission.ortho_keywords or {})
    lines = [f"# Params file for the {profile} profile: give it to pdsgen dtm, ortho and extras as --params FILE.",
             "# Uncomment each keyword you state. A keyword left out keeps the value shown as the",
             '# profile\'s ("UNK" means not stated: pdsgen validate warns about it, and --strict fails).',
             "# Keywords and their checks: schemas/params.toml.", ""]
    for keyword, entry in params_schema().items():
        uses = [use for use in entry.get("used_by", ()) if use in _PRODUCT_USES]
        if not uses or entry["kind"] in ("table", "flag") or keyword in _NOT_IDENTIFICATION:
            continue
        lines.append(f"# {keyword}: {entry['description']} ({', '.join(uses)})")
        lines += _profile_values(keyword, dtm, ortho)
        lines.append(f"# {keyword} = {_example(keyword, entry['kind'], dtm.get(keyword) or ortho.get(keyword))}")
        lines.append("")
    return "\n".join(lines)


def _profile_values(keyword: str, dtm: dict[str, str], ortho: dict[str, str]) -> list[str]:
    """What the profile writes without the keyword, for its DTMs and orthoimages where they differ."""
    in_dtm, in_ortho = dtm.get(keyword), ortho.get(keyword)
    if in_dtm is None and in_ortho is None:
        written = _WRITTEN_BY_PDSGEN.get(keyword)
        return [f"#   pdsgen writes: {written}"] if written else []
    if in_ortho is None or in_dtm == in_ortho or in_dtm is None:
        return [f"#   the profile's: {in_dtm or in_ortho}"]
    return [f"#   the profile's: {in_dtm} (DTMs), {in_ortho} (orthoimages: a params file of their own)"]


def _example(keyword: str, kind: str, value: str | None) -> str:
    if kind == "list":
        return '["SOURCE_PRODUCT_1", "SOURCE_PRODUCT_2"]'
    if kind == "version":
        return f'"{value or "1.0"}"'
    if value and value.upper() != "UNK":
        return f'"{value}"'
    return '"..."'


@click.command(short_help=COMMANDS["params"])
@click.option("--template", "profile", required=True, type=ProfileChoice(),
              help="The profile whose keywords to list.")
@click.option("-o", "--output", "output", type=click.Path(dir_okay=False),
              help="Write the template to this file (refused if it exists) instead of printing it.")
def params(profile: str, output: str | None) -> None:
    """Print (or write) a commented params TOML template for PROFILE: every identification keyword
    its products carry, with the value the profile writes when the keyword is not given."""
    from ..errors import OutputError
    from ..storage.staging import staged_file

    text = params_template(profile)
    if output is None:
        click.echo(text, nl=False)
        return
    target = Path(output)
    if target.exists():
        raise OutputError(target, "exists; give a new file name (a params file is not overwritten)")
    if not target.parent.is_dir():
        raise OutputError(target, "its directory does not exist")
    with staged_file(target) as staged:
        staged.write_text(text, encoding="ascii")
    click.echo(f"PARAMS   {target} ({profile} profile): uncomment and fill in, then give it as --params {target}")
