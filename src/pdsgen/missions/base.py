"""What a mission is to pdsgen, and the registry of missions by profile name.

A mission is data plus, when its products have their own form, the writers that
make them. A mission whose DTMs and orthoimages are the standard PDS3 forms
(float32 .IMG, JP2 + .LBL) needs no writer of its own: it gives its keyword
defaults, credit and naming rule, and the standard writers use them.
Writers are named as "module:function" so the registry never imports a writer
(the writers import mission facts; naming them keeps the import graph acyclic).
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from enum import Enum
from typing import TYPE_CHECKING, Any

from ..errors import PdsgenError

if TYPE_CHECKING:
    from ..geo.geometry import MapGeometry

Writer = Callable[..., Any]


class ProductKind(str, Enum):
    """What a product holds: heights (a DTM) or an image (an orthoimage).

    "kind" names other things in pdsgen too - HRSC's height kinds dt4/da4 (`ProductOptions.kind`),
    the command of a batch job, the kind Extras are asked to treat products as (a product kind, or
    nomap for HiRISE NOMAP mosaics), the class of a label token - so the product kind is this one
    type, not text.
    It is a `str` (`ProductKind.DTM == "dtm"`), so options, manifests and results that hold the
    text keep working.
    """

    DTM = "dtm"
    ORTHO = "ortho"

    def __str__(self) -> str:
        return self.value

    def __format__(self, spec: str) -> str:
        return format(self.value, spec)


# The product kinds' names, in the order --help lists them.
PRODUCT_KINDS = tuple(kind.value for kind in ProductKind)


@dataclass(frozen=True)
class ProductIdRequest:
    """Everything a mission may use to name a product it was not given an ID for."""

    stem: str
    geometry: MapGeometry
    sources: Sequence[str] = ()
    institution: str | None = None
    version: str = "1.0"
    bands: int = 1
    observation_id: str | None = None
    sequence: int = 1


@dataclass(frozen=True)
class LabelFacts:
    """What mission detection looks at, taken from a label by whichever reader parsed it."""

    instrument_id: str = ""
    data_set_id: str = ""
    group_names: frozenset[str] = frozenset()  # OBJECT and GROUP names, upper case
    file_name: str = ""


def data_set_names_mission(facts: LabelFacts, instrument_id: str, data_set_prefix: str) -> bool:
    """Whether the label's DATA_SET_ID makes it the mission's: only when the label states no
    instrument, or the mission's. A label that states another instrument - "UNK" included, as a
    product made without identification keywords does - is not taken for the mission's because
    its maker borrowed a data set ID."""
    stated = facts.instrument_id.strip().upper()
    return facts.data_set_id.strip().upper().startswith(data_set_prefix) and stated in ("", instrument_id)


@dataclass(frozen=True)
class ContextReference:
    """A registered PDS4 context product a label points at: investigation, host, instrument."""

    name: str
    type: str  # Mission / Individual Investigation; Host / Instrument
    lid: str
    reference_type: str  # data_to_investigation, is_instrument_host, is_instrument


@dataclass(frozen=True)
class Pds4Facts:
    """What a mission contributes to its PDS4 labels: the LID's bundle part and context."""

    bundle: str
    investigation: ContextReference
    observing_system: tuple[ContextReference, ...] = ()
    authority: str = "urn:nasa:pds"  # LID prefix of the archive holding the products (ESA: urn:esa:psa)
    # The curating_facility of the products a label names as its sources (PDS3 product IDs).
    curating_facility: str = "PDS"


# Products of no particular mission (PDS4 requires an investigation; this is PDS's "none").
INDIVIDUAL_INVESTIGATION = Pds4Facts(
    bundle="pdsgen",
    investigation=ContextReference("No Specific Investigation", "Individual Investigation",
                                   "urn:nasa:pds:context:investigation:individual.none", "data_to_investigation"),
)


@dataclass(frozen=True)
class OptionUse:
    """The options a mission's products use, by library keyword, for each product kind.

    Only the options some profile does without are declared here; those every profile takes
    (product ID, params, version, overwrite ...) are marked `always` in the option vocabulary
    (products/options.py). The CLI's flags, its refusal of a flag a profile does not use, the
    library's refusal of a keyword and a batch manifest's check are all derived from this.
    """

    dtm: frozenset[str]
    ortho: frozenset[str]
    mosaic: frozenset[str]
    # The mission's own defaults of options it uses, where they differ from the vocabulary's
    # (HRSC: big-endian heights); a writer's options object is built with them.
    defaults: Mapping[str, Any] = field(default_factory=dict)
    # Values the mission accepts for an option besides the vocabulary's `choices` (iMars: da, dt).
    choices: Mapping[str, tuple[Any, ...]] = field(default_factory=dict)
    # Defaults of the command line (and a batch manifest's job) where they differ from the
    # library's: HRSC and iMars take input heights above the sphere unless told otherwise, while
    # for every other profile an unset --vertical-datum means "the label does not state one".
    command_defaults: Mapping[str, Any] = field(default_factory=dict)

    def of(self, command: str) -> frozenset[str]:
        """The declared options of the products `command` makes: "dtm", "ortho" (a ProductKind's
        name) or "mosaic"."""
        return {"dtm": self.dtm, "ortho": self.ortho, "mosaic": self.mosaic}[command]

    def adding(self, *, dtm: Iterable[str] = (), ortho: Iterable[str] = (),
               mosaic: Iterable[str] = ()) -> OptionUse:
        """These options and more: a mission that takes the standard ones plus its own."""
        return OptionUse(self.dtm | set(dtm), self.ortho | set(ortho), self.mosaic | set(mosaic), self.defaults,
                         self.choices, self.command_defaults)


