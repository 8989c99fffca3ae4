"""Regenerate schemas/pds4/packed/: the PDS4 schemas pdsgen ships compressed.

Usage (from the repository root):

    python tools/pack_pds4_schemas.py PATH/TO/pds4-schema-files COMMIT

PATH is a checkout of sbn-psi/pds4-schema-files (a mirror of https://pds.nasa.gov/pds4/)
at COMMIT. Written, unchanged from the mirror:

- PDS4_PDS_<IM>.tar.xz: the core schema (.xsd) and Schematron (.sch) of every released
  Information Model version the mirror holds (1.0.0.0 = 1000 onwards) but the one pdsgen
  writes, which is shipped as plain files in schemas/pds4/<IM>/;
- <ns>_<n>.tar.xz: every version the mirror holds of every discipline and common
  dictionary (each namespace directory under pds4/ but the core, mission/ and the
  single-mission ones in NOT_DISCIPLINES), those not already shipped as plain files;
  one namespace's versions in name order, cut into archives of at most CHUNK_BYTES
  unpacked (successive versions differ little, so xz packs them ~50:1, and a label's
  lookup decompresses a few MB at most);
- index.json: every packed file's archive, SHA-256 and path in the mirror, and the
  mirror's repository and commit (the catalog reads only this until a file is needed).

Archives are deterministic (sorted members, zero times and owners) so that running this
again on the same commit changes nothing. A label's lookup decompresses one archive
per IM version or dictionary chunk it needs (50-100 KB of xz each).
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
# Namespace directories of the mirror that are not discipline or common dictionaries: the
# core (packed per IM version), and dictionaries of one mission or one instrument.
NOT_DISCIPLINES = ("pds", "mission", "ladee", "msss_cam_mh")
CHUNK_BYTES = 8_000_000


def _pack(target: Path, files: list[Path]) -> None:
    buffer = io.BytesIO()
    with tarfile.open(fileobj=buffer, mode="w:xz", preset=9) as tar:
        for path in sorted(files, key=lambda p: p.name):
            data = path.read_bytes()
            info = tarfile.TarInfo(path.name)
            info.size, info.mtime, info.mode = len(data), 0, 0o644
            tar.addfile(info, io.BytesIO(data))
    target.write_bytes(buffer.getvalue())


def _unique(files: list[Path]) -> list[Path]:
    """One of each file name: the mirror holds some files under two namespace versions
    (multi/v1 and multi/v2), byte for byte the same; different bytes are an error, since
    the catalog finds a schema by its file name alone."""
    kept: dict[str, Path] = {}
    for path in files:
        other = kept.setdefault(path.name, path)
        if other != path and other.read_bytes() != path.read_bytes():
            raise SystemExit(f"{path.name}: {other} and {path} differ")
    return list(kept.values())


def _chunks(files: list[Path]) -> list[list[Path]]:
    """One namespace's files in name order (versions side by side), in runs of at most
    CHUNK_BYTES unpacked."""
    chunks: list[list[Path]] = []
    size = CHUNK_BYTES
    for path in sorted(files, key=lambda p: p.name.upper()):
        if size + path.stat().st_size > CHUNK_BYTES and (not chunks or chunks[-1]):
            chunks.append([])
            size = 0
        chunks[-1].append(path)
        size += path.stat().st_size
    return chunks


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
    for namespace in sorted(d.name for d in (mirror / "pds4").iterdir() if d.is_dir()):
        if namespace not in NOT_DISCIPLINES:
            files = _unique([p for p in sorted((mirror / "pds4" / namespace).rglob("*"))
                             if p.suffix in (".xsd", ".sch") and p.name not in loose])
            for number, chunk in enumerate(_chunks(files), 1):
                groups[f"{namespace}_{number}.tar.xz"] = chunk
    index: dict[str, dict[str, str]] = {}
    for archive, files in sorted(groups.items()):
        _pack(OUT / archive, files)
        for path in files:
            if path.name in index:  # the catalog finds a schema by its file name
                raise SystemExit(f"{path.name} is both {index[path.name]['path']} and {path.relative_to(mirror)}")
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
