"""A volume whose VOLDESC.CAT or index label is a symbolic link leading out of the volume is
refused in one line naming the link, and nothing is written: the file outside is neither
read nor delivered (the one containment rule, storage/containment.contained)."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from pdsgen.errors import InputError
from pdsgen.migrate.volume import migrate_volume

VOLUME = Path(__file__).parent / "data" / "volume_fbirtfspec"


def _refused(volume: Path, out: Path, link: Path) -> None:
    with pytest.raises(InputError) as refused:
        migrate_volume(volume, out, bundle_lid="urn:nasa:pds:fbirtfspec")
    assert str(refused.value) == f"{link}: is a symbolic link to a file outside {volume}; it is not taken"
    assert not out.exists()


def test_a_voldesc_linked_from_outside_the_volume_is_not_read(tmp_path):
    volume = tmp_path / "SBN_0233"
    shutil.copytree(VOLUME, volume)
    outside = tmp_path / "outside.cat"
    shutil.move(volume / "voldesc.cat", outside)
    (volume / "voldesc.cat").symlink_to(outside)
    _refused(volume, tmp_path / "bundle", volume / "voldesc.cat")


def test_an_index_label_linked_from_outside_the_volume_is_not_read(tmp_path):
    volume = tmp_path / "SBN_0233"
    shutil.copytree(VOLUME, volume)
    outside = tmp_path / "elsewhere"
    outside.mkdir()
    shutil.move(volume / "index" / "index.lbl", outside / "index.lbl")
    shutil.copy(volume / "index" / "index.tab", outside / "index.tab")
    (volume / "index" / "index.lbl").symlink_to(outside / "index.lbl")
    _refused(volume, tmp_path / "bundle", volume / "index" / "index.lbl")
