"""Writer/validator agreement: a label is checked by the validator before it is published.

pdsgen must never deliver what `pdsgen validate` rejects. Every product writer hands
its final label text to `check_label` before the product is renamed into place; the
validator's label rules run on it (its own code, imported, not a second copy of the
rules). A value that breaks the PDS3 data dictionary - usually one a producer gave in
`--params`, such as a 74-character PRODUCER_FULL_NAME where the dictionary allows
60 - is refused with one line naming the keyword, unless the producer has said to
keep it (`--allow-dictionary-deviations`, or `allow_dictionary_deviations = true`
in the params file); then it is written and reported once as a warning.
Other rule families judge the product as a whole (file names, data, mission rules
that depend on a name) and are left to `pdsgen validate`.
"""

from __future__ import annotations

import tempfile
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import ParamsError, param
from .params import ParamValue

if TYPE_CHECKING:
    from ..validate import Finding

DICTIONARY_FAMILY = "DICT-"
ALLOW_PARAM = "ALLOW_DICTIONARY_DEVIATIONS"


def allows_deviations(option: bool | None, keywords: Mapping[str, ParamValue]) -> bool:
    """The option if given, else the params setting, else False."""
    if option is not None:
        return bool(option)
    return str(keywords.get(ALLOW_PARAM, "false")).lower() == "true"


def label_keywords(keywords: Mapping[str, ParamValue]) -> dict[str, ParamValue]:
    """The params keywords that go into labels (the agreement setting does not)."""
    return {key: value for key, value in keywords.items() if key != ALLOW_PARAM}


def check_label(text: str, file_name: str, *, allow_deviations: bool) -> tuple[str, ...]:
    """Run the validator's label rules on `text` as `file_name`; refuse or return warnings.

    Returns one warning line per dictionary deviation kept (empty when the label is
    clean). Raises ParamsError naming the first offending keyword otherwise.
    """
    from ..validate import validate_file  # the validator is loaded only when a product is written

    with tempfile.TemporaryDirectory(prefix="pdsgen-check-") as tmp:
        path = Path(tmp) / file_name
        path.write_bytes(text.encode("ascii"))
        report, _ = validate_file(path, labels_only=True, strict=True)  # pdsgen's own labels: strict
    deviations = [f for f in report.findings if f.severity == "error" and f.rule.startswith(DICTIONARY_FAMILY)]
    if deviations and not allow_deviations:
        first = deviations[0]
        more = f" (and {len(deviations) - 1} more)" if len(deviations) > 1 else ""
        raise ParamsError(None, f"{_named(first)} (PDS3 data dictionary, {first.rule}){more}; "
                                f"fix the value or pass {param('allow_dictionary_deviations', True)} to keep it")
    return tuple(f"{file_name}: {_named(f)} (PDS3 data dictionary, {f.rule}); kept as allowed"
                 for f in deviations)


def _named(finding: Finding) -> str:
    """The finding's message, led by its keyword unless the message already starts with it."""
    keyword = finding.keyword or "label"
    return finding.message if finding.message.startswith(keyword) else f"{keyword}: {finding.message}"
