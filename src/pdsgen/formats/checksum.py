"""File checksums: the MD5 PDS labels and delivery manifests state, and SHA-256 for integrity.

One home for every digest pdsgen computes of a file's bytes, read in blocks so memory
stays flat whatever the file's size. Writers that digest bytes as they write them
(pds4/content.py's ContentTap) and readers that look at each block for something else
too (validate/pds4/data_checks.py) take a digest object from here and feed it themselves.
"""

from __future__ import annotations

import hashlib
import os
from collections.abc import Iterator
from typing import Protocol

BLOCK_BYTES = 8 * 1024 * 1024  # one read: large enough for speed, small enough for flat memory


class Digest(Protocol):
    """What hashlib's digest objects offer (hashlib's own type is private)."""

    def update(self, data: bytes | bytearray | memoryview, /) -> None: ...

    def hexdigest(self) -> str: ...


def md5() -> Digest:
    """A new MD5 digest (PDS3 manifests, PDS4 md5_checksum): a file format's checksum, not security."""
    return hashlib.md5(usedforsecurity=False)


def sha256() -> Digest:
    """A new SHA-256 digest (integrity of downloaded and cached files)."""
    return hashlib.sha256()


def blocks(path: str | os.PathLike[str], size: int = BLOCK_BYTES) -> Iterator[bytes]:
    """The file's bytes, `size` at a time."""
    with open(path, "rb") as stream:
        while block := stream.read(size):
            yield block


def file_md5(path: str | os.PathLike[str]) -> str:
    """The MD5 of a file (hex), read in blocks."""
    return _file_digest(path, md5())


def file_sha256(path: str | os.PathLike[str]) -> str:
    """The SHA-256 of a file (hex), read in blocks."""
    return _file_digest(path, sha256())


def size_and_md5(path: str | os.PathLike[str]) -> tuple[int, str]:
    """The byte count and MD5 (hex) of a file, in one pass."""
    digest, size = md5(), 0
    for block in blocks(path):
        digest.update(block)
        size += len(block)
    return size, digest.hexdigest()


def bytes_md5(data: bytes) -> str:
    """The MD5 (hex) of bytes about to be written as a file."""
    digest = md5()
    digest.update(data)
    return digest.hexdigest()


def bytes_sha256(data: bytes) -> str:
    """The SHA-256 (hex) of bytes about to be written as a file (or of a text's encoding)."""
    digest = sha256()
    digest.update(data)
    return digest.hexdigest()


def _file_digest(path: str | os.PathLike[str], digest: Digest) -> str:
    for block in blocks(path):
        digest.update(block)
    return digest.hexdigest()


def label_md5(path: str | os.PathLike[str]) -> str | None:
    """The MD5 of a PDS3 label's own bytes (from the file's start to the end of its END line; all
    of a detached label, the label part of an attached one): the identity of what a product says
    of itself, recorded by what is made from it (the Extras' README.TXT) so a later change of the
    product is a fact. None when the file is no PDS3 label or cannot be read."""
    from ..label.read import read_pds3_label  # the label reader, on first use

    try:
        found = read_pds3_label(path)
    except OSError:
        return None
    if found is None:
        return None
    return bytes_md5(found.head[:found.label.label_end])
