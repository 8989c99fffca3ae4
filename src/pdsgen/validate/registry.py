"""The one table of rules: stable id -> family, severity, summary, check function.

Ids never change meaning once published (CI configurations refer to them). Each
family lives in its own module; this table is the only place that ties them together.
`pdsgen validate --list-rules` prints it.

Two families are profiles of one archive: HRSC (Mars Express HRSC level-4 labels: the
MEX:DTM group against the IMAGE object, the file name and the archive's map
conventions; they run only on labels recognised as HRSC, see profiles.py) and IMARS
(iMars `*_ucl.pvl` metadata files, which are PVL rather than PDS3 labels: their rules
take an ImarsContext and run only on those files, marked target="imars"). HRSC's own
offset convention is reported by the MAP family (MAP-011), beside MAP-004/MAP-005,
so every offset-convention verdict stays in one family.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass

from ..missions.imars import METADATA_SUFFIX as IMARS_METADATA_SUFFIX
from ..pds4.rules import RULES as PDS4_RULES
from .context import FileContext
from .families import dict_rules as D
from .families import file_rules as F
from .families import geo_rules as G
from .families import hrsc_rules as H
from .families import image_rules as I
from .families import imars_rules as X
from .families import map_rules as M
from .families import pointer_rules as P
from .families import set_rules as T
from .families import syntax_rules as S
from .model import Hit

FAMILIES = ("FILE", "SYNTAX", "DICT", "PTR", "REC", "IMG", "MAP", "GEO", "HRSC", "SET", "IMARS", "PDS4")


@dataclass(frozen=True)
class Rule:
    id: str
    severity: str
    summary: str
    check: Callable[[FileContext], Iterable[Hit]] | None  # per-file check
    needs_data: bool = False
    set_check: Callable[[list, set[str]], Iterable[Hit]] | None = None  # across files (SET)
    target: str = "label"  # "label": PDS3 labels (FileContext); "imars": iMars PVL (ImarsContext)
    note: str = ""  # when a finding of this rule takes another severity, and why

    @property
    def family(self) -> str:
        return self.id.split("-")[0]


def _table() -> list[Rule]:
    r = S.from_reader
    return [
        Rule("FILE-001", "error", "label bytes are printable 7-bit ASCII", F.check_ascii),
        Rule("FILE-002", "error", "lines end in CR LF (mixed ends, or LF in a file with attached data)",
             F.check_line_ends_error),
        Rule("FILE-003", "warning", "a detached label uses LF-only line ends", F.check_line_ends_warning),
        Rule("FILE-004", "error", "a label line has at most 78 characters (80 bytes with CR LF)",
             F.check_line_length, note="warning for labels pdsgen did not write, unless --strict: "
             "NASA's PDS3 tools rate it so, and released HiRISE DTM labels have 91-character lines"),
        Rule("FILE-005", "error", "a label padded to its records pads every line to RECORD_BYTES",
             F.check_padded_lines),
        Rule("FILE-006", "error", "PDS_VERSION_ID is the first statement (after a valid SFDU)",
             F.check_first_statement, note="warning for SFDU-wrapped PDS version 2 labels (Voyager, "
             "Galileo, Magellan volumes), which have no PDS_VERSION_ID"),
        Rule("FILE-007", "error", "an END statement closes the label", F.check_end),
        Rule("FILE-008", "warning", "the label is padded with spaces (not NUL)", F.check_padding),
        Rule("FILE-009", "warning", "label lines contain no tab characters", F.check_tabs),
        Rule("FILE-010", "error", "PDS_VERSION_ID = PDS3", F.check_version),
        Rule("FILE-011", "error", "the file is not empty", F.check_empty),
        # FILE-013 is reported by the runner for a file named on the command line
        Rule("FILE-013", "error", "a file named for validation is a PDS3 label (not a JP2, TIFF, bare image)",
             None),
        Rule("SYNTAX-001", "error", "statements parse: KEYWORD = value, quotes and brackets closed",
             r("SYNTAX-001")),
        Rule("SYNTAX-002", "error", "keyword names are identifiers: a letter, then letters, digits and _",
             r("SYNTAX-002")),
        Rule("SYNTAX-015", "warning", "keyword names have at most 30 characters (pointer names may be "
             "longer: ^DATA_SET_MAP_PROJECTION_CATALOG)", r("SYNTAX-015")),
        Rule("SYNTAX-003", "warning", "keywords are upper case", r("SYNTAX-003")),
        Rule("SYNTAX-004", "error", "a keyword appears once within its object", S.check_duplicates),
        Rule("SYNTAX-005", "error", "OBJECT/END_OBJECT and GROUP/END_GROUP balance and match",
             r("SYNTAX-005")),
        Rule("SYNTAX-006", "info", "END_OBJECT/END_GROUP repeat the object name", r("SYNTAX-006")),
        Rule("SYNTAX-007", "error", "based integers are 2#..#, 8#..# or 16#..# with valid digits",
             r("SYNTAX-007")),
        Rule("SYNTAX-008", "error", "dates and times are valid CCYY-MM-DDThh:mm:ss.sss / CCYY-DDD",
             r("SYNTAX-008")),
        Rule("SYNTAX-009", "error", "every keyword has a value", r("SYNTAX-009")),
        Rule("SYNTAX-010", "warning", "unquoted values are identifiers (else quote them)",
             S.check_unquoted),
        Rule("SYNTAX-011", "error", "units are not empty", r("SYNTAX-011")),
        Rule("SYNTAX-012", "warning", "no ';' statement terminators (PVL, not PDS3)", r("SYNTAX-012")),
        Rule("SYNTAX-013", "warning", "values are not empty (\"\" or ()); an empty set {} is valid ODL",
             r("SYNTAX-013")),
        Rule("SYNTAX-014", "warning", "a <unit> follows its value on the same line (pvl reads it either way)",
             r("SYNTAX-014")),
        Rule("DICT-001", "warning", "keywords are defined in the data dictionary or a mission namespace",
             D.check_unknown),
        Rule("DICT-002", "error", "values have the dictionary type of their keyword", D.check_type),
        Rule("DICT-003", "warning", "numeric values lie within the dictionary range (in its unit)",
             D.check_range, note="error in labels pdsgen writes and under --strict: its writers refuse them"),
        Rule("DICT-004", "error", "values of closed (STATIC) value sets are standard values",
             D.check_static_values),
        Rule("DICT-013", "warning", "mission identity values (MISSION_NAME, INSTRUMENT_HOST_ID ...) are "
             "registered in the shipped dictionary version", D.check_identity_values),
        Rule("DICT-005", "warning", "values of SUGGESTED value sets are among the suggestions",
             D.check_suggested_values),
        Rule("DICT-010", "info", "values of DYNAMIC value sets not yet in the dictionary",
             D.check_dynamic_values),
        Rule("DICT-009", "info", "text keywords given unquoted numbers (readers accept them)",
             D.check_number_for_text),
        Rule("DICT-006", "warning", "value lengths lie within the dictionary minimum/maximum length",
             D.check_length, note="error in labels pdsgen writes and under --strict: its writers refuse them"),
        Rule("DICT-007", "warning", "units are known PDS units", D.check_units),
        Rule("DICT-011", "error", "units measure what the dictionary's unit measures (KM, DEG ...)",
             D.check_unit_dimension),
        Rule("DICT-012", "info", "numeric 'not applicable' values (-2147483648, -9.99e+31, -1e+32) are "
             "exempt from DICT-003", D.check_hrsc_not_applicable),
        Rule("DICT-008", "info", "placeholder values (NULL) are reported", D.check_placeholder),
        Rule("PTR-001", "error", "pointers have a PDS3 form: n, n <BYTES>, \"F\", (\"F\", n)",
             P.check_pointer_form),
        Rule("PTR-002", "error", "files named by data pointers exist", P.check_target_exists,
             needs_data=True),
        Rule("PTR-003", "error", "files named by pointers match in case", P.check_target_case,
             needs_data=True),
        Rule("PTR-004", "error", "attached data do not start inside the label text",
             P.check_start_inside_label),
        Rule("PTR-005", "error", "no data between the label's END and the pointed start byte",
             P.check_start_blank_gap),
        Rule("PTR-006", "info", "attached data begin with blanks (start may be later)",
             P.check_start_possible, needs_data=True),
        Rule("PTR-007", "error", "^STRUCTURE includes do not loop back", P.check_include_loops,
             needs_data=True),
        Rule("PTR-008", "warning", "an attached label's file holds its data (not a label-only copy; "
             "data checks are skipped for one)", P.check_data_present),
        Rule("REC-001", "error", "RECORD_TYPE = FIXED_LENGTH comes with RECORD_BYTES",
             P.check_record_bytes_present),
        Rule("REC-002", "error", "RECORD_BYTES x FILE_RECORDS equals the file size", P.check_file_size,
             needs_data=True),
        Rule("REC-003", "error", "LABEL_RECORDS hold the label and end where attached data start",
             P.check_label_records),
        Rule("REC-004", "error", "REQUIRED_STORAGE_BYTES = RECORD_BYTES x FILE_RECORDS of the image",
             P.check_required_storage),
        Rule("REC-005", "error", "objects fit in RECORD_BYTES x FILE_RECORDS", P.check_object_fits_records),
        Rule("REC-006", "error", "the data file holds every byte of each object (not truncated)",
             P.check_object_in_file, needs_data=True),
        Rule("REC-007", "error", "an UNCOMPRESSED_FILE's records hold exactly its IMAGE",
             P.check_uncompressed_records),
        Rule("REC-008", "error", "FILE_RECORDS no larger than the described objects need",
             P.check_records_accounted),
        Rule("IMG-001", "error", "IMAGE objects have LINES, LINE_SAMPLES, SAMPLE_TYPE, SAMPLE_BITS",
             I.check_required),
        Rule("IMG-002", "error", "SAMPLE_TYPE is known and fits SAMPLE_BITS", I.check_sample_type),
        Rule("IMG-003", "error", "SAMPLE_BIT_MASK has no bits beyond SAMPLE_BITS", I.check_bit_mask),
        Rule("IMG-004", "error", "special constants are representable in the sample type",
             I.check_constants),
        Rule("IMG-005", "error", "VALID_MINIMUM <= VALID_MAXIMUM", I.check_valid_range_order),
        Rule("IMG-006", "error", "BAND_STORAGE_TYPE is a PDS3 storage type", I.check_band_storage,
             note="warning for a standard type spelled with spaces (BAND SEQUENTIAL)"),
        Rule("IMG-007", "error", "VALID_MINIMUM/MAXIMUM and MINIMUM/MAXIMUM match the data",
             I.check_extremes, needs_data=True),
        Rule("IMG-008", "warning", "MEAN and STANDARD_DEVIATION match the data", I.check_moments,
             needs_data=True),
        Rule("MAP-001", "error", "IMAGE_MAP_PROJECTION has the keywords a reader needs",
             M.check_required),
        Rule("MAP-002", "error", "MAP_RESOLUTION = pi R / 180 / MAP_SCALE for the projection's radius",
             M.check_resolution),
        Rule("MAP-003", "error", "offsets agree with the latitude/longitude bounds (residual in px)",
             M.check_offsets),
        Rule("MAP-004", "info", "offset convention detected: standard", M.check_convention_standard),
        Rule("MAP-005", "warning", "offset convention detected: older one-pixel-apart",
             M.check_convention_old),
        Rule("MAP-006", "error", "axis radii are positive and A >= B >= C", M.check_radii),
        Rule("MAP-007", "error", "MAP_PROJECTION_TYPE is a projection GDAL knows",
             M.check_projection_name, note="warning for a PDS3 projection GDAL does not georeference "
             "(POINT_PERSPECTIVE, ORTHOGRAPHIC ...)"),
        Rule("MAP-008", "error", "LINE/SAMPLE_LAST_PIXEL match the image size", M.check_last_pixel),
        Rule("MAP-009", "info", "bounds not checked (projection without formulas here)",
             M.check_not_checked),
        Rule("MAP-010", "warning", "bounds within 1 px of the edges but not exact (imprecise bounds)",
             M.check_bounds_imprecise),
        Rule("GEO-001", "error", "the JP2 file opens and is a JPEG 2000 file", G.check_readable,
             needs_data=True),
        Rule("GEO-002", "error", "JP2 size, bands and precision agree with the label", G.check_header,
             needs_data=True),
        Rule("GEO-003", "warning", "the JP2 carries a GeoJP2 or GMLJP2 box", G.check_has_georef,
             needs_data=True),
        Rule("GEO-004", "error", "GeoJP2/GMLJP2 geotransform agrees with the label within 1e-3 px",
             G.check_geotransform, needs_data=True),
        Rule("GEO-005", "error", "GeoJP2 projection parameters agree with the label",
             G.check_projection, needs_data=True),
        Rule("GEO-006", "error", "equirectangular standard parallel in key 3078, not 3089",
             G.check_std_parallel_key, needs_data=True),
        Rule("MAP-011", "info", "offset convention detected: older one-pixel-apart, HRSC's own (DSMAP.CAT)",
             M.check_convention_hrsc),
        Rule("HRSC-001", "error", "MEX:DTM_MISSING_DN equals the IMAGE's MISSING_CONSTANT",
             H.check_missing_dn),
        Rule("HRSC-002", "error", "MEX:DTM_SCALING_FACTOR/OFFSET equal the IMAGE's SCALING_FACTOR/OFFSET",
             H.check_scaling),
        Rule("HRSC-003", "error", "MEX:DTM_DESC agrees with the MEX:DTM radii (3396.0 sphere, -1e+32 areoid)",
             H.check_desc_radii),
        Rule("HRSC-004", "error", "MEX:DTM_DESC agrees with the file name (_dt4 sphere, _da4 areoid)",
             H.check_desc_file_name),
        Rule("HRSC-005", "error", "the map reference body is the 3396.0 km sphere", H.check_reference_body),
        Rule("HRSC-006", "warning", "sinusoidal within +-85 deg centre latitude, polar stereographic poleward",
             H.check_projection_by_latitude),
        Rule("IMARS-001", "error", "the iMars metadata file parses as PVL", X.check_parses, target="imars"),
        Rule("IMARS-002", "error", "ProductInfo (with Producer), Image, DataProduct, MapProjection, "
             "Algorithm and their keywords are present", X.check_structure, target="imars"),
        Rule("IMARS-003", "error", f"the file is named <ProductInfo.ProductId>{IMARS_METADATA_SUFFIX}",
             X.check_product_id,
             target="imars"),
        Rule("IMARS-004", "error", "DataProduct.FileName exists beside the metadata (exact case)",
             X.check_data_file, needs_data=True, target="imars"),
        Rule("IMARS-005", "error", "GDAL opens the data file as a GeoTIFF", X.check_opens, needs_data=True,
             target="imars"),
        Rule("IMARS-006", "error", "Image size, bands, sample type, NoData, scaling and offset = the GeoTIFF's",
             X.check_image, needs_data=True, target="imars"),
        Rule("IMARS-007", "error", "PixelResolution, UpperLeftCornerX/Y = the GeoTIFF geotransform (1e-3 px)",
             X.check_geotransform, needs_data=True, target="imars"),
        Rule("IMARS-008", "error", "MapProjection Proj4 = the GeoTIFF's CRS", X.check_crs, needs_data=True,
             target="imars"),
        Rule("IMARS-009", "error", "ValidMinimum/ValidMaximum = the data's valid range", X.check_valid_range,
             needs_data=True, target="imars"),
        Rule("IMARS-010", "error", "the footprint <hOOOO_NNNN>.geojson exists and is a FeatureCollection",
             X.check_footprint, needs_data=True, target="imars"),
        Rule("IMARS-011", "error", "the footprint has a feature whose id is ProductInfo.ProductId",
             X.check_footprint_feature, needs_data=True, target="imars"),
        # FILE-012 is reported by the runner itself when a file cannot be opened
        Rule("FILE-012", "error", "the file can be read", None),
        Rule("SET-001", "error", "related products (an ortho and its DTM, one stereo pair, one HRSC orbit) "
             "share projection parameters", None, set_check=T.check_projections),
        Rule("SET-002", "error", "PRODUCT_ID matches the file name (HiRISE, HRSC and pdsgen products)",
             T.check_product_id),
        Rule("SET-003", "error", "SOURCE_PRODUCT_ID references to products of the set resolve", None,
             set_check=T.check_sources),
        Rule("SET-004", "warning", "a delivery set has README.TXT and browse JPEGs (Extras)", None,
             set_check=T.check_extras),
        Rule("SET-005", "warning", "a product label describes data: a data pointer or an OBJECT "
             "(*.FMT/*.CAT and labels others include are exempt)", None, set_check=T.check_describes_data),
        # PDS4 labels are checked by pdsgen.pds4 (the runner hands them over); listed here for --list-rules
        *(Rule(r.id, r.severity, r.summary, None, target="pds4") for r in PDS4_RULES),
    ]


RULES: dict[str, Rule] = {}


def rules() -> dict[str, Rule]:
    """The rule table, built on first use."""
    if not RULES:
        ordered = sorted(_table(), key=lambda r: (FAMILIES.index(r.family), r.id))
        RULES.update((rule.id, rule) for rule in ordered)
    return RULES
