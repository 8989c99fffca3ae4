"""The options of `pdsgen extras`, in --help order (the vocabulary's form: products/options.py).

`make_extras` takes each entry's library keyword; the CLI makes its click options from the
entries and a batch manifest's [[extras]] job its call (`library_options`), so the call is
written once for both.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from ..formats.kind import NOMAP
from ..missions import PRODUCT_KINDS
from ..products.options import OptionSpec

# The command's own option between these and --overwrite on --help (its choices are the missions
# registered when the command line is parsed); help texts name options by their entries' flags.
PROFILE_FLAG = "profile"
KIND = OptionSpec("kind", "kind", choices=(*PRODUCT_KINDS, NOMAP),
                  help="Treat every PRODUCT as this kind [default: from the label, metadata or "
                       "values; refused when they do not say]. nomap: PRODUCTs are one HiRISE "
                       "observation's RED and/or IRB NOMAP mosaics (not map-projected).")
RENDERING_OPTIONS: tuple[OptionSpec, ...] = (
    OptionSpec("credit", "credit",
               help=f"Credit line on annotated images [default: params CREDIT, else the --{PROFILE_FLAG}'s, else "
                    "that of the mission the label names, else the label's mission and PRODUCER_INSTITUTION_NAME]."),
    OptionSpec("params_file", "params", keyword="params", file=True,
               help="PVL or TOML file of producer keywords (contact, known artifacts ...)."),
    OptionSpec("browse_width", "browse-width", value_type=int,
               help="Browse width in pixels [default: 1024 for DTMs, 2048 for orthoimages]."),
    OptionSpec("thumb_width", "thumb-width", value_type=int, default=128, show_default=True,
               help="Thumbnail width in pixels."),
    OptionSpec("azimuth", "azimuth", value_type=float, default=315.0, show_default=True,
               help="Light direction for shaded relief, degrees clockwise from image up."),
    OptionSpec("altitude", "altitude", value_type=float, default=45.0, show_default=True,
               help="Light elevation above the horizon for shaded relief, degrees."),
    OptionSpec("exaggeration", "exaggeration", value_type=float,
               help="Vertical exaggeration of the shaded relief [default: 1, raised "
                    "automatically when the relief is too faint at preview scale]."),
    KIND,
    OptionSpec("vertical_datum", "vertical-datum", metavar="TEXT",
               help="What the DTMs' heights are above, as the legends and README.TXT say it (e.g. \"the Mars "
                    "2000 areoid\") [default: what the label's own NOTE or DESCRIPTION says, else \"a "
                    "reference surface the label does not name\"]."),
    OptionSpec("root", "root", file=False, metavar="DIR",
               help="Directory tree the files a product's label names may lie in (a volume's LABEL/ beside "
                    "DATA/), when the label is inside it [default: the label's own directory]."),
    OptionSpec("product_id", "product-id", help=f"With --{KIND.flag} {NOMAP}: the observation ID (e.g. "
                                                "PSP_005000_1000) when the file names carry none."),
)
OVERWRITE_EXTRAS = OptionSpec("overwrite", "overwrite", is_flag=True, help="Replace existing Extras files.")
EXTRAS_OPTIONS: tuple[OptionSpec, ...] = (*RENDERING_OPTIONS, OVERWRITE_EXTRAS)


def library_options(params: Mapping[str, Any]) -> dict[str, Any]:
    """make_extras's keywords from `pdsgen extras`'s parsed parameters (a manifest's [[extras]] job's
    too): each entry's value under its library keyword, and the profile."""
    return {"profile": params["profile"], **{spec.library_keyword: params[spec.param] for spec in EXTRAS_OPTIONS}}
