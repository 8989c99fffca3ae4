"""The one way from a name someone else wrote to a local path: the containment rule.

A name from outside - an object key under an s3:// prefix, a file a label, index table or
manifest names, a job's output directory, a link inside a delivery - must never make pdsgen
read or write a file outside the tree it was given. Every module that turns such a name into
a local path does it here, so the rule is written once:

- `checked_name` refuses a name no tree holds: empty, absolute (`/x`, `//x`), a `..` or `.`
  or empty segment (`a//b`), a NUL, a segment over NAME_MAX bytes or a whole over PATH_MAX;
- `inside` joins a checked name onto a root and keeps it only if, every link resolved, it
  still lies inside the root (a link beside it that leaves the tree is refused);
- `contained` is the test itself, for paths already in hand (a label's pointer, a walk's
  entry): the path if it resolves inside the root, else None.

It stands on the lowest floor (storage imports no folder), so labels, the validator,
deliver, migrate, batch and the S3 staging all import it.
"""

from __future__ import annotations

import os
from pathlib import Path, PurePosixPath

from ..errors import InputError

# What a Linux file system takes: a segment of at most NAME_MAX bytes, a path of PATH_MAX.
NAME_MAX = 255
PATH_MAX = 4096


def name_problem(name: str) -> str | None:
    """Why NAME (a relative, '/'-separated name from outside) cannot become a path inside a
    tree, or None when it can. Trailing '/' (a prefix) is allowed; nothing else empty is."""
    if not name:
        return "is an empty name"
    if "\x00" in name:
        return "holds a NUL character, which no file name takes"
    if name.startswith("/"):
        return "is an absolute name (it would leave the tree it belongs to)"
    encoded = name.encode("utf-8", "surrogateescape")
    if len(encoded) > PATH_MAX:
        return f"is longer than {PATH_MAX} bytes, more than a file system takes"
    for segment in name.rstrip("/").split("/"):
        if segment in ("", ".", ".."):
            shown = "an empty" if not segment else f"a {segment!r}"
            return f"has {shown} segment (it could leave the tree it belongs to)"
        if len(segment.encode("utf-8", "surrogateescape")) > NAME_MAX:
            return f"has a segment longer than {NAME_MAX} bytes, more than a file system takes"
    return None


def checked_name(name: str, source: str | os.PathLike[str]) -> PurePosixPath:
    """NAME as a relative path, or InputError naming SOURCE (the URL, label or manifest it
    came from) and why it cannot be a path inside a tree."""
    problem = name_problem(name)
    if problem is not None:
        raise InputError(source, f"the name {name!r} {problem}")
    return PurePosixPath(name.rstrip("/"))


def contained(path: Path, root: Path) -> Path | None:
    """`path` if, every symbolic link resolved, it lies inside `root` (resolved the same way).

    The one containment rule for paths in hand: what a name or a link reaches outside the
    tree the user gave is neither read, written nor delivered."""
    real, top = os.path.realpath(path), os.path.realpath(root)
    return path if real == top or real.startswith(top.rstrip(os.sep) + os.sep) else None


def inside(root: Path, name: str, source: str | os.PathLike[str]) -> Path:
    """ROOT / NAME for a NAME from outside, refused (InputError naming SOURCE) when the name
    is not a plain relative name or, links resolved, the path leaves ROOT."""
    path = root.joinpath(*checked_name(name, source).parts)
    if contained(path, root) is None:
        raise InputError(source, f"the name {name!r} leads outside {root} through a symbolic link")
    return path


def link_leaves(path: Path, root: Path) -> bool:
    """Whether PATH is a symbolic link whose target lies outside ROOT (or is dangling there)."""
    return path.is_symlink() and contained(path, root) is None


__all__ = ["NAME_MAX", "PATH_MAX", "checked_name", "contained", "inside", "link_leaves", "name_problem"]