# What the standard writers (float32 PDS3 DTM, JP2 + LBL orthoimage) use: a mission that
# declares nothing else gets these.
STANDARD_OPTIONS = OptionUse(
    dtm=frozenset({"source_product_ids", "byte_order", "vertical_datum", "label", "allow_dictionary_deviations"}),
    ortho=frozenset({"bits", "observation_id", "source_dtm_id", "sequence", "gmljp2", "label",
                     "allow_dictionary_deviations"}),
    mosaic=frozenset({"byte_order", "label", "allow_dictionary_deviations"}),
)


@dataclass(frozen=True)
class Mission:
    """One mission profile: names, keyword defaults, credit, detection and writers."""

    name: str
    dtm_keywords: Mapping[str, str] = field(default_factory=dict)
    dtm_note: str = ""
    credit: str = ""
    ortho_keywords: Mapping[str, str] | None = None  # None: no standard JP2 + LBL orthoimages
    ortho_description: str = "Orthorectified image"
    filter_wavelengths_nm: Mapping[str, int] | None = None
    default_ortho_bits_for_float: int = 16
    valid_range_decimals: int | None = None  # VALID_MINIMUM/MAXIMUM to this many decimals (None: exact)
    ortho_stretch_namespace: str | None = None  # e.g. "MRO": MRO:MINIMUM_STRETCH/MAXIMUM_STRETCH per band
    ortho_standard_parallels_na: bool = False  # FIRST/SECOND_STANDARD_PARALLEL = "N/A" in ortho labels
    # Comment lines (/* ... */) in IMAGE_MAP_PROJECTION saying how the source's grid was read.
    map_projection_note: tuple[str, ...] = ()
    dtm_product_id: Callable[[ProductIdRequest], str] | None = None  # None: from the input file name
    ortho_product_id: Callable[[ProductIdRequest], str] | None = None
    dtm_writer: Writer | str | None = None  # None: the standard float32 PDS3 DTM writer
    ortho_writer: Writer | str | None = None  # None: the standard JP2 + LBL writer
    detect: Callable[[LabelFacts], bool] | None = None  # does a label belong to this mission?
    # What the heights of a DTM so named are above ("the Mars 2000 areoid"); Extras legends.
    dtm_height_datum: Callable[[str], str | None] | None = None
    # Whether a product ID names one of the mission's DTMs: an orthoimage's source DTM ID is
    # refused when it does not (None: any product ID is taken).
    source_dtm_id: Callable[[str], bool] | None = None
    pds4: Pds4Facts = INDIVIDUAL_INVESTIGATION  # context of the standard products' PDS4 labels
    options: OptionUse = STANDARD_OPTIONS  # the options its products use (the CLI's and the library's)
    composes_ortho_bands: bool = False  # an orthoimage may be made of several single-band input files
    # Mosaics (`pdsgen mosaic`), each "module:function" imported on first use: a reader of the
    # mission's own inputs (HRSC-AX tiles: the inputs as the mosaic plans them, and the ProductStatement
    # their labels make) with the options that reader takes rather than the writers; a form
    # of its own (iMars); and a check of a mosaic's product ID (the refusal, or None when it is fine).
    mosaic_reader: str | None = None
    mosaic_reader_options: frozenset[str] = frozenset()
    mosaic_writer: str | None = None
    mosaic_product_id: Callable[[str], str | None] | None = None

    def writer(self, kind: ProductKind | str) -> Writer | None:
        """The mission's own writer of its `kind` products (DTM or ortho), imported on first use."""
        named = self.dtm_writer if kind == ProductKind.DTM else self.ortho_writer
        if named is None or callable(named):
            return named
        return resolve(named)


def resolve(named: str) -> Any:
    """The function a mission names as "module:function", imported on first use (a mission's
    module imports no writer, so declaring one costs nothing until a product needs it)."""
    module, _, function = named.partition(":")
    return getattr(importlib.import_module(module), function)


_REGISTRY: dict[str, Mission] = {}


def register_mission(mission: Mission, *, replace: bool = False) -> Mission:
    """Make `mission` available as `profile=mission.name` to the writers and the CLI."""
    if mission.name in _REGISTRY and not replace:
        raise ValueError(f"a mission named {mission.name!r} is already registered")
    _REGISTRY[mission.name] = mission
    return mission


def unregister_mission(name: str) -> None:
    _REGISTRY.pop(name, None)


def get_mission(name: str) -> Mission:
    try:
        return _REGISTRY[name]
    except KeyError:
        raise PdsgenError(None, f"unknown profile {name!r}; choose from {', '.join(_REGISTRY)}") from None


def mission_names() -> list[str]:
    return list(_REGISTRY)


# The profile used when none is named (the CLI's --profile default, write_dtm's `profile`).
DEFAULT_PROFILE = "generic"


def detect_mission(facts: LabelFacts) -> str | None:
    """The first registered mission that recognises this label (and file name), if any."""
    for mission in _REGISTRY.values():
        if mission.detect is not None and mission.detect(facts):
            return mission.name
    return None
