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
from ..params import ParamValue

if TYPE_CHECKING:
    from ..validate.model import Hit

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
    """Run the validator's data-dictionary rules on `text` as `file_name`; refuse or return warnings.

    Returns one warning line per dictionary deviation kept (empty when the label is
    clean). Raises ParamsError naming the first offending keyword otherwise.
    """
    deviations = dictionary_errors(text, file_name)
    if deviations and not allow_deviations:
        rule, first = deviations[0]
        more = f" (and {len(deviations) - 1} more)" if len(deviations) > 1 else ""
        raise ParamsError(None, f"{_named(first)} (PDS3 data dictionary, {rule}){more}; "
                                f"fix the value or pass {param('allow_dictionary_deviations', True)} to keep it")
    return tuple(f"{file_name}: {_named(hit)} (PDS3 data dictionary, {rule}); kept as allowed"
                 for rule, hit in deviations)


def dictionary_errors(text: str, file_name: str) -> list[tuple[str, Hit]]:
    """(rule id, hit) of each error the validator's DICT rules find in the label `text`, in
    label order, as `pdsgen validate --strict` reports them (pdsgen's own labels: strict).

    Only the DICT family's code and the label reader are loaded (the other families
    judge the product as a whole and are not acted on here), so writing a product does
    not import the whole validator.
    """
    from ..validate.context import FileContext
    from ..validate.families import dict_rules  # noqa: F401  (importing it registers the DICT rules)
    from ..validate.model import Hit
    from ..validate.registry import registered

    found: list[tuple[str, Hit]] = []
    with tempfile.TemporaryDirectory(prefix="pdsgen-check-") as tmp:
        path = Path(tmp) / file_name
        path.write_bytes(text.encode("ascii"))
        ctx = FileContext(path, labels_only=True, strict=True)
        for rule in registered(DICTIONARY_FAMILY.rstrip("-")):
            if rule.check is None or rule.target != "label" or rule.needs_data:
                continue
            try:
                found += [(rule.id, hit) for hit in rule.check(ctx) if (hit.severity or rule.severity) == "error"]
            except Exception as exc:  # as the validator reports a check that cannot run: an error
                found.append((rule.id, Hit(f"check could not run on this file ({type(exc).__name__}: {exc})")))
    return sorted(found, key=lambda found: (found[1].line or 0, found[0]))


def _named(hit: Hit) -> str:
    """The finding's message, led by its keyword unless the message already starts with it."""
    keyword = hit.keyword or "label"
    return hit.message if hit.message.startswith(keyword) else f"{keyword}: {hit.message}"
