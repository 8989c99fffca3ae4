"""A cluster's worker reads a run's files at their absolute names and hands back what it found
under the names the client gave (validate/partitions.ClientPaths): the report of a run on a
cluster must read as the one-process run's, byte for byte, without the worker ever changing its
own directory."""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

from pdsgen.validate.model import Finding
from pdsgen.validate.partitions import ClientPaths
from pdsgen.validate.report import FileReport

CLIENT = "/home/user/archive"


@dataclass
class _Facts:
    path: Path
    described: list[Path] = field(default_factory=list)
    pair: tuple[str, int] = ("", 0)


def test_a_relative_name_is_read_at_the_clients_directory():
    paths = ClientPaths(CLIENT)
    assert paths.absolute(("bundle/data/p.xml", "bundle")) == (f"{CLIENT}/bundle/data/p.xml", f"{CLIENT}/bundle")
    assert paths.absolute(("../other/p.xml", None)) == (f"{CLIENT}/../other/p.xml", None)
    assert paths.absolute(("/srv/bundle/p.xml", "/srv/bundle")) == ("/srv/bundle/p.xml", "/srv/bundle")


def test_what_comes_back_names_the_files_as_given():
    paths = ClientPaths(CLIENT)
    item = ("bundle/data/p.xml", "bundle")
    read = paths.absolute(item)[0]
    report = FileReport(read, [Finding("PDS4-053", "error", f"{CLIENT}/bundle/data/p.tab",
                                       f"record 3: see {CLIENT}/bundle/data/p.tab", 55, "maximum")])
    facts = {"reader": _Facts(Path(read), [Path(f"{CLIENT}/bundle/data/p.tab")], (read, 7))}
    mapped_report, mapped_facts = paths.as_given(item, (report, facts))
    assert mapped_report == FileReport("bundle/data/p.xml", [Finding("PDS4-053", "error", "bundle/data/p.tab",
                                                                     "record 3: see bundle/data/p.tab", 55,
                                                                     "maximum")])
    assert mapped_facts == {"reader": _Facts(Path("bundle/data/p.xml"), [Path("bundle/data/p.tab")],
                                             ("bundle/data/p.xml", 7))}


def test_a_name_above_the_clients_directory_comes_back_as_given():
    paths = ClientPaths(CLIENT)
    item = ("../other/p.xml", None)
    read = paths.absolute(item)[0]
    assert os.path.isabs(read)
    assert paths.as_given(item, FileReport(str(Path(read).parent / "p.tab"))) == FileReport("../other/p.tab")


def test_an_absolute_name_comes_back_untouched():
    """Given absolutely, even inside the client's directory, a name is what the user gave."""
    paths = ClientPaths(CLIENT)
    item = (f"{CLIENT}/bundle/p.xml", None)
    report = FileReport(f"{CLIENT}/bundle/p.xml", [Finding("X-001", "error", f"{CLIENT}/bundle/p.tab", "m")])
    assert paths.as_given(item, report) == report
