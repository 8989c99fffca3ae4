"""PDS3 products described in PDS4 labels, their files unchanged (`pdsgen migrate`)."""

from __future__ import annotations

from .objects import Refused
from .product import MigratedProduct, MigrationRun, migrate_product, migrate_products, product_labels

__all__ = ["MigratedProduct", "MigrationRun", "Refused", "migrate_product", "migrate_products", "product_labels"]
