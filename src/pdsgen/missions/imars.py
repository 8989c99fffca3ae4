"""iMars deliveries (UCL): int16 GeoTIFF + PVL metadata + GeoJSON footprint of HRSC scenes.

Names: `<hOOOO_NNNN>_<kind>4_ucl.tif` and `.pvl` (kind `da`/`dt` for DTMs, `nd`
for the orthoimage), footprint `<hOOOO_NNNN>.geojson`; orbit and sequence are
HRSC's (see missions/hrsc.py), so are the sphere and the no-data DN.
"""

from __future__ import annotations

from .base import Mission, OptionUse
from .hrsc import AREOID_DESC, SPHERE_DESC, height_datum

CREDIT = "ESA/DLR/FU Berlin/UCL"
INSTITUTION = "UCL MULLARD SPACE SCIENCE LABORATORY"
METADATA_SUFFIX = "_ucl.pvl"
DTM_DESCRIPTIONS = {"dt": SPHERE_DESC, "da": AREOID_DESC}
DTM_NOTE = "Heights in meters = DN * SCALING_FACTOR + OFFSET."


def product_stem(base: str, kind: str) -> str:
    """`h1234_0000` + `da` -> `h1234_0000_da4_ucl` (the .tif and .pvl share it)."""
    return f"{base}_{kind}4_ucl"


def mosaic_stem(product_id: str, product_type: str) -> str:
    """A mosaic of strips, named as the iMars mosaics are: `sprc_mosaic` + DTM -> `sprc_mosaic_dtm`
    (`_ori` for the orthoimage); its footprint is `<ID>.geojson` like a strip's."""
    return f"{product_id}_{PRODUCT_TYPES[product_type][1].lower()}"


# The Image keyword that marks a mosaic's metadata (its value: how many source strips).
MOSAIC_KEYWORD = "MosaicSourceCount"


def mosaic_base(product_id: str) -> str | None:
    """`sprc_mosaic_dtm` -> `sprc_mosaic` (the footprint's name); None if not a mosaic's ID."""
    for product_type in PRODUCT_TYPES:
        suffix = mosaic_stem("", product_type)
        if product_id.endswith(suffix) and len(product_id) > len(suffix):
            return product_id[: -len(suffix)]
    return None


def metadata_name(product_id: str) -> str:
    """The metadata file of a product: `<ProductId>_ucl.pvl`."""
    return f"{product_id}{METADATA_SUFFIX}"


def is_metadata_name(name: str) -> bool:
    return name.lower().endswith(METADATA_SUFFIX)


def footprint_name(base: str) -> str:
    return f"{base}.geojson"


def footprint_shapefile_names(base: str) -> dict[str, str]:
    """The Shapefile of the footprint, as the delivery lists it: `<base>.shp .shx .dbf .prj`
    (and QGIS's `.qpj`), beside the GeoJSON."""
    return {part: f"{base}{part}" for part in (".shp", ".shx", ".dbf", ".prj", ".qpj")}


# The facts of the real iMars metadata (PVL objects and GeoTIFF tags).
PROCESSING_ORGANISATION = "UCL MSSL IMAGING GROUP"
SOFTWARE_NAME = "pdsgen"
PROCESSING_LEVEL = "4"
DATA_SET_NAME = "iMars HRSC DTM and ORI products"
PRODUCT_TYPES = {  # product type -> (ProductTypeName, ProductTypeID)
    "DTM": ("DIGITAL TERRAIN MODEL", "DTM"),
    "ORI": ("ORTHORECTIFIED IMAGE", "ORI"),
}


MISSION = Mission(
    name="imars",
    dtm_note=DTM_NOTE,
    credit=CREDIT,
    dtm_height_datum=height_datum,  # HRSC's kinds and datums
    dtm_writer="pdsgen.products.imars:write_imars_dtm",
    ortho_writer="pdsgen.products.imars:write_imars_ori",
    # GeoTIFF + PVL: no PDS label to choose a dialect of or keep deviations in
    options=OptionUse(
        dtm=frozenset({"source_product_ids", "kind", "vertical_datum", "areoid", "precision"}),
        ortho=frozenset({"source_product_ids", "bits"}),
        mosaic=frozenset({"precision"}),
        defaults={"kind": "da"},  # areoid heights: iMars's DTMs are DA4
        choices={"kind": ("da", "dt")},  # its own names of DA4 and DT4 (the writer reads dt4/da4 so too)
        command_defaults={"vertical_datum": "sphere"},  # input heights above the sphere unless told
    ),
    mosaic_writer="pdsgen.mosaic.imars:write_imars_mosaic",  # <ID>_dtm.tif/_ori.tif, a polygon per strip
)
