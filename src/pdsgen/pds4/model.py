"""The PDS4 Information Model version pdsgen writes, and the namespaces it uses.

One setting: moving to a later IM is a change of this table (and shipping that
version's schemas under `schemas/pds4/<IM>/`), not of the writer or validator.
Schema file names follow the PDS convention `PDS4_<NS>_<IM>[_<LDD version>]`.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..label.grammar import SAMPLE_TYPES

PDS_NS = "http://pds.nasa.gov/pds4/pds/v1"
CART_NS = "http://pds.nasa.gov/pds4/cart/v1"
DISP_NS = "http://pds.nasa.gov/pds4/disp/v1"
XSI_NS = "http://www.w3.org/2001/XMLSchema-instance"
SCHEMATRON_NS = "http://purl.oclc.org/dsdl/schematron"
SCHEMA_HOST = "pds.nasa.gov"


@dataclass(frozen=True)
class Namespace:
    """One namespace of a label: prefix, URI and the schema file stem for our IM."""

    prefix: str
    uri: str
    stem: str  # e.g. PDS4_CART_1O00_1970 (no extension)

    @property
    def xsd_url(self) -> str:
        return f"https://{SCHEMA_HOST}/pds4/{self.prefix}/v1/{self.stem}.xsd"

    @property
    def sch_url(self) -> str:
        return f"https://{SCHEMA_HOST}/pds4/{self.prefix}/v1/{self.stem}.sch"


@dataclass(frozen=True)
class InformationModel:
    """An IM version and the discipline dictionaries built for it."""

    version: str  # information_model_version in the label, e.g. 1.24.0.0
    code: str  # the version as it appears in schema file names, e.g. 1O00
    namespaces: tuple[Namespace, ...]

    def namespace(self, prefix: str) -> Namespace:
        return next(ns for ns in self.namespaces if ns.prefix == prefix)


IM_1O00 = InformationModel(
    version="1.24.0.0",
    code="1O00",
    namespaces=(
        Namespace("pds", PDS_NS, "PDS4_PDS_1O00"),
        Namespace("cart", CART_NS, "PDS4_CART_1O00_1970"),
        Namespace("disp", DISP_NS, "PDS4_DISP_1O00_1510"),
    ),
)

# The version pdsgen writes.
CURRENT_IM = IM_1O00


# PDS4 numeric data types by (numpy kind+size, big endian): the one table. The PDS3 side is
# label.grammar.SAMPLE_TYPES (name -> byte order, kind); `pds4_data_type` joins the two, and
# NUMPY_TYPES (PDS4 name -> numpy dtype) is this table's reverse.
DATA_TYPES = {
    ("f4", False): "IEEE754LSBSingle",
    ("f4", True): "IEEE754MSBSingle",
    ("f8", False): "IEEE754LSBDouble",
    ("f8", True): "IEEE754MSBDouble",
    ("u1", False): "UnsignedByte",
    ("u1", True): "UnsignedByte",
    ("i1", False): "SignedByte",
    ("i1", True): "SignedByte",
    ("u2", False): "UnsignedLSB2",
    ("u2", True): "UnsignedMSB2",
    ("i2", False): "SignedLSB2",
    ("i2", True): "SignedMSB2",
    ("u4", False): "UnsignedLSB4",
    ("u4", True): "UnsignedMSB4",
    ("i4", False): "SignedLSB4",
    ("i4", True): "SignedMSB4",
    ("u8", False): "UnsignedLSB8",
    ("u8", True): "UnsignedMSB8",
    ("i8", False): "SignedLSB8",
    ("i8", True): "SignedMSB8",
}
# The reverse, for reading labels: data_type -> numpy dtype string.
NUMPY_TYPES = {name: (">" if big else "<") + code for (code, big), name in DATA_TYPES.items()}
NUMPY_TYPES.update({"UnsignedByte": "u1", "SignedByte": "i1"})


def pds4_data_type(sample_type: str, bits: int) -> str | None:
    """The PDS4 data_type of PDS3 samples (`SAMPLE_TYPE`/`DATA_TYPE` and their bits), or None when
    PDS4 has none (VAX and IBM reals, complex, bit strings, sizes no numeric type has)."""
    order_kind = SAMPLE_TYPES.get(sample_type.upper())
    if order_kind is None or bits % 8:
        return None
    order, kind = order_kind
    return DATA_TYPES.get((f"{kind}{bits // 8}", order == ">"))
