"""The option vocabulary of the product commands: one entry per option, in --help order.

An entry says everything about one option once: its flag and help, its click parameter
name (also a batch manifest's key), the library keyword it becomes and how its value is
converted, and whether every profile uses it. Which of the other options a profile uses is
the mission's declaration (`Mission.options`). The CLI builds its click options, its table
of flags per profile and its refusal of a flag a profile does not use from these two;
`write_dtm`/`write_ortho` refuse a keyword from the same declaration. Adding a mission, or
a mission using an option, is an edit in missions/ only; a new option is an entry here.

Plain data, no click: the CLI turns each entry into a click option (cli/_profile_options.py).
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from ..dialect import DIALECT_NAMES, Dialect
from ..errors import ParamsError, PdsgenError, param
from ..missions import DEFAULT_PROFILE, Mission, ProductKind, get_mission, mission_names
from ..params import ParamValue
from ..storage.locations import internal


class _NotGiven:
    """An entry's default when it states none (the CLI's own default then applies: False for a flag)."""

    def __repr__(self) -> str:
        return "NOT_GIVEN"


NOT_GIVEN: Any = _NotGiven()


@dataclass(frozen=True)
class OptionSpec:
    """One option of a product command."""

    param: str  # click's parameter name, the manifest's key
    flag: str  # the command line's name of it, without its leading dashes
    help: str
    keyword: str = ""  # the library keyword ("": the same as `param`)
    always: bool = False  # every profile uses it (else: those whose mission declares `keyword`)
    choices: tuple[str, ...] | None = None
    value_type: type | None = None  # float, int; None: text (or a flag)
    default: Any = NOT_GIVEN
    show_default: bool = False
    is_flag: bool = False
    multiple: bool = False
    nargs: int = 1
    metavar: str | None = None
    required: bool = False
    file: bool = False  # a file path (not a directory)
    stored: bool = False  # a file that may be an object in storage: passed as storage.internal gives it
    convert: Callable[[Any], Any] | None = None  # the parsed value -> the library's
    omit_unset: bool = False  # None stays out of the library call: the writer's own default applies

    @property
    def library_keyword(self) -> str:
        return self.keyword or self.param


def _as_tuple(value: Any) -> tuple[Any, ...]:
    return tuple(value)


def _tuple_or_none(value: Any) -> tuple[Any, ...] | None:
    return tuple(value) if value else None


def _int_or_none(value: Any) -> int | None:
    return int(value) if value else None


def _true_or_none(value: Any) -> bool | None:
    """A flag whose absence means "as the params file says": unset is None, never False."""
    return value or None


# -- entries shared by several commands (each command lists its own, in its --help order) ---------

PARAMS = OptionSpec("params_file", "params", keyword="params", always=True, file=True,
                    help="PVL or TOML file of producer/data-set keywords (see schemas/params.toml).")
OVERWRITE = OptionSpec("overwrite", "overwrite", is_flag=True, always=True, help="Replace an existing product.")
REPROJECT = OptionSpec("reproject", "reproject", keyword="reproject_input", is_flag=True,
                       help="hrsc: warp the input into the HRSC projection and sphere instead of refusing it.")
SOURCE_LABELS = OptionSpec(
    "source_labels", "source-label", multiple=True, file=True, convert=_as_tuple,
    help="hrsc: level-2/3 label whose identification, time and orbit keywords the "
         "product carries; hrsc-ax: XML image label of the tile's MAP/DTM keywords "
         "and survey date; repeat for each source.")
OFFSET_CONVENTION = OptionSpec(
    "offset_convention", "offset-convention", choices=("standard", "dlr"), default="standard",
    show_default=True, help="hrsc: PDS3 standard projection offsets (GDAL reads them "
                            "exactly) or DLR's own, one pixel apart.")
VICAR_OFFSETS = OptionSpec(
    "vicar_offsets", "vicar-offsets", choices=("standard", "dlr"), default="standard", show_default=True,
    help="hrsc-ax: how the tile's VICAR MAP offsets count: from the centre of pixel 1,1 as the HRSC-AX "
         "image description defines them (GDAL reads them so), or DLR's HRSC Mars counting, one pixel further.")
ALLOW_DEVIATIONS = OptionSpec(
    "allow_deviations", "allow-dictionary-deviations", keyword="allow_dictionary_deviations",
    is_flag=True, default=None, convert=_true_or_none,
    help="Keep label values that break the PDS3 data dictionary (warned once) instead of refusing the product.")
ANY_KIND = OptionSpec(
    "any_kind", "any-kind", is_flag=True, always=True,
    help="Make the product even if the input looks like the other kind (a DTM of 8-bit image DNs or "
         "reflectance, an orthoimage of heights), which is refused otherwise.")
# The options about what the labels of `pdsgen dtm` and `pdsgen ortho` carry.
LABEL_FIDELITY = (SOURCE_LABELS, OFFSET_CONVENTION, VICAR_OFFSETS, ALLOW_DEVIATIONS)


def label_option(help_text: str) -> OptionSpec:
    """--label: the dialect of the product's labels."""
    return OptionSpec("label", "label", choices=DIALECT_NAMES, default=Dialect.PDS3.value, show_default=True,
                      help=help_text)


