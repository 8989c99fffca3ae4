"""The record that lets README.TXT describe every product in an Extras directory.

Several `pdsgen extras` calls may write into one directory, and README.TXT must
describe all of their products, not only the last call's. Re-reading earlier
products would need their files at the same paths and a second full read of each,
so instead every call records, in the small JSON file `.pdsgen-extras.json` beside
README.TXT, the README entry of each product (see `readme_txt.product_entry`) and
the directory-wide params keywords. The next call reads that record, replaces the
entries of products it is given again, adds the new ones, drops products whose
Extras files are no longer all in the directory, and writes README.TXT and the
record anew.
"""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from ..errors import PdsgenError
from .readme_txt import DIRECTORY_KEYWORDS, ENTRY_KEYS

INDEX_NAME = ".pdsgen-extras.json"
INDEX_FORMAT = "pdsgen extras README index 1"

Entry = dict[str, Any]


def load_index(outdir: Path) -> tuple[list[Entry], dict[str, str]]:
    """The product entries and directory keywords recorded in OUTDIR (none if no record)."""
    path = outdir / INDEX_NAME
    if not path.is_file():
        return [], {}
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        raise PdsgenError(path, f"cannot be read ({exc}); delete it to start README.TXT "
                                "afresh") from None
    if not _well_formed(data):
        raise PdsgenError(path, "is not a pdsgen Extras record; delete it to start "
                                "README.TXT afresh")
    return data["products"], data["keywords"]


def merge_entries(previous: Sequence[Entry], new: Sequence[Entry], outdir: Path) -> list[Entry]:
    """Earlier entries (replaced in place when given again), then new ones; only
    products whose Extras files are all still in OUTDIR."""
    fresh = {e["product_id"]: e for e in new}
    merged = [fresh.pop(e["product_id"], e) for e in previous]
    merged += list(fresh.values())
    return [e for e in merged if e in new or all((outdir / name).is_file() for name, _, _ in e["files"])]


def index_bytes(entries: Sequence[Entry], keywords: Mapping[str, str]) -> bytes:
    """The record's JSON text."""
    data = {"format": INDEX_FORMAT, "keywords": dict(keywords), "products": list(entries)}
    return (json.dumps(data, indent=1, sort_keys=True) + "\n").encode("utf-8")


def _well_formed(data: Any) -> bool:
    if not (isinstance(data, dict) and data.get("format") == INDEX_FORMAT):
        return False
    keywords, products = data.get("keywords"), data.get("products")
    if not (isinstance(keywords, dict) and isinstance(products, list)):
        return False
    if not all(k in DIRECTORY_KEYWORDS and isinstance(v, str) for k, v in keywords.items()):
        return False
    return all(_well_formed_entry(e) for e in products)


def _well_formed_entry(entry: Any) -> bool:
    if not (isinstance(entry, dict) and set(entry) == ENTRY_KEYS):
        return False
    files = entry["files"]
    return (isinstance(entry["product_id"], str) and isinstance(files, list) and all(
        isinstance(f, list) and len(f) == 3 and all(isinstance(x, str) for x in f)
        and "/" not in f[0] and "\\" not in f[0] and f[0] not in ("", ".", "..")
        for f in files))
