"""What the IMARS rules get for one iMars metadata file: the parsed PVL and its GeoTIFF.

iMars deliveries (pds3-products.md section 7) are not PDS3 labels: a PVL file
`<ID>_<type>4_ucl.pvl` with objects ProductInfo (group Producer), Image, DataProduct,
MapProjection and Algorithm describes a GeoTIFF beside it, and a GeoJSON footprint
`<hOOOO_NNNN>.geojson` outlines the scene. The PVL is parsed once with the pvl
library; the GeoTIFF is opened with GDAL (rasterio) only when a data rule asks, and
closed by `close()`. Nothing here raises on odd input: a parse failure is kept for
the IMARS-001 rule to report.
"""

from __future__ import annotations

import re
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..formats.sniff import file_head
from ..missions.imars import is_metadata_name

if TYPE_CHECKING:
    from ..label.beside import DirectoryNames

_SNIFF_BYTES = 64 * 1024
_OBJECT = re.compile(rb"(?im)^[ \t]*object[ \t]*=[ \t]*(productinfo|image)[ \t]*\r?$")
_BEGIN = re.compile(r"(?i)^\s*(?:begin_)?(object|group)\s*=\s*([A-Za-z0-9_:]+)")
_END = re.compile(r"(?i)^\s*end_(object|group)\b")
_KEY = re.compile(r"^\s*([A-Za-z0-9_:^]+)\s*=")


def is_imars_metadata(path: Path) -> bool:
    """An iMars metadata file: `*_ucl.pvl`, or a `.pvl` with ProductInfo and Image objects."""
    if path.suffix.lower() != ".pvl":
        return False
    if is_metadata_name(path.name):
        return True
    head = file_head(path, _SNIFF_BYTES) or b""
    return {m.group(1).lower() for m in _OBJECT.finditer(head)} == {b"productinfo", b"image"}


def lookup(container: Any, key: str) -> Any:
    """A member of a PVL object by name, ignoring case (iMars writers differ in case)."""
    if container is None or not hasattr(container, "items"):
        return None
    for name, value in container.items():
        if name.upper() == key.upper():
            return value
    return None


class ImarsContext:
    """One iMars metadata file being validated."""

    def __init__(self, path: Path, labels_only: bool = False) -> None:
        self.path = path
        self.labels_only = labels_only
        self.cache: dict[str, Any] = {}  # what IMARS rules share per file: "_footprint"
        self.parse_error: Exception | None = None
        self.module: Any = None
        from ..bounded import parse_pvl, read_bytes  # pvl is loaded only when an iMars file is checked
        from ..errors import InputError

        try:  # a regular file within the reader's size cap, then PVL within its nesting cap
            self.text = ""
            self.text = read_bytes(path, what="iMars metadata file").decode("latin-1")
            self.module = parse_pvl(path, self.text)
        except InputError as exc:
            cause = exc.__cause__
            self.parse_error = cause if isinstance(cause, Exception) else ValueError(exc.problem)
        self._dataset: Any = None
        self.open_error: str | None = None

    # -- the PVL -------------------------------------------------------------------
    def obj(self, *names: str) -> Any:
        """A nested object/group (`obj("ProductInfo", "Producer")`), or None."""
        node = self.module
        for name in names:
            node = lookup(node, name)
        return node

    def value(self, *names: str) -> Any:
        return self.obj(*names)

    @cached_property
    def _lines(self) -> dict[tuple[str, ...], int]:
        """1-based line of each keyword and object, by its upper-case path."""
        where: dict[tuple[str, ...], int] = {}
        stack: list[str] = []
        for number, line in enumerate(self.text.splitlines(), start=1):
            begin = _BEGIN.match(line)
            if begin:
                stack.append(begin.group(2).upper())
                where.setdefault(tuple(stack), number)
                continue
            if _END.match(line):
                if stack:
                    stack.pop()
                continue
            key = _KEY.match(line)
            if key:
                where.setdefault((*stack, key.group(1).upper()), number)
        return where

    def line(self, *names: str) -> int | None:
        return self._lines.get(tuple(n.upper() for n in names))

    # -- files beside it -------------------------------------------------------------
    @property
    def listing(self) -> DirectoryNames:
        from ..label.beside import directory_listing  # start-up: loaded only when a file is looked up

        return directory_listing(self.path.parent)

    def resolve(self, name: str) -> tuple[Path | None, Path | None]:
        """(exact path, path differing only in case) of a file beside the metadata."""
        from ..label.beside import resolve_beside

        return resolve_beside(self.path.parent, self.listing, name)

    @property
    def data_name(self) -> str | None:
        name = self.value("DataProduct", "FileName")
        return str(name).strip() if isinstance(name, str) and name.strip() else None

    @cached_property
    def data_path(self) -> Path | None:
        """The GeoTIFF (exact name, else the one differing in case), if there is one."""
        if self.data_name is None:
            return None
        exact, other = self.resolve(self.data_name)
        return exact or other

    def dataset(self) -> Any:
        """The GeoTIFF opened with GDAL, or None (open_error says why)."""
        if self._dataset is None and self.open_error is None and self.data_path is not None:
            import rasterio

            try:
                self._dataset = rasterio.open(self.data_path)
            except Exception as exc:  # rasterio.errors.RasterioIOError and friends
                self.open_error = str(exc)
        return self._dataset

    def close(self) -> None:
        if self._dataset is not None:
            self._dataset.close()
            self._dataset = None