DTM_OPTIONS: tuple[OptionSpec, ...] = (
    OptionSpec("product_id", "product-id", always=True,
               help="Product ID (default: built by the profile; hrsc: h1234_0000)."),
    OptionSpec("source_ids", "source-product-id", keyword="source_product_ids", multiple=True,
               convert=_as_tuple,
               help="Source observation/product ID; repeat for each (hirise: two stereo images)."),
    OptionSpec("institution", "institution", help="Producing institution letter for HiRISE product IDs."),
    OptionSpec("product_version", "version", keyword="version", default="1.0", show_default=True, always=True,
               help="PRODUCT_VERSION_ID (HiRISE IDs encode it as two digits)."),
    PARAMS,
    OptionSpec("byte_order", "byte-order", choices=("lsb", "msb"), default=None,
               help="lsb: PC_REAL / LSB_INTEGER; msb: IEEE_REAL / MSB_INTEGER. [default: lsb; hrsc: msb]"),
    OptionSpec("kind", "kind", choices=("dt4", "da4"), default="dt4", show_default=True,
               help="hrsc/imars: heights above the 3396.0 km sphere (dt4) or the areoid (da4)."),
    OptionSpec("vertical_datum", "vertical-datum", choices=("sphere", "areoid"), default=None,
               help="What the input heights are measured from. hrsc/imars: converted to the product's datum "
                    "[default: sphere]; other profiles: stated in the label's NOTE, which the Extras legend "
                    "and README.TXT then repeat [default: not stated]."),
    OptionSpec("areoid", "areoid", file=True, stored=True,
               help="hrsc: areoid heights above the 3396.0 km sphere (any GDAL raster), to convert datums."),
    OptionSpec("precision", "precision", value_type=float, default=1.0, show_default=True,
               help="hrsc/imars: metres per stored integer step (SCALING_FACTOR)."),
    REPROJECT,
    *LABEL_FIDELITY,
    label_option("pds3 (.IMG, attached label), pds4 (.img + .xml) or both (.IMG + a PDS4 .xml "
                 "describing it); hrsc: pds3 or both."),
    ANY_KIND,
    OVERWRITE,
)

DTM_HELP = """Convert the single-band elevation raster INPUT (any GDAL format, projected
    CRS: equirectangular, polar stereographic or sinusoidal) into a PDS3 DTM in OUTDIR:
    <PRODUCT_ID>.IMG (float32), or with --label pds4 a PDS4 one (<PRODUCT_ID>.img + .xml);
    for --profile hrsc hOOOO_NNNN_dt4.img / _da4.img
    (16-bit integers with MEX:DTM scaling); for --profile imars the iMars form:
    hOOOO_NNNN_da4_ucl.tif (int16 GeoTIFF), its .pvl metadata and hOOOO_NNNN.geojson;
    for --profile hrsc-ax the HRSC-AX tile's VICAR .dsm as HRSCAX_<tile>_DEM.IMG (float32
    ellipsoid heights, transverse Mercator)."""

ORTHO_OPTIONS: tuple[OptionSpec, ...] = (
    OptionSpec("product_id", "product-id", always=True, help="Product ID (default: built by the profile)."),
    OptionSpec("bits", "bits", choices=("8", "10", "16"), convert=_int_or_none,
               help="DN bits (default: 8 for byte input, 16 for wider; floats 10 (hirise) or 16)."),
    OptionSpec("value_range", "range", value_type=float, nargs=2, metavar="MIN MAX", always=True,
               convert=_tuple_or_none,
               help="Input values mapped onto the valid DNs; outside become saturation DNs "
                    "(default: integer DNs kept if they fit, else the data's min and max)."),
    OptionSpec("observation_id", "observation-id",
               help="Source observation, e.g. ESP_042252_1930 (hirise product ID)."),
    OptionSpec("source_dtm_id", "source-dtm-id", help="Product ID of the DTM the image was orthorectified on."),
    OptionSpec("sequence", "sequence", value_type=int, default=1, show_default=True,
               help="Sequence number NN of HiRISE ortho IDs."),
    PARAMS,
    OptionSpec("product_version", "version", keyword="version", default="1.0", show_default=True, always=True,
               help="PRODUCT_VERSION_ID."),
    OptionSpec("gmljp2", "gmljp2", is_flag=True,
               help="Also write a GMLJP2 box (the GeoJP2 box is always written)."),
    OptionSpec("source_ids", "source-product-id", keyword="source_product_ids", multiple=True,
               convert=_as_tuple,
               help="hrsc/imars: source product (e.g. H1234_0000_ND3) giving orbit and sequence."),
    OptionSpec("reproject", "reproject", keyword="reproject_input", is_flag=True,
               help="hrsc: warp the input into the HRSC projection and sphere."),
    *LABEL_FIDELITY,
    label_option("pds3 (.JP2 + .LBL), pds4 (.JP2 + uncompressed .img + .xml) or both; "
                 "hrsc: pds3 or both (the nd4 .img + a PDS4 .xml describing it)."),
    ANY_KIND,
    OVERWRITE,
)

