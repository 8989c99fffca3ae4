"""The contract every product result keeps, whichever mission wrote it.

A writer returns a `ProductResult`: its product ID, the files it wrote, the map geometry,
the dictionary deviations it kept (`warnings`), whether its label was checked with the
validator's rules, and the one line that says what was written (`summary_line`, the line
`pdsgen dtm` and `pdsgen ortho` print). It is a `CommandResult` (pdsgen/results.py), the
result every command returns: the CLI and `pdsgen batch` read only that contract, so a
new mission's result needs no edit there, and nothing asks a result which class it is.
"""

from __future__ import annotations

from abc import abstractmethod
from dataclasses import dataclass
from pathlib import Path
from typing import Any, ClassVar

from ..geo.geometry import MapGeometry
from ..results import CommandResult, written_line


class ProductResult(CommandResult):
    """What a writer returns. Each mission's result is a frozen dataclass deriving from it,
    with fields of its own (paths, DN ranges, scaling) beside these."""

    product_id: str
    geometry: MapGeometry
    warnings: tuple[str, ...]  # dictionary deviations kept (allow_dictionary_deviations)
    # The writer checked the label with the validator's rules before publishing it (and
    # refuses a product that fails them); False where the metadata is not a PDS3 label.
    label_checked: ClassVar[bool] = True

    @property
    @abstractmethod
    def files(self) -> tuple[Path, ...]:
        """Every file this product wrote, the main one first."""

    @property
    def summary_line(self) -> str:
        """What was written, in one line: the line `pdsgen dtm` / `pdsgen ortho` print, in the one
        form of the commands that make products (`written_line`): every file, then the size."""
        size = f"{self.geometry.lines} x {self.geometry.samples} (lines x samples)"
        return written_line(self.written_files, (size, *self.summary_facts))

    @property
    def summary_facts(self) -> tuple[str, ...]:
        """What the summary line says of the product after its files and size (its values, DNs)."""
        return ()

    @property
    def summary_lines(self) -> tuple[str, ...]:
        return (self.summary_line,)

    def details(self) -> dict[str, Any]:
        """`checks.label_rules` is "passed" for products whose label the writer checked with the
        validator's rules before publishing (it refuses them otherwise); the deviations it was
        told to keep are listed under `checks.warnings` too (as before the common `warnings`)."""
        return {
            "product_id": self.product_id,
            "lines": self.geometry.lines,
            "samples": self.geometry.samples,
            "checks": {
                "label_rules": "passed" if self.label_checked else "not run",
                "warnings": list(self.warnings),
            },
        }


@dataclass(frozen=True)
class ListedProduct(CommandResult):
    """A mosaic: the product's own summary line (every file, the size, its values) saying it is
    a mosaic; its JSON the product's own."""

    product: ProductResult

    @property
    def files(self) -> tuple[Path, ...]:
        return self.product.files

    @property
    def warnings(self) -> tuple[str, ...]:
        return self.product.warnings

    @property
    def summary_lines(self) -> tuple[str, ...]:
        return (f"{self.product.summary_line}, a mosaic",)

    def details(self) -> dict[str, Any]:
        return self.product.details()


def checked_result(value: object, writer: object) -> ProductResult:
    """What a mission's writer returned, refused (TypeError) unless it keeps the contract.

    Missions name their writers as "module:function" and the registry imports them on
    first use, so their return type is known only when they return.
    """
    if not isinstance(value, ProductResult):
        name = getattr(writer, "__qualname__", repr(writer))
        raise TypeError(f"{name} returned a {type(value).__name__}, not a ProductResult")
    return value


__all__ = ["ListedProduct", "ProductResult", "checked_result"]
