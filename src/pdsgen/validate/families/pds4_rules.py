"""PDS4: labels are checked by pdsgen.pds4 (the runner hands .xml labels over); its rules
are registered here so that --list-rules, configuration and baselines know their ids."""

from __future__ import annotations

from ...pds4.rules import RULES as PDS4_RULES
from ..registry import Rule, register

register(*(Rule(r.id, r.severity, r.summary, None, target="pds4") for r in PDS4_RULES))