ORTHO_HELP = """Convert the 1-band (RED) or 3-band (IRB) orthoimage INPUT (any GDAL format,
    projected CRS as for DTMs) into OUTDIR/<PRODUCT_ID>.JP2 and .LBL (--label pds4: .JP2,
    .img and .xml); for --profile
    hrsc the 8-bit nadir image hOOOO_NNNN_nd4.img (attached label, DN 0 = no data);
    for --profile imars hOOOO_NNNN_nd4_ucl.tif with its .pvl and footprint; for --profile
    hrsc-ax TILE.pan, or the channel files of one colour product in band order
    (TILE.re TILE.gr TILE.bl, TILE.cir_re TILE.cir_gr TILE.cir_bl)."""

# Keywords the library takes that are no command-line option of the product (a batch sets them).
# `threads`: cores for the JPEG 2000 encoder (writers using one core anyway leave it unused).
# By the command making the products: a product kind's, or the mosaic's.
LIBRARY_ONLY = {ProductKind.DTM: frozenset[str](), ProductKind.ORTHO: frozenset({"threads"}),
                "mosaic": frozenset[str]()}


def used_options(command: str, mission: Mission, vocabulary: Iterable[OptionSpec]) -> list[OptionSpec]:
    """The entries of `vocabulary` the mission's products use when `command` (a ProductKind, or
    "mosaic") makes them."""
    declared = mission.options.of(command)
    return [spec for spec in vocabulary if spec.always or spec.library_keyword in declared]


def library_keywords(command: str, mission: Mission, vocabulary: Iterable[OptionSpec]) -> frozenset[str]:
    """Every keyword a library call of `command` making the mission's product may be given."""
    used = frozenset(spec.library_keyword for spec in used_options(command, mission, vocabulary))
    return used | mission.options.of(command) | LIBRARY_ONLY[command]


def _refuse_unused(command: str, mission: Mission, profile: str, options: Mapping[str, Any],
                   vocabulary: Iterable[OptionSpec]) -> None:
    """ParamsError naming the keywords given that the profile does not use (never silently
    dropped). A keyword given as None is not given, as an option left at its default on the
    command line is not."""
    given = {name for name, value in options.items() if value is not None}
    unused = sorted(given - library_keywords(command, mission, vocabulary))
    if unused:
        raise ParamsError(None, f"the {profile} profile does not use {', '.join(unused)}")


_VOCABULARIES = {ProductKind.DTM: DTM_OPTIONS, ProductKind.ORTHO: ORTHO_OPTIONS}


def library_choices(spec: OptionSpec) -> tuple[Any, ...]:
    """An entry's choices as the library takes them (--bits 8 is the library's 8)."""
    choices = spec.choices or ()
    return tuple(spec.convert(choice) for choice in choices) if spec.convert else choices


def check_choices(vocabulary: Iterable[OptionSpec], options: Mapping[str, Any],
                  own_choices: Mapping[str, Sequence[Any]] | None = None) -> None:
    """ParamsError for an option given a value its entry does not offer - the one check of `choices`,
    in one wording, for every writer. `own_choices`: values a mission accepts besides (iMars: da, dt).
    None is not given (the default applies)."""
    for spec in vocabulary:
        value = options.get(spec.library_keyword)
        if spec.choices is None or value is None:
            continue
        allowed = (*library_choices(spec), *(own_choices or {}).get(spec.library_keyword, ()))
        if value not in allowed:
            raise ParamsError(None, f"{param(spec.library_keyword)} must be one of "
                                    f"{', '.join(map(str, allowed))}, not {value!r}")


# -- the library call a product command makes from its parsed parameters (the CLI's and a batch job's) --

