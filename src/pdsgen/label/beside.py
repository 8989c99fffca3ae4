"""Finding a file a PDS3 label names, beside the label, with the PDS case rules.

PDS file names are case-sensitive on most systems an archive is served from, so a look-up
tells the exact name from a name differing only in case (the validator reports the near
miss; readers use it). Each directory is listed once while it is unchanged, for all the
labels in it: the validator, deliver, migration and Extras all look files up here.

Containment: a label is text someone else wrote, so a name in it (../x, /etc/x, a symbolic
link beside it that points away) must never make pdsgen read or copy a file outside the
directory tree it was given. storage/containment.contained is the one rule, and every look-up here applies it:
a file outside the tree is not found (`outside_tree` says where it would have been, for the
validator's finding and the one-line refusals).
"""

from __future__ import annotations

import os
import time
from collections import OrderedDict
from collections.abc import Iterator
from functools import lru_cache
from pathlib import Path

from ..storage.containment import contained


class DirectoryNames:
    """The names in one directory, with their case-folded index, so a look-up is one hash.

    A label's look-up of the file beside it used to scan the names; with N products in a
    directory that is N^2 comparisons, on top of N listings."""

    __slots__ = ("names", "_set", "_folded")

    def __init__(self, names: list[str]) -> None:
        self.names = names
        self._set = frozenset(names)
        self._folded: dict[str, list[str]] = {}
        for name in names:
            self._folded.setdefault(name.lower(), []).append(name)

    def __contains__(self, name: object) -> bool:
        return name in self._set

    def __iter__(self) -> Iterator[str]:
        return iter(self.names)

    def __len__(self) -> int:
        return len(self.names)

    def same_but_case(self, name: str) -> list[str]:
        """The names equal to `name` ignoring case, in listing order (`name` itself included)."""
        return self._folded.get(name.lower(), [])


# Listings kept per process (each --jobs worker has its own), by directory, with the
# directory's mtime when listed: every look-up stats the directory and lists it again when a
# name was added, removed or renamed since, so a file that appears during a run is seen as
# when each label listed its directory. A listing made less than _SETTLE_NS after the
# directory's last change is not trusted (a change within the same timestamp tick would
# leave the mtime as it was) and is made again at the next look-up.
_LISTINGS: OrderedDict[str, tuple[int, int, DirectoryNames]] = OrderedDict()
_MAX_LISTINGS = 256
_SETTLE_NS = 1_000_000_000


def directory_listing(directory: Path) -> DirectoryNames:
    """The names in `directory` (none if it cannot be read), listed once while it is unchanged."""
    key = os.path.abspath(directory)  # a relative name is another directory after a chdir
    try:
        mtime = os.stat(key).st_mtime_ns
    except OSError:
        return DirectoryNames([])
    cached = _LISTINGS.get(key)
    if cached is not None and cached[0] == mtime and cached[1] - mtime >= _SETTLE_NS:
        _LISTINGS.move_to_end(key)
        return cached[2]
    listed_at = time.time_ns()
    try:
        names = DirectoryNames(os.listdir(key))
    except OSError:
        return DirectoryNames([])
    _LISTINGS[key] = (mtime, listed_at, names)
    _LISTINGS.move_to_end(key)
    while len(_LISTINGS) > _MAX_LISTINGS:
        _LISTINGS.popitem(last=False)
    return names


def trusted_tree(label: Path, given: Path | None = None, root: Path | None = None) -> Path:
    """The tree the files a label names must stay inside: the directory the user gave (`given`,
    when the label was found in it), else the label's own directory; widened to `root` (the
    root the user names) when the label lies inside it. A genuine volume's labels name
    ../../LABEL/X.FMT, so a volume checked whole, or a label with the volume as its root, keeps
    its format files; a root never narrows the tree, and a label outside it keeps its own."""
    base = given if given is not None else label.parent
    if root is not None and contained(label, root) is not None and contained(base, root) is not None:
        return root
    return base


def resolve_beside(directory: Path, listing: DirectoryNames, file_name: str,
                   root: Path | None = None) -> tuple[Path | None, Path | None]:
    """(exact path, path differing only in case) of a file named by a label in `directory`,
    inside `root` (the tree the user gave; the label's directory unless told).

    PDS file names are case-sensitive on most systems an archive is served from,
    so a near miss in case is reported rather than silently accepted.
    """
    tree = directory if root is None else root
    if "/" in file_name or os.sep in file_name:
        named = directory / file_name
        return (named, None) if named.is_file() and contained(named, tree) else (None, None)
    if file_name in listing and (directory / file_name).is_file():
        return contained(directory / file_name, tree), None
    for name in listing.same_but_case(file_name):
        if (directory / name).is_file() and contained(directory / name, tree):
            return None, directory / name
    return None, None


