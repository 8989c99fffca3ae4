"""Where a path points: a local file, or an object in an S3-compatible bucket.

pdsgen keeps one internal form for an object: GDAL's own `/vsis3/BUCKET/KEY`. It is a
plain POSIX path, so `pathlib` joins, splits and resolves it without losing anything
(`s3://` would lose a slash), every raster reader hands it to GDAL unchanged, and GDAL
reads it with range requests. Users write `s3://BUCKET/KEY` (or GDAL's form); messages
show `s3://` again. HTTP(S) URLs are read-only and go to GDAL as `/vsicurl/URL`.

Credentials and endpoints come as AWS's own tools take them (AWS_ACCESS_KEY_ID,
AWS_SECRET_ACCESS_KEY, AWS_SESSION_TOKEN, AWS_PROFILE, AWS_DEFAULT_REGION,
AWS_ENDPOINT_URL_S3 / AWS_ENDPOINT_URL); `gdal_environment` passes the endpoint on in
GDAL's words, for the block that reads. This module imports no S3 client: the base install reads through GDAL.
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import PurePosixPath
from urllib.parse import urlsplit

GDAL_S3 = "/vsis3/"
GDAL_HTTP = "/vsicurl/"
S3_SCHEME = "s3://"
_HTTP_SCHEMES = ("http://", "https://")
_INTERNAL_S3 = re.compile(r"/vsis3/(?=[^/\s:'\"])")
_COLLAPSED_URL = re.compile(r"^/vsicurl/(https?):/(?!/)")


def is_remote(path: str | os.PathLike[str] | None) -> bool:
    """Whether PATH names an object (s3://, /vsis3/) or a web resource rather than a local file."""
    if path is None:
        return False
    text = os.fspath(path)
    return text.startswith((S3_SCHEME, GDAL_S3, GDAL_HTTP, *_HTTP_SCHEMES))


def is_s3(path: str | os.PathLike[str] | None) -> bool:
    """Whether PATH names an object or prefix in an S3-compatible bucket."""
    return path is not None and os.fspath(path).startswith((S3_SCHEME, GDAL_S3))


def internal(path: str | os.PathLike[str]) -> str:
    """The form pdsgen passes around: `/vsis3/BUCKET/KEY` for S3, `/vsicurl/URL` for HTTP(S),
    a local path unchanged. Every command calls it on each path it is given."""
    text = os.fspath(path)
    if text.startswith(S3_SCHEME):
        return GDAL_S3 + text[len(S3_SCHEME):]
    if text.startswith(_HTTP_SCHEMES):
        return GDAL_HTTP + text
    return _COLLAPSED_URL.sub(r"/vsicurl/\1://", text)  # pathlib.Path made "https://" "https:/"


def display(path: str | os.PathLike[str]) -> str:
    """PATH as a person writes it: `s3://BUCKET/KEY` for an object."""
    text = internal(path)
    if text.startswith(GDAL_S3):
        return S3_SCHEME + text[len(GDAL_S3):]
    if text.startswith(GDAL_HTTP):
        return text[len(GDAL_HTTP):]
    return text


def display_text(text: str) -> str:
    """A message with each internal `/vsis3/` path written as `s3://`."""
    return _INTERNAL_S3.sub(S3_SCHEME, text)


@dataclass(frozen=True)
class S3Location:
    """An object or prefix: BUCKET and KEY (no leading slash; empty for a bucket's top)."""

    bucket: str
    key: str

    @classmethod
    def parse(cls, path: str | os.PathLike[str]) -> S3Location:
        text = internal(path)
        if not text.startswith(GDAL_S3):
            raise ValueError(f"{display(text)}: not an s3:// location")
        bucket, _, key = text[len(GDAL_S3):].partition("/")
        return cls(bucket, key)

    @property
    def url(self) -> str:
        return f"{S3_SCHEME}{self.bucket}/{self.key}"

    @property
    def path(self) -> PurePosixPath:
        """The internal form, as a path other code joins names onto."""
        return PurePosixPath(f"{GDAL_S3}{self.bucket}/{self.key}".rstrip("/"))

    @property
    def prefix(self) -> str:
        """KEY as a "directory": empty, or ending in one slash."""
        key = self.key.strip("/")
        return f"{key}/" if key else ""

    def child(self, relative: str) -> S3Location:
        return S3Location(self.bucket, self.prefix + relative)


def endpoint_url() -> str | None:
    """The S3 endpoint the user set for AWS's tools (None: AWS itself)."""
    return os.environ.get("AWS_ENDPOINT_URL_S3") or os.environ.get("AWS_ENDPOINT_URL") or None


def gdal_options(environ: dict[str, str] | None = None) -> dict[str, str]:
    """GDAL configuration options that follow from the AWS variables (the endpoint's host,
    its scheme, path-style addressing for non-AWS stores, the region); options the user set
    in GDAL's own words are left out, so they keep winning."""
    env = os.environ if environ is None else environ
    options: dict[str, str] = {}
    endpoint = env.get("AWS_ENDPOINT_URL_S3") or env.get("AWS_ENDPOINT_URL")
    if endpoint:
        parts = urlsplit(endpoint if "://" in endpoint else f"https://{endpoint}")
        options["AWS_S3_ENDPOINT"] = parts.netloc + parts.path.rstrip("/")
        options["AWS_HTTPS"] = "NO" if parts.scheme == "http" else "YES"
        options["AWS_VIRTUAL_HOSTING"] = "FALSE"  # MinIO, Ceph, moto: bucket in the path
    if env.get("AWS_DEFAULT_REGION"):
        options["AWS_REGION"] = env["AWS_DEFAULT_REGION"]
    return {name: value for name, value in options.items() if name not in env}


@contextmanager
def gdal_environment() -> Iterator[None]:
    """GDAL configured with `gdal_options` inside the block only (rasterio.Env), so a
    program calling pdsgen finds its environment and GDAL's configuration as they were.

    Read from the AWS variables each time, in this process or a batch job's (which
    inherits them); with none set there is nothing to configure and no Env is entered."""
    options = gdal_options()
    if not options:
        yield
        return
    import rasterio  # the remote case only: the base commands and --version do not pay for it

    with rasterio.Env(**options):
        yield


__all__ = ["S3Location", "display", "display_text", "endpoint_url", "gdal_environment", "gdal_options",
           "internal", "is_remote", "is_s3"]
