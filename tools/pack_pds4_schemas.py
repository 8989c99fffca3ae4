"""Regenerate schemas/pds4/packed/: the PDS4 schemas pdsgen ships compressed.

Usage (from the repository root):

    python tools/pack_pds4_schemas.py PATH/TO/pds4-schema-files COMMIT

PATH is a checkout of sbn-psi/pds4-schema-files (a mirror of https://pds.nasa.gov/pds4/)
at COMMIT. Written, unchanged from the mirror:

- PDS4_PDS_<IM>.tar.xz: the core schema (.xsd) and Schematron (.sch) of every released
  Information Model version the mirror holds (1.0.0.0 = 1000 onwards) but the one pdsgen
  writes, which is shipped as plain files in schemas/pds4/<IM>/;
- disciplines_<IM>.tar.xz: the common discipline dictionaries at the IM version pdsgen
  writes (model.CURRENT_IM), those not already shipped as plain files in schemas/pds4/<IM>/;
- index.json: every packed file's archive, SHA-256 and path in the mirror, and the
  mirror's repository and commit (the catalog reads only this until a file is needed).

Archives are deterministic (sorted members, zero times and owners) so that running this
again on the same commit changes nothing. One archive per IM version keeps a label's
lookup to one ~50 KB decompression.
"""

from __future__ import annotations

import hashlib
import io
import json
import re
import sys
import tarfile
from pathlib import Path

REPOSITORY = "sbn-psi/pds4-schema-files"
ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "schemas" / "pds4" / "packed"
CORE = re.compile(r"PDS4_PDS_(1[0-9A-Z]{3})\.(xsd|sch)$")
# Common discipline dictionaries, by namespace directory in the mirror.
DISCIPLINES = ("cart", "disp", "geom", "img", "img_surface", "msn", "msn_surface", "proc", "rings", "sp")


def _pack(target: Path, files: list[Path]) -> None:
    buffer = io.BytesIO()
    with tarfile.open(fileobj=buffer, mode="w:xz", preset=9) as tar:
        for path in sorted(files, key=lambda p: p.name):
            data = path.read_bytes()
            info = tarfile.TarInfo(path.name)
            info.size, info.mtime, info.mode = len(data), 0, 0o644
            tar.addfile(info, io.BytesIO(data))
    target.write_bytes(buffer.getvalue())


def main(mirror: Path, commit: str) -> None:
    sys.path.insert(0, str(ROOT / "src"))
    from pdsgen.pds4.model import CURRENT_IM

    loose = {p.name for p in (ROOT / "schemas" / "pds4" / CURRENT_IM.code).iterdir()}
    OUT.mkdir(parents=True, exist_ok=True)
    for old in OUT.glob("*.tar.xz"):
        old.unlink()
    groups: dict[str, list[Path]] = {}
    for path in sorted((mirror / "pds4" / "pds" / "v1").iterdir()):
        match = CORE.match(path.name)
        if match and path.name not in loose:
            groups.setdefault(f"PDS4_PDS_{match[1]}.tar.xz", []).append(path)
    for namespace in DISCIPLINES:
        for path in sorted((mirror / "pds4" / namespace / "v1").glob(f"*_{CURRENT_IM.code}_*")):
            if path.suffix in (".xsd", ".sch") and path.name not in loose:
                groups.setdefault(f"disciplines_{CURRENT_IM.code}.tar.xz", []).append(path)
    index: dict[str, dict[str, str]] = {}
    for archive, files in sorted(groups.items()):
        _pack(OUT / archive, files)
        for path in files:
            index[path.name] = {"archive": archive, "sha256": hashlib.sha256(path.read_bytes()).hexdigest(),
                                "path": str(path.relative_to(mirror))}
    (OUT / "index.json").write_text(json.dumps({"repository": REPOSITORY, "commit": commit, "files": index},
                                               indent=1, sort_keys=True) + "\n", encoding="utf-8")
    total = sum(p.stat().st_size for p in OUT.glob("*.tar.xz"))
    print(f"{len(groups)} archives, {len(index)} files, {total / 1024:.0f} KB in {OUT}")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(Path(sys.argv[1]), sys.argv[2])
