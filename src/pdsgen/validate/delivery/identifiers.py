"""DLV-029: each part of a product names that product, not another of the delivery: the README.TXT
entry documenting it (its Product ID, and the previews it lists, named by the product's ID as
the Extras name them), and its PDS4 label (the LID's last field, the product's ID in lower case
as pdsgen and migrate write it). A part naming another delivered product's ID was copied from,
or left by, that product; a name that is no product's of the delivery is not this check's (a
genuine archive's LIDs follow their own rules)."""

from __future__ import annotations

from .model import DeliveryModel, ExtrasEntry, Product
from .parts import Found


def check_identifiers(model: DeliveryModel, found: list[Found]) -> None:
    """DLV-029 on the model's joined products and the Extras' entries."""
    ids = {p.pds3.product_id.upper() for p in model.products if p.pds3 is not None and p.pds3.product_id}
    for extras in model.extras:
        _check_entry(model, extras, ids, found)
    for product in model.products:
        _check_lid(product, ids, found)


def _check_entry(model: DeliveryModel, extras: ExtrasEntry, ids: set[str], found: list[Found]) -> None:
    entry = extras.entry
    record = model.pds3(extras.product) if extras.product is not None else None
    own = (record.product_id or "").upper() if record is not None else ""
    if own and entry.product_id.upper() != own:
        found.append(Found("DLV-029", extras.readme, f"the entry of Product ID {entry.product_id} documents "
                                                     f"{record.path.name if record else ''}, whose PRODUCT_ID is "
                                                     f"{own}", entry.line))
    documented = entry.product_id.upper()
    for name, line in entry.files:
        stem = name.split(".", 1)[0].upper()
        if stem != documented and stem in ids:
            found.append(Found("DLV-029", extras.readme, f"{name}, listed among the files of {entry.product_id}, "
                                                         f"is named by another product's ID ({stem})", line))


def _check_lid(product: Product, ids: set[str], found: list[Found]) -> None:
    if product.pds3 is None or product.pds4 is None or not product.pds3.product_id:
        return
    own = product.pds3.product_id.upper()
    last = product.pds4.lid.rsplit(":", 1)[-1].upper()
    if last != own and last in ids:
        found.append(Found("DLV-029", product.pds4.path, f"logical_identifier {product.pds4.lid} names product "
                                                         f"{last}, but the label describes "
                                                         f"{product.pds3.path.name} (PRODUCT_ID {own})"))