def outside_tree(directory: Path, file_name: str, root: Path | None = None) -> Path | None:
    """The file a label in `directory` names when it exists outside `root` (the label's
    directory unless told), so it is refused: a name that climbs out (../x), an absolute one,
    or links leading out; None when it is inside or missing (nothing is read then: a genuine
    label-only copy of a volume, naming ../../LABEL/X.FMT, is not an error of containment)."""
    tree = directory if root is None else root
    path = directory / file_name
    try:
        exists = path.exists()
    except (OSError, ValueError):  # a NUL or an over-long name: nothing to refuse
        return None
    return path if exists and contained(path, tree) is None else None


def find_beside(directory: Path, file_name: str, root: Path | None = None) -> Path | None:
    """The file a label in `directory` names: the exact name, else one differing only in case;
    only inside `root` (the label's directory unless told)."""
    exact, other = resolve_beside(directory, directory_listing(directory), file_name, root)
    return exact or other


# -- reference pointers: where a volume keeps the files they name -------------------------------
# A reference pointer names a file kept elsewhere in an archive: a format file (^STRUCTURE), a
# catalog file (^DATA_SET_CATALOG ...), a document (^DESCRIPTION), an index table (^INDEX). A
# PDS3 volume keeps them in its LABEL, CATALOG, DOCUMENT and INDEX directories, and a label in
# DATA/X/ names "T.FMT" without a path: a reader looks beside the label first, then in the
# volume's directory for that kind of pointer (NASA's PDS3 tools resolve so: StandardPathResolver).

# The volume directory a reference pointer's file is kept in, by the pointer's last word.
VOLUME_DIRECTORIES = {"STRUCTURE": "LABEL", "CATALOG": "CATALOG", "DESCRIPTION": "DOCUMENT", "INDEX": "INDEX"}


def pointer_kind(keyword: str) -> str | None:
    """STRUCTURE, CATALOG, DESCRIPTION or INDEX for ^X or ^..._X (NASA's rule: the name, or a
    name ending in _X; ^DATA_SET_MAP_PROJECTION names a catalog file too); None otherwise."""
    name = keyword.upper().lstrip("^")
    if name == "DATA_SET_MAP_PROJECTION":
        return "CATALOG"
    return next((kind for kind in VOLUME_DIRECTORIES if name == kind or name.endswith("_" + kind)), None)


# Pointers whose file's statements become part of the label (NASA's IncludePointer kinds).
INCLUDE_KINDS = ("STRUCTURE", "CATALOG")


def is_include(keyword: str) -> bool:
    """^STRUCTURE, ^CATALOG, ^..._STRUCTURE, ^..._CATALOG: the file named is part of the label."""
    name = keyword.upper().lstrip("^")
    return any(name == kind or name.endswith("_" + kind) for kind in INCLUDE_KINDS)


def find_reference(directory: Path, name: str, kind: str | None, tree: Path, volume: Path | None = None
                   ) -> Path | None:
    """The file a reference pointer of `kind` in a label in `directory` names: beside the
    label (or at the path it gives: ../../LABEL/T.FMT), else in the directory for the kind
    (LABEL/, CATALOG/, DOCUMENT/, INDEX/) of its volume's root (`volume`, else found by
    `volume_root`). A pointer of no kind (^TEXT ...): beside the label only. Never outside `tree`."""
    found = find_beside(directory, name, tree)
    if found is not None or "/" in name or kind is None:
        return found
    root = volume if volume is not None else volume_root(directory, tree)[0]
    folder = VOLUME_DIRECTORIES[kind]
    return find_beside(root / folder, name, tree) if folder in directory_listing(root) else None


def volume_root(directory: Path, tree: Path) -> tuple[Path, bool]:
    """(root, whole) of the volume a label in `directory` belongs to: the nearest directory from
    it up to `tree` holding VOLDESC.CAT (whole: a volume given whole), else `tree` itself."""
    for place in volume_ancestors(directory, tree):
        if "VOLDESC.CAT" in directory_listing(place):
            return place, True
    return _real_directory(tree), False


def _real_directory(path: str | os.PathLike[str]) -> Path:
    """A directory with its links resolved, remembered: the candidates a volume search visits
    (every file found is still checked by `contained` when it is found). Remembered by its
    absolute path: a relative one names another directory once the process changes directory."""
    return _resolved(os.path.abspath(path))


@lru_cache(maxsize=1024)
def _resolved(absolute: str) -> Path:
    return Path(os.path.realpath(absolute))


def volume_ancestors(directory: Path, tree: Path) -> Iterator[Path]:
    """`directory` and its parents, up to and including `tree` (never above it), links resolved:
    each path is resolved once (a label's look-ups run for every label of a volume)."""
    place, top = _real_directory(directory), _real_directory(tree)
    if place != top and top not in place.parents:
        return
    while True:
        yield place
        if place == top:
            return
        place = place.parent
