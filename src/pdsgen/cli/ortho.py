"""`pdsgen ortho`: an orthoimage to a lossless JPEG 2000 with a detached PDS3 label."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import click

from ..errors import PdsgenError
from ..formats.jp2 import JP2INFO_NAME
from ..pds4.model import LABEL_DIALECTS
from ..products.ortho import write_ortho
from ..products.result import ProductResult
from ..profiles import profile_names
from ..storage import internal, output_area
from . import COMMANDS
from ._output import Outcome, output_options, product_summary
from ._profile_options import label_fidelity_options, profile_options, refuse_unused_options

_COMMON = {"input_path", "outdir", "product_id", "value_range", "params_file", "product_version", "overwrite"}
USED_BY_PROFILE = {
    "generic": _COMMON | {"allow_deviations", "bits", "observation_id", "source_dtm_id", "sequence", "gmljp2", "label"},
    "hirise": _COMMON | {"allow_deviations", "bits", "observation_id", "source_dtm_id", "sequence", "gmljp2", "label"},
    "hrsc": _COMMON | {"allow_deviations", "source_labels", "offset_convention", "bits", "source_ids", "reproject",
                       "label"},
    "imars": _COMMON | {"bits", "source_ids"},
    "hrsc-ax": _COMMON | {"allow_deviations", "source_labels", "vicar_offsets", "gmljp2", "label"},
}
# Profiles whose products may be composed of several single-band input files.
SEVERAL_INPUTS = {"hrsc-ax"}

# Files one orthoimage updates for its whole directory: fetched from, and written back to, an s3:// OUTDIR.
SHARED_FILES = (JP2INFO_NAME,)


@click.command(short_help=COMMANDS["ortho"])
@output_options
@click.argument("input_path", metavar="INPUT", type=click.Path(dir_okay=False))
@click.argument("more_inputs", metavar="[INPUT]...", nargs=-1, type=click.Path(dir_okay=False))
@click.option("-o", "--outdir", required=True, type=click.Path(file_okay=False), help="Output directory.")
@click.option("--profile", type=click.Choice(profile_names()),
              default="generic", show_default=True, help="Mission profile: names and keywords.")
@click.option("--product-id", help="Product ID (default: built by the profile).")
@click.option("--bits", type=click.Choice(["8", "10", "16"]),
              help="DN bits (default: 8 for byte input, 16 for wider; floats 10 (hirise) or 16).")
@click.option("--range", "value_range", type=float, nargs=2, metavar="MIN MAX",
              help="Input values mapped onto the valid DNs; outside become saturation DNs "
                   "(default: integer DNs kept if they fit, else the data's min and max).")
@click.option("--observation-id", help="Source observation, e.g. ESP_042252_1930 (hirise product ID).")
@click.option("--source-dtm-id", help="Product ID of the DTM the image was orthorectified on.")
@click.option("--sequence", type=int, default=1, show_default=True,
              help="Sequence number NN of HiRISE ortho IDs.")
@click.option("--params", "params_file", type=click.Path(dir_okay=False),
              help="PVL or TOML file of producer/data-set keywords (see schemas/params.toml).")
@click.option("--version", "product_version", default="1.0", show_default=True, help="PRODUCT_VERSION_ID.")
@click.option("--gmljp2", is_flag=True, help="Also write a GMLJP2 box (the GeoJP2 box is always written).")
@click.option("--source-product-id", "source_ids", multiple=True,
              help="hrsc/imars: source product (e.g. H1234_0000_ND3) giving orbit and sequence.")
@click.option("--reproject", is_flag=True, help="hrsc: warp the input into the HRSC projection and sphere.")
@label_fidelity_options
@click.option("--label", type=click.Choice(LABEL_DIALECTS), default="pds3", show_default=True,
              help="pds3 (.JP2 + .LBL), pds4 (.JP2 + uncompressed .img + .xml) or both; "
                   "hrsc: pds3 or both (the nd4 .img + a PDS4 .xml describing it).")
@click.option("--overwrite", is_flag=True, help="Replace an existing product.")
@click.pass_context
def ortho(ctx, input_path, more_inputs, outdir, profile, product_id, bits, value_range, observation_id, source_dtm_id,
          sequence, params_file, product_version, gmljp2, source_ids, reproject, source_labels,
          offset_convention, vicar_offsets, allow_deviations, label, overwrite) -> Outcome:
    """Convert the 1-band (RED) or 3-band (IRB) orthoimage INPUT (any GDAL format,
    projected CRS as for DTMs) into OUTDIR/<PRODUCT_ID>.JP2 and .LBL (--label pds4: .JP2,
    .img and .xml); for --profile
    hrsc the 8-bit nadir image hOOOO_NNNN_nd4.img (attached label, DN 0 = no data);
    for --profile imars hOOOO_NNNN_nd4_ucl.tif with its .pvl and footprint; for --profile
    hrsc-ax TILE.pan, or the channel files of one colour product in band order
    (TILE.re TILE.gr TILE.bl, TILE.cir_re TILE.cir_gr TILE.cir_bl)."""
    refuse_unused_options(ctx, profile, USED_BY_PROFILE.get(profile, USED_BY_PROFILE["generic"]))
    with output_area(outdir, overwrite, shared=SHARED_FILES) as area:  # s3:// OUTDIR: uploaded when complete
        product = write_ortho(ortho_inputs(ctx.params), area.directory, profile=profile, **library_options(ctx.params))
        lines, summary = area.shown([_summary(product)]), area.shown(product_summary("ortho", product))
    return Outcome(lines, summary, product.warnings)


def ortho_inputs(params: Mapping[str, Any]) -> str | tuple[str, ...]:
    """The input of write_ortho: one file, or (profiles that compose bands) the files in band order."""
    more = tuple(params.get("more_inputs") or ())
    if not more:
        return internal(params["input_path"])
    if params["profile"] not in SEVERAL_INPUTS:
        raise PdsgenError(None, f"--profile {params['profile']} takes one INPUT; "
                                f"{len(more) + 1} were given")
    return (internal(params["input_path"]), *(internal(path) for path in more))


def library_options(params: Mapping[str, Any]) -> dict[str, object]:
    """write_ortho's keywords from the command's parsed parameters: those the profile uses.

    `pdsgen batch` calls it too, so a manifest's job and the command make the same call.
    """
    bits, value_range = params["bits"], params["value_range"]
    given = {
        "product_id": params["product_id"], "bits": int(bits) if bits else None,
        "value_range": tuple(value_range) if value_range else None, "observation_id": params["observation_id"],
        "source_dtm_id": params["source_dtm_id"], "sequence": params["sequence"], "params": params["params_file"],
        "gmljp2": params["gmljp2"], "version": params["product_version"], "overwrite": params["overwrite"],
        "source_product_ids": tuple(params["source_ids"]), "reproject_input": params["reproject"],
        "label": params["label"], "allow_dictionary_deviations": params["allow_deviations"] or None,
        "source_labels": tuple(params["source_labels"]), "offset_convention": params["offset_convention"],
        "vicar_offsets": params["vicar_offsets"],
    }
    return profile_options(given, USED_BY_PROFILE.get(params["profile"], USED_BY_PROFILE["generic"]))


def _summary(product: ProductResult) -> str:
    """The one line `pdsgen ortho` prints: the product's own, in the form its profile made."""
    return product.summary_line