def library_options(command: str, vocabulary: Iterable[OptionSpec], params: Mapping[str, Any]) -> dict[str, Any]:
    """The library keywords (with their values) of the options the parameters' profile uses.

    `params` are a command's parsed parameters under their click names (a batch job's too), so
    `pdsgen COMMAND` and a manifest's [[COMMAND]] job make the same call."""
    profile = params["profile"]
    mission = get_mission(profile if profile in mission_names() else DEFAULT_PROFILE)
    options: dict[str, Any] = {}
    for spec in used_options(command, mission, vocabulary):
        value = params[spec.param]
        if value is None:
            value = mission.options.command_defaults.get(spec.library_keyword)
        if spec.omit_unset and value is None:
            continue  # the writer's own default
        if spec.stored:
            value = value and internal(value)
        elif spec.convert is not None:
            value = spec.convert(value)
        options[spec.library_keyword] = value
    return options


def ortho_inputs(params: Mapping[str, Any]) -> str | tuple[str, ...]:
    """The input of write_ortho: one file, or (profiles that compose bands) the files in band order."""
    more = tuple(params.get("more_inputs") or ())
    if not more:
        return internal(params["input_path"])
    if not get_mission(params["profile"]).composes_ortho_bands:
        raise PdsgenError(None, f"{param('profile', params['profile'])} takes one INPUT; "
                                f"{len(more) + 1} were given")
    return (internal(params["input_path"]), *(internal(path) for path in more))


def ortho_shared_files() -> tuple[str, ...]:
    """Files one orthoimage updates for its whole directory (fetched from, and written back to,
    an s3:// OUTDIR). Read when asked: formats.jp2 is no import of a DTM conversion."""
    from ..formats.jp2 import JP2INFO_NAME

    return (JP2INFO_NAME,)


@dataclass(frozen=True)
class ProductOptions:
    """Every option a DTM or orthoimage writer may be given, by library keyword: what a mission's
    writer takes as `writer(input_path, outdir, options)`.

    Built once, by `build`, from a caller's keywords: the defaults here are the vocabulary's, a
    mission's own (HRSC's big-endian heights) come from its declaration (`OptionUse.defaults`).
    A writer reads the fields its product uses; `build` has refused a keyword the mission does not use.
    """

    product_id: str | None = None
    source_product_ids: Sequence[str] = ()
    params: str | os.PathLike[str] | Mapping[str, ParamValue] | None = None
    version: str = "1.0"
    overwrite: bool = False
    label: str | Dialect = Dialect.PDS3
    allow_dictionary_deviations: bool | None = None
    source_labels: Sequence[str | os.PathLike[str]] = ()
    offset_convention: str = "standard"  # hrsc: "standard" or "dlr" projection offsets
    vicar_offsets: str = "standard"  # hrsc-ax: how a tile's VICAR MAP offsets count
    reproject_input: bool = False
    any_kind: bool = False  # the standard writers: make it whatever kind the input looks like
    # DTMs
    byte_order: str = "lsb"
    institution: str | None = None
    kind: str = "dt4"
    vertical_datum: str | None = None  # None: the datum of `kind`
    areoid: str | os.PathLike[str] | None = None
    precision: float = 1.0
    # orthoimages
    bits: int | None = None  # None: from the input's sample type
    value_range: tuple[float, float] | None = None
    source_dtm_id: str | None = None
    observation_id: str | None = None
    sequence: int = 1
    gmljp2: bool = False
    # library-only (LIBRARY_ONLY): no command-line option sets them
    threads: int | None = None  # cores for the JPEG 2000 encoder (None: all)

    @classmethod
    def build(cls, product: ProductKind | str, mission: Mission, keywords: Mapping[str, Any],
              profile: str | None = None) -> ProductOptions:
        """The options of a `product` (ProductKind, or its name) of `mission` from a caller's keywords.

        A keyword given as None is not given (the default applies, as for an option left unset on
        the command line); one the mission does not use, or no writer knows, is refused in one line
        naming `profile` (default: the mission's name), never dropped silently."""
        profile = profile or mission.name
        unknown = sorted(set(keywords) - _FIELD_NAMES)
        if unknown:
            raise ParamsError(None, f"the {profile} profile does not use {', '.join(unknown)}")
        product = ProductKind(product)
        _refuse_unused(product, mission, profile, keywords, _VOCABULARIES[product])
        given = {name: value for name, value in keywords.items() if value is not None}
        defaults = {name: value for name, value in mission.options.defaults.items() if name in _FIELD_NAMES}
        chosen = {**defaults, **given}
        check_choices(_VOCABULARIES[product], chosen, mission.options.choices)
        return cls(**chosen)

    def replace(self, **changes: Any) -> ProductOptions:
        """These options with some changed (a mosaic's product ID and sources, a tile's own ID)."""
        return dataclasses.replace(self, **changes)


_FIELD_NAMES = frozenset(field.name for field in dataclasses.fields(ProductOptions))
