"""Regenerate schemas/pds4/context_products.txt.xz: the registered PDS context products.

Usage (from the repository root):

    python tools/pack_context_products.py PATH/TO/validate COMMIT

PATH is a checkout of NASA-PDS/validate at COMMIT. Its
src/main/resources/util/registered_context_products.json is the snapshot of PDS's
registry of context products that NASA's validator ships (refreshed weekly there) and
checks context references against. Written: one `LID VERSION` line per product, sorted,
xz-compressed (names and types, which the error check does not use, are left out),
after a header line naming the repository, commit and path.
"""

from __future__ import annotations

import json
import lzma
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "schemas" / "pds4" / "context_products.txt.xz"
SOURCE = "src/main/resources/util/registered_context_products.json"


def main(checkout: Path, commit: str) -> None:
    products = json.loads((checkout / SOURCE).read_text(encoding="utf-8"))["Product_Context"]
    lines = sorted({" ".join(product["lidvid"].split("::", 1)) for product in products})
    header = f"# NASA-PDS/validate @ {commit} {SOURCE}"
    OUT.write_bytes(lzma.compress(("\n".join([header, *lines]) + "\n").encode("utf-8"), preset=9))
    print(f"{len(lines)} context products, {OUT.stat().st_size} bytes in {OUT}")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(Path(sys.argv[1]), sys.argv[2])
