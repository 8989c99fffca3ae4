"""The DTM writer at the import path the README documents; the code is in pdsgen.products.dtm."""

from .products.dtm import DtmProduct, write_dtm, write_pds3_dtm

__all__ = ["DtmProduct", "write_dtm", "write_pds3_dtm"]
