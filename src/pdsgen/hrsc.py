"""The HRSC level-4 writers at the import path the README documents; the code is in pdsgen.products.hrsc."""

from .products.hrsc import HrscDtmProduct, HrscImageProduct, Int16Encoding, write_hrsc_dtm, write_hrsc_nd4

__all__ = ["HrscDtmProduct", "HrscImageProduct", "Int16Encoding", "write_hrsc_dtm", "write_hrsc_nd4"]
