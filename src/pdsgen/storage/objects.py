"""Talking to the bucket: existence, listing, download, upload, delete - through boto3.

Why boto3 (the optional extra `pdsgen[s3]`) and not GDAL's /vsis3/ alone or fsspec/s3fs:
GDAL reads rasters well but cannot write a product without a local file (its /vsis3/
writes are sequential, one format at a time, and PDS3 .IMG/.LBL and JP2 writers here are
Python), reports a missing bucket and a wrong key alike as "No such file", and has no
listing with sizes and times that resume needs. boto3 says which of bucket, key or
credentials is wrong, uploads large files in parts (and aborts a failed upload, so no
object appears), and reads the AWS variables and profiles exactly as the AWS CLI does.
s3fs adds an async layer and a second configuration surface over the same botocore,
for nothing pdsgen needs. Reading rasters stays with GDAL (range requests).
"""

from __future__ import annotations

import functools
import os
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType
from typing import Any

from ..errors import InputError, OutputError, PdsgenError
from .locations import S3Location, endpoint_url

MISSING_CLIENT = "reading and writing s3:// needs boto3: pip install 'pdsgen[s3]'"
# Files above this size are uploaded in parts of this size (S3 allows at most 10,000 parts).
MULTIPART_BYTES = 64 * 1024 * 1024


@dataclass(frozen=True)
class ObjectInfo:
    """One object: where it is, its size and its last-modified time (ns since the epoch)."""

    location: S3Location
    size: int
    mtime_ns: int


@contextmanager
def boto3_kept_from_rasterio() -> Iterator[None]:
    """Inside the block (a pdsgen command in its own process, a batch job's process), a first
    `import rasterio` finds no boto3; on leaving, the process's modules are as they were (but
    for what was imported). Nothing is hidden if rasterio or boto3 is loaded already.

    rasterio imports boto3 whenever it is installed (the s3 extra; moto brings it into a test
    environment too) to offer its AWSSession: some 230 modules and a sixth of a second on every
    command, even a local one. pdsgen does not need it: GDAL reads the AWS variables itself
    (locations.gdal_environment adds the endpoint), which is rasterio's own fallback. rasterio
    decides once, when its `session` module is imported. The client below imports boto3 all
    the same (`_import_boto3`). This module is the only one that touches sys.modules for it."""
    hidden = "rasterio" not in sys.modules and "boto3" not in sys.modules
    if hidden:
        sys.modules["boto3"] = None  # type: ignore[assignment]  # `import boto3` raises ImportError
    try:
        yield
    finally:
        if hidden and "boto3" in sys.modules and sys.modules["boto3"] is None:
            del sys.modules["boto3"]


def _import_boto3() -> ModuleType:
    """boto3 itself, also inside `boto3_kept_from_rasterio` (rasterio has chosen by then)."""
    if "boto3" in sys.modules and sys.modules["boto3"] is None:
        del sys.modules["boto3"]
    import boto3

    return boto3


@functools.lru_cache(maxsize=8)
def _client(endpoint: str | None, profile: str | None, identity: tuple[str | None, ...]) -> Any:
    """One boto3 client per endpoint and identity (they are thread-safe and slow to make)."""
    try:
        boto3 = _import_boto3()
        from botocore.config import Config
    except ImportError:
        raise PdsgenError(None, MISSING_CLIENT) from None
    session = boto3.session.Session(profile_name=profile)
    config = Config(retries={"max_attempts": 3, "mode": "standard"}, connect_timeout=10, read_timeout=60)
    return session.client("s3", endpoint_url=endpoint, config=config)


def client() -> Any:
    """The S3 client for the AWS variables now set."""
    identity = tuple(os.environ.get(f"AWS_{name}") for name in ("ACCESS_KEY_ID", "SECRET_ACCESS_KEY", "SESSION_TOKEN"))
    return _client(endpoint_url(), os.environ.get("AWS_PROFILE") or None, identity)


def problem(exc: BaseException, location: S3Location, reading: bool = True) -> PdsgenError:
    """A client failure as one line naming the URL: no such bucket or key, access denied,
    endpoint unreachable, no credentials."""
    from botocore.exceptions import ClientError, EndpointConnectionError, NoCredentialsError

    kind = InputError if reading else OutputError
    if isinstance(exc, NoCredentialsError):
        return kind(location.url, "no credentials: set AWS_ACCESS_KEY_ID and AWS_SECRET_ACCESS_KEY, or AWS_PROFILE")
    if isinstance(exc, EndpointConnectionError):
        return kind(location.url, f"cannot reach the S3 endpoint ({endpoint_url() or 'AWS'})")
    if isinstance(exc, ClientError):
        code = str(exc.response.get("Error", {}).get("Code", ""))
        if code == "NoSuchBucket":
            return kind(location.url, f"no such bucket: {location.bucket}")
        if code in ("404", "NoSuchKey", "NotFound"):
            return kind(location.url, "no such object")
        if code in ("403", "AccessDenied", "InvalidAccessKeyId", "SignatureDoesNotMatch", "InvalidToken",
                    "ExpiredToken"):
            return kind(location.url, f"access denied ({code}): check the AWS credentials")
        return kind(location.url, f"S3 error {code}: {exc.response.get('Error', {}).get('Message', '')}".strip())
    return kind(location.url, f"S3 request failed ({str(exc).splitlines()[0] if str(exc) else type(exc).__name__})")


