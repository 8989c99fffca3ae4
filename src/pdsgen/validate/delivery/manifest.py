"""DLV-020/021: MD5SUMS.TXT against the files of the delivery (MD5s streamed by
formats/checksum.py); DLV-030: what the delivery holds that is no file."""

from __future__ import annotations

from ...archive import layout
from .model import DeliveryModel
from .parts import Found, all_files, irregular_files, named_inside


def check_manifest(model: DeliveryModel, labels_only: bool, found: list[Found]) -> None:
    """DLV-020: each line of MD5SUMS.TXT names a file of the delivery with that MD5; DLV-021:
    every file of the delivery is listed."""
    from ...formats.checksum import file_md5  # start-up: loaded only when a delivery is checked

    root = model.root
    for irregular in irregular_files(root):  # DLV-030, whether or not a manifest lists it
        found.append(Found("DLV-030", irregular, "is not a regular file of the delivery (a FIFO, socket, "
                                                 "device, or a link dangling or leading outside): an archive "
                                                 "holds files only; never read"))
    manifest = root / layout.MANIFEST
    if not manifest.is_file():
        return
    listed: dict[str, int] = {}
    for number, digest, name in ((m.number, m.digest, m.name) for m in model.manifest()):
        if digest is None:
            found.append(Found("DLV-020", manifest, f"not an 'md5  path' line: {name[:60]!r}", number))
            continue
        listed[name] = number
        path, problem = named_inside(root, name)
        if path is None:  # never read (/dev/zero, ../x): named only
            found.append(Found("DLV-020", manifest, f"{name!r} is not a file inside the delivery ({problem})",
                                number))
        elif not path.is_file():
            what = "is not a regular file" if path.exists() else "does not exist"
            found.append(Found("DLV-020", manifest, f"{name} is listed but {what}", number))
        elif not labels_only and file_md5(path) != digest:
            found.append(Found("DLV-020", path, f"MD5 differs from {layout.MANIFEST} line {number}: the file "
                                                 "changed after the manifest was written; to mend, run pdsgen "
                                                 "deliver again: it rewrites the manifest and keeps text written "
                                                 "into AAREADME.TXT, VOLDESC.CAT or the bundle label (a delivery "
                                                 "text file, [delivery] table, keeps it for good)"))
    for path in all_files(root):
        name = path.relative_to(root).as_posix()
        if name not in (layout.MANIFEST, layout.MANIFEST_LABEL, layout.RELEASED_MARKER) \
                and not layout.is_review_page(name) \
                and name not in listed:
            found.append(Found("DLV-021", path, f"not listed in {layout.MANIFEST}"))

