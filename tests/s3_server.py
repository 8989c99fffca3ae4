"""A real S3 server on 127.0.0.1 for the object-storage tests: moto's server, in its own
process, with authentication on (so a wrong secret key is refused as by AWS).

The session fixture `s3_server` starts it on a free port, creates an IAM user allowed
everything and its access key, and exports them with the endpoint as AWS's tools take
them (AWS_ACCESS_KEY_ID, AWS_SECRET_ACCESS_KEY, AWS_ENDPOINT_URL, AWS_DEFAULT_REGION);
pdsgen, its child processes and GDAL find the server from those variables alone.
"""

from __future__ import annotations

import json
import os
import shutil
import socket
import subprocess
import sys
import time
import uuid
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest

# Requests moto serves before it starts checking signatures: creating the user, its policy and its key.
_SET_UP_REQUESTS = 3


@dataclass
class S3Server:
    endpoint: str
    key_id: str
    secret: str
    client: Any  # boto3 S3 client with the valid key

    def new_bucket(self) -> str:
        name = f"pdsgen-{uuid.uuid4().hex[:12]}"
        self.client.create_bucket(Bucket=name)
        return name

    def put(self, bucket: str, key: str, data: bytes) -> str:
        self.client.put_object(Bucket=bucket, Key=key, Body=data)
        return f"s3://{bucket}/{key}"

    def keys(self, bucket: str, prefix: str = "") -> list[str]:
        pages = self.client.get_paginator("list_objects_v2").paginate(Bucket=bucket, Prefix=prefix)
        return sorted(item["Key"] for page in pages for item in page.get("Contents", []))

    def get(self, bucket: str, key: str) -> bytes:
        return self.client.get_object(Bucket=bucket, Key=key)["Body"].read()

    def tree(self, bucket: str, prefix: str) -> dict[str, bytes]:
        """Every object under PREFIX: its name below the prefix -> its bytes."""
        return {key[len(prefix):].lstrip("/"): self.get(bucket, key) for key in self.keys(bucket, prefix)}


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def _moto_server_command() -> list[str]:
    beside = Path(sys.executable).with_name("moto_server")
    return [str(beside) if beside.exists() else (shutil.which("moto_server") or "moto_server")]


@pytest.fixture(scope="session")
def s3_server() -> Iterator[S3Server]:
    boto3 = pytest.importorskip("boto3", reason="the s3 extra (boto3) is not installed")
    port = _free_port()
    endpoint = f"http://127.0.0.1:{port}"
    env = {**os.environ, "INITIAL_NO_AUTH_ACTION_COUNT": str(_SET_UP_REQUESTS)}
    server = subprocess.Popen([*_moto_server_command(), "-H", "127.0.0.1", "-p", str(port)], env=env,
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    saved = dict(os.environ)
    try:
        deadline = time.monotonic() + 30
        while True:
            try:
                socket.create_connection(("127.0.0.1", port), 0.2).close()
                break
            except OSError:
                if time.monotonic() > deadline or server.poll() is not None:
                    raise RuntimeError("moto_server did not start") from None
                time.sleep(0.05)
        iam = boto3.client("iam", endpoint_url=endpoint, aws_access_key_id="setup", aws_secret_access_key="setup",
                           region_name="us-east-1")
        iam.create_user(UserName="pdsgen-tests")
        iam.put_user_policy(UserName="pdsgen-tests", PolicyName="everything", PolicyDocument=json.dumps(
            {"Version": "2012-10-17", "Statement": [{"Effect": "Allow", "Action": "*", "Resource": "*"}]}))
        key = iam.create_access_key(UserName="pdsgen-tests")["AccessKey"]
        for name in [n for n in os.environ if n.startswith(("AWS_", "CPL_AWS", "GDAL_HTTP"))]:
            del os.environ[name]  # nothing of the developer's own AWS set-up reaches the tests
        os.environ.update(AWS_ACCESS_KEY_ID=key["AccessKeyId"], AWS_SECRET_ACCESS_KEY=key["SecretAccessKey"],
                          AWS_ENDPOINT_URL=endpoint, AWS_DEFAULT_REGION="us-east-1",
                          AWS_CONFIG_FILE=os.devnull, AWS_SHARED_CREDENTIALS_FILE=os.devnull)
        client = boto3.client("s3", endpoint_url=endpoint, aws_access_key_id=key["AccessKeyId"],
                              aws_secret_access_key=key["SecretAccessKey"], region_name="us-east-1")
        yield S3Server(endpoint, key["AccessKeyId"], key["SecretAccessKey"], client)
    finally:
        os.environ.clear()
        os.environ.update(saved)
        server.terminate()
        try:
            server.wait(10)
        except subprocess.TimeoutExpired:
            server.kill()
            server.wait()
