"""Regenerate schemas/pds4/context_products.txt.xz: the registered PDS context products.

Usage (from the repository root):

    python tools/pack_context_products.py PATH/TO/validate COMMIT

PATH is a checkout of NASA-PDS/validate at COMMIT. Its
src/main/resources/util/registered_context_products.json is the snapshot of PDS's
registry of context products that NASA's validator ships (refreshed weekly there) and
checks context references against. Written: one line per product, sorted,
`LID VERSION<TAB>TYPES<TAB>NAMES` (types and names as the registry gives them, each list
joined by '|', runs of blanks folded, "N/A" left out: the target types and names
migrate and the PDS4 checks read), xz-compressed, after a header line naming the
repository, commit and path.
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
    lines = sorted({_line(product) for product in products})
    header = f"# NASA-PDS/validate @ {commit} {SOURCE}"
    OUT.write_bytes(lzma.compress(("\n".join([header, *lines]) + "\n").encode("utf-8"), preset=9))
    print(f"{len(lines)} context products, {OUT.stat().st_size} bytes in {OUT}")


def _line(product: dict) -> str:
    def kept(values: list[str]) -> str:
        folded = (" ".join(value.split()) for value in values)
        return "|".join(value for value in folded if value and value != "N/A")
    lid_version = " ".join(product["lidvid"].split("::", 1))
    return f"{lid_version}\t{kept(product['type'])}\t{kept(product['name'])}"


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(Path(sys.argv[1]), sys.argv[2])
