"""The orthoimage writer at the import path the README documents; the code is in pdsgen.products.ortho."""

from .products.ortho import OrthoProduct, write_jp2_ortho, write_ortho

__all__ = ["OrthoProduct", "write_jp2_ortho", "write_ortho"]
