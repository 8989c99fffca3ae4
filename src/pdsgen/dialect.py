"""The label dialect a product or delivery is written in: PDS3, PDS4, or both.

One small type instead of string compares in every writer: `dialect.pds3` says whether a
PDS3 label (or volume) is written, `dialect.pds4` whether a PDS4 one is. It is a `str`
(`Dialect.BOTH == "both"`), so results, summaries and callers that hold the text keep working.
"""

from __future__ import annotations

from enum import Enum

from .errors import ParamsError, param


class Dialect(str, Enum):
    PDS3 = "pds3"
    PDS4 = "pds4"
    BOTH = "both"

    def __str__(self) -> str:
        return self.value

    def __format__(self, spec: str) -> str:
        return format(self.value, spec)

    @property
    def pds3(self) -> bool:
        """A PDS3 label (attached or detached) or a PDS3 volume is written."""
        return self is not Dialect.PDS4

    @property
    def pds4(self) -> bool:
        """A PDS4 label or a PDS4 bundle is written."""
        return self is not Dialect.PDS3

    @classmethod
    def of(cls, value: str | Dialect) -> Dialect:
        """The dialect named `value` (a writer's `label`); ParamsError for any other text."""
        try:
            return cls(value)
        except ValueError:
            raise ParamsError(None, f"{param('label')} must be one of {', '.join(DIALECT_NAMES)}, "
                                    f"not {value!r}") from None


# The names, in the order --help lists them.
DIALECT_NAMES = tuple(d.value for d in Dialect)
