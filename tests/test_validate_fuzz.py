"""Never a traceback: labels damaged at random (bytes deleted, inserted, flipped) are
validated to the end, every problem is a finding and no check fails to run."""

from __future__ import annotations

import random

from pdsgen.validate import validate_paths
from test_validate_ortho import make_ortho
from test_validate_support import make_dtm

PUNCTUATION = b'=(){}"\'<>#/*^ \r\n,;0123456789ABCZ:-.'


def _mutate(data: bytes, rng: random.Random) -> bytes:
    out = bytearray(data)
    for _ in range(rng.randint(1, 6)):
        pos = rng.randrange(len(out)) if out else 0
        roll = rng.random()
        if roll < 0.3 and out:
            del out[pos:pos + rng.randint(1, 20)]
        elif roll < 0.6:
            out[pos:pos] = bytes(rng.choice(PUNCTUATION) for _ in range(rng.randint(1, 5)))
        elif out:
            out[pos] = rng.randrange(256)
    return bytes(out)


def test_random_damage_never_breaks_the_validator(tmp_path):
    (tmp_path / "d").mkdir()
    (tmp_path / "o").mkdir()
    dtm = make_dtm(tmp_path / "d", lines=12, samples=9)
    ortho = make_ortho(tmp_path / "o")
    sources = [(dtm, dtm.read_bytes()[:6000]), (ortho.label_path, ortho.label_path.read_bytes())]
    rng = random.Random(20261121)
    damaged = []
    for i in range(120):
        path, data = sources[i % 2]
        if path == dtm:
            data = dtm.read_bytes()  # attached label: damage the label part, keep the data
            end = data.index(b"\r\nEND\r\n") + 7
            data = _mutate(data[:end], rng) + data[end:]
        else:
            data = _mutate(data, rng)
        target = path.parent / f"X{i:03d}{path.suffix}"
        target.write_bytes(data)
        damaged.append(target)
    report = validate_paths(damaged)
    assert len(report.files) == len(damaged)
    assert not [f for f in report.findings if "could not run" in f.message]
    assert report.count("error") > 0
