"""The iMars writers at the import path the README documents; the code is in pdsgen.products.imars."""

from .products.imars import ImarsProduct, write_imars_dtm, write_imars_ori

__all__ = ["ImarsProduct", "write_imars_dtm", "write_imars_ori"]
