"""`pdsgen migrate s3://BUCKET/VOLUME -o s3://BUCKET/BUNDLE` (a real S3 server on 127.0.0.1): the
bundle in the bucket is the one the same migration writes on disk, file for file, and a migration
in place in the bucket leaves every published byte of the volume."""

from __future__ import annotations

from pathlib import Path

from click.testing import CliRunner

from pdsgen.cli import main

VOLUME = Path(__file__).parent / "data" / "volume_fbirtfspec"


def _invoke(*args: object) -> str:
    result = CliRunner().invoke(main, [str(a) for a in args])
    assert result.exit_code == 0, result.output
    return result.output


def _local_tree(root: Path) -> dict[str, bytes]:
    return {p.relative_to(root).as_posix(): p.read_bytes() for p in sorted(root.rglob("*")) if p.is_file()}


def test_a_volume_in_a_bucket_becomes_the_same_bundle_as_on_disk(s3_server, tmp_path):
    bucket = s3_server.new_bucket()
    volume = _local_tree(VOLUME)
    for name, data in volume.items():
        s3_server.put(bucket, f"SBN_0233/{name}", data)
    shown = _invoke("migrate", f"s3://{bucket}/SBN_0233", "-o", f"s3://{bucket}/bundle",
                    "--bundle-lid", "urn:nasa:pds:fbirtfspec")
    assert f"s3://{bucket}/bundle" in shown and "/tmp" not in shown  # paths as the user named them
    _invoke("migrate", VOLUME, "-o", tmp_path / "bundle", "--bundle-lid", "urn:nasa:pds:fbirtfspec")
    remote, local = s3_server.tree(bucket, "bundle/"), _local_tree(tmp_path / "bundle")
    assert sorted(remote) == sorted(local)
    assert {name for name in remote if remote[name] != local[name]} == set()
    for name, data in volume.items():
        assert remote[name] == data, name  # every file of the volume, byte-identical

    _invoke("migrate", f"s3://{bucket}/SBN_0233/", "--in-place", "--bundle-lid", "urn:nasa:pds:fbirtfspec")
    in_place = s3_server.tree(bucket, "SBN_0233/")
    assert all(in_place[name] == data for name, data in volume.items())
    assert "bundle_fbirtfspec.xml" in in_place and "data/fieberbeyer2010/1358.xml" in in_place
