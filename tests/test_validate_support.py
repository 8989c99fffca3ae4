"""Helpers for the validator tests (no tests here): generated products and byte-exact label edits.

Edits keep every byte count the same (the label is padded to its records), so one
corruption produces the one defect it is meant to, not a cascade of record errors.
"""

from __future__ import annotations

from pathlib import Path

from pdsgen import write_dtm

from helpers import ORIGINS, elevation_array, stated_keywords, write_raster


def make_dtm(tmp_path: Path, kind: str = "equirectangular", lines: int = 40, samples: int = 50,
             dtype: str = "float32", byte_order: str = "lsb", profile: str = "generic",
             name: str = "dtm") -> Path:
    """Write a DTM product with pdsgen, its identification stated as a producer's params file
    states it (what these tests check is the product, not a missing params file), and return
    its .IMG path."""
    crs, transform = ORIGINS[kind]
    data = elevation_array(lines, samples, seed=lines + samples, dtype="float64")
    nodata = -32768 if dtype in ("int16", "int32", "float32", "float64") else 0
    if dtype.startswith("uint"):
        data = data - data.min() + 1
    data = data.astype(dtype)
    if lines > 1:
        data[0, : max(1, samples // 10)] = nodata
    source = write_raster(tmp_path / f"{name}_{kind}.tif", data, crs, transform, nodata=nodata)
    kwargs = {"source_product_ids": ["PSP_008669_1705", "PSP_009025_1705"]} if profile == "hirise" else {}
    # 8-bit heights are what these tests mean to make: pdsgen takes such a raster for an image's DNs
    # unless told (any_kind)
    product = write_dtm(source, tmp_path / name, byte_order=byte_order, profile=profile,
                        institution="U" if profile == "hirise" else None, any_kind=dtype == "uint8",
                        params=stated_keywords(), **kwargs)
    return product.path


def label_end(data: bytes) -> int:
    """Offset just past the END line of an attached label."""
    index = data.index(b"\r\nEND\r\n")
    return index + len(b"\r\nEND\r\n")


def replace_in_label(path: Path, old: bytes, new: bytes) -> None:
    """Replace one label text with another of the same length."""
    assert len(old) == len(new), (old, new)
    data = path.read_bytes()
    end = label_end(data)
    assert data[:end].count(old) == 1, old
    path.write_bytes(data[:end].replace(old, new) + data[end:])


def resize_label_text(path: Path, old: bytes, new: bytes) -> None:
    """Replace label text with text of another length, taking or giving the difference
    from the space padding after END, so the data stay where the pointer says. A label
    that fills its records exactly gives the room from its alignment blanks instead
    ("KEY  = value" read as "KEY = value")."""
    data = path.read_bytes()
    end = label_end(data)
    assert data[:end].count(old) == 1, old
    head = data[:end].replace(old, new)
    rest = data[end:]
    delta = len(head) - end
    blanks = len(rest) - len(rest.lstrip(b" "))
    if delta > blanks:
        at = head.index(new) + len(new)
        before, after = head[:at], head[at:]
        assert after.count(b"  = ") >= delta - blanks, "not enough padding after END"
        head = before + after.replace(b"  = ", b" = ", delta - blanks)
        delta = len(head) - end
    assert delta <= blanks, "not enough padding after END"
    rest = rest[delta:] if delta >= 0 else b" " * -delta + rest
    path.write_bytes(head + rest)
