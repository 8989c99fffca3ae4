"""Refactoring changes no product: every file of every kind of product, byte for byte, as the
version named in tests/golden/products_made.json wrote it (tests/products_made.py lists the
commands). Nothing is masked: every date written comes from SOURCE_DATE_EPOCH, which the
commands run under (pdsgen/clock.py), so the table holds on any day.

After an intended change of output, regenerate the table with
`python tests/products_made.py DIR > tests/golden/products_made.json` and say why in the commit.
"""

from __future__ import annotations

import json
from pathlib import Path

from products_made import make

TABLE = Path(__file__).parent / "golden" / "products_made.json"


def test_every_product_file_is_byte_identical_to_the_recorded_version(tmp_path):
    recorded = json.loads(TABLE.read_text())
    made = make(tmp_path)
    missing = sorted(set(recorded["files"]) - set(made))
    extra = sorted(set(made) - set(recorded["files"]))
    changed = sorted(name for name in set(made) & set(recorded["files"]) if made[name] != recorded["files"][name])
    assert (missing, extra, changed) == ([], [], []), f"differs from the products of {recorded['made_by']}"