def _errors() -> tuple[type[BaseException], ...]:
    """The client's errors, to catch; none without the client (boto3 brings botocore), whose
    absence `client()` has then said in one line that this must not replace."""
    try:
        from botocore.exceptions import BotoCoreError, ClientError
    except ImportError:
        return ()
    return (BotoCoreError, ClientError)


_BUCKETS_SEEN: set[tuple[str | None, str]] = set()  # (endpoint, bucket) found to exist by this process


def check_bucket(location: S3Location, reading: bool = True) -> None:
    """One line if the bucket is missing, forbidden or unreachable (asked once per process
    and bucket while it answers: a batch job process makes many products in one bucket)."""
    if (endpoint_url(), location.bucket) in _BUCKETS_SEEN:
        return
    s3 = client()
    try:
        s3.head_bucket(Bucket=location.bucket)
    except _errors() as exc:
        code = str(getattr(exc, "response", {}).get("Error", {}).get("Code", ""))
        if code in ("404", "NoSuchBucket", "NotFound"):
            kind = InputError if reading else OutputError
            raise kind(location.url, f"no such bucket: {location.bucket}") from None
        raise problem(exc, location, reading) from None
    _BUCKETS_SEEN.add((endpoint_url(), location.bucket))


def stat(location: S3Location) -> ObjectInfo | None:
    """The object's size and time, or None if there is no such object (a missing bucket,
    refused credentials or an unreachable endpoint are errors, not "missing")."""
    try:
        head = client().head_object(Bucket=location.bucket, Key=location.key)
    except _errors() as exc:
        code = str(getattr(exc, "response", {}).get("Error", {}).get("Code", ""))
        if code in ("404", "NoSuchKey", "NotFound"):
            check_bucket(location)
            return None
        raise problem(exc, location) from None
    return ObjectInfo(location, int(head["ContentLength"]), int(head["LastModified"].timestamp() * 1e9))


def require_object(location: S3Location) -> ObjectInfo:
    """The object's info, or one line saying why it cannot be read."""
    info = stat(location)
    if info is None:
        raise InputError(location.url, "no such object")
    return info


def list_objects(location: S3Location, recursive: bool = True) -> Iterator[ObjectInfo]:
    """Every object under LOCATION taken as a directory (its key and a slash), in key order;
    not `recursive`: only those directly in it, as a directory listing."""
    paginator = client().get_paginator("list_objects_v2")
    delimiter = {} if recursive else {"Delimiter": "/"}
    try:
        for page in paginator.paginate(Bucket=location.bucket, Prefix=location.prefix, **delimiter):
            for item in page.get("Contents", []):
                yield ObjectInfo(S3Location(location.bucket, item["Key"]), int(item["Size"]),
                                 int(item["LastModified"].timestamp() * 1e9))
    except _errors() as exc:
        raise problem(exc, location) from None


def read_if_there(location: S3Location) -> bytes | None:
    """The object's bytes, or None if there is no such object."""
    try:
        return bytes(client().get_object(Bucket=location.bucket, Key=location.key)["Body"].read())
    except _errors() as exc:
        if str(getattr(exc, "response", {}).get("Error", {}).get("Code", "")) in ("404", "NoSuchKey", "NotFound"):
            return None
        raise problem(exc, location) from None


def read_bytes(location: S3Location) -> bytes:
    try:
        return bytes(client().get_object(Bucket=location.bucket, Key=location.key)["Body"].read())
    except _errors() as exc:
        raise problem(exc, location) from None


def put_bytes(location: S3Location, data: bytes) -> None:
    """Write a small object whole (a PUT is atomic: readers see the old or the new one)."""
    try:
        client().put_object(Bucket=location.bucket, Key=location.key, Body=data)
    except _errors() as exc:
        raise problem(exc, location, reading=False) from None


def download(location: S3Location, target: Path) -> None:
    target.parent.mkdir(parents=True, exist_ok=True)
    try:
        client().download_file(location.bucket, location.key, str(target))
    except _errors() as exc:
        raise problem(exc, location) from None


def upload(source: Path, location: S3Location) -> None:
    """Upload a complete local file; above MULTIPART_BYTES in parts (a failed multipart
    upload is aborted by boto3, so no object appears)."""
    from boto3.s3.transfer import TransferConfig

    config = TransferConfig(multipart_threshold=MULTIPART_BYTES, multipart_chunksize=MULTIPART_BYTES)
    try:
        client().upload_file(str(source), location.bucket, location.key, Config=config)
    except _errors() as exc:
        raise problem(exc, location, reading=False) from None
    except Exception as exc:  # boto3's S3UploadFailedError wraps the ClientError as text
        raise OutputError(location.url, f"upload failed ({str(exc).splitlines()[0]})") from None


def delete(location: S3Location) -> None:
    try:
        client().delete_object(Bucket=location.bucket, Key=location.key)
    except _errors() as exc:
        raise problem(exc, location, reading=False) from None
