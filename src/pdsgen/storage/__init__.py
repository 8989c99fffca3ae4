"""Object storage: products read from and written into S3-compatible buckets.

One home for everything pdsgen knows about locations that are not local files; each
command calls it at its boundary (see areas.py), and writers never see a URL they must
understand. The S3 client (boto3) is the optional extra `pdsgen[s3]`; without it pdsgen
still reads objects through GDAL's /vsis3/.

For a command being added (e.g. one that merges many inputs into one product), taking
an s3:// input or OUTDIR is three lines::

    from pdsgen import storage

    inputs = [storage.raster_input(p) for p in inputs]      # GDAL reads objects in place
    with storage.output_area(outdir, overwrite) as area:    # staging dir, uploaded on success
        product = write_something(inputs, area.directory, ...)
        lines = area.shown([summary_line(product)])         # URLs, not staging paths
"""

from __future__ import annotations

from .areas import OutputArea, explain_unreadable, local_inputs, output_area, raster_input, tree_area
from .locations import S3Location, display, display_text, gdal_environment, internal, is_remote, is_s3

__all__ = ["OutputArea", "S3Location", "display", "display_text", "explain_unreadable", "gdal_environment", "internal",
           "is_remote",
           "is_s3", "local_inputs", "output_area", "raster_input", "tree_area"]
