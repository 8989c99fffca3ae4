"""What every object description shares: the refusal, where an object lies, how a refusal
names it, and the PDS3 values every kind of object states the same way (units, special
constants, positive counts). The describers (objects.py, qube.py) import from here.
"""

from __future__ import annotations

import os
import struct
from dataclasses import dataclass
from pathlib import Path

from ..errors import InputError
from ..label.beside import find_beside, find_reference
from ..label.grammar import PLACEHOLDERS
from ..label.includes import MAX_INCLUDE_DEPTH  # no genuine volume nests format files more than a few deep
from ..label.parser import LabelFile
from ..label.tree import Block, Pointer, Statement, Value
from ..validate.context import FileContext
from .mapping import SPECIAL_CONSTANTS, SPECIAL_ORDER


class Refused(InputError):
    """A product migration cannot describe exactly: one line per obstacle, nothing written.

    `problems` holds every obstacle found (each names its object and label line); `problem`,
    the first, is what callers reading one message get."""

    def __init__(self, path: str | os.PathLike[str] | None, problem: str, more: tuple[str, ...] = ()) -> None:
        self.problems = (problem, *more)
        super().__init__(path, problem)

    # A label can name obstacles without end (20,000 pointers to nothing were 20,000 lines):
    # the first SHOWN are told, the rest counted on one more line.
    SHOWN = 20

    def __str__(self) -> str:
        told = list(self.problems[:self.SHOWN])
        if len(self.problems) > self.SHOWN:
            told.append(f"and {len(self.problems) - self.SHOWN} more obstacle(s) of the same product")
        return "\n".join(f"{self.path}: {problem}" if self.path is not None else problem for problem in told)


class MissingFile(Refused):
    """A data file a pointer names is not there (gathered: one line per file, naming its pointers)."""

    def __init__(self, path: str | os.PathLike[str] | None, file_name: str) -> None:
        self.file_name = file_name
        super().__init__(path, f"data file {file_name} is missing")


@dataclass(frozen=True)
class Target:
    """Where a described object lies: its OBJECT block, local identifier, byte offset, file,
    and the RECORD_BYTES its file counts records in."""

    block: Block
    ident: str
    offset: int
    path: Path
    record_bytes: int | None
    next_start: int | None = None  # where the next object of the same file starts, or the file's end


def where(block: Block) -> str:
    """How a refusal names an object: `OBJECT = HISTORY (line 40)`."""
    return f"OBJECT = {block.name} (line {block.line})"


def pointer_where(ptr: Pointer) -> str:
    return f"^{ptr.name} (line {ptr.statement.line})"


def unit(block: Block) -> str | None:
    unit = block.text("UNIT")
    return None if unit is None or unit.upper() in PLACEHOLDERS else unit


def special_constants(ctx: FileContext, block: Block, is_float: bool, bits: int,
                      keywords: dict[str, str] = SPECIAL_CONSTANTS) -> list[tuple[str, float | int]]:
    """Special_Constants in the schema's order; a based integer of a float image is its bit
    pattern (16#FF7FFFFB# is the float32 ISIS NULL, -3.4028226550889045e+38)."""
    found: dict[str, tuple[str, float | int]] = {}
    for keyword, element in keywords.items():
        value = block.value(keyword)
        if value is None or value.items is not None or not value.is_number:
            continue
        number = sample_value(value, is_float, bits)
        if element in found and found[element][1] != number:
            raise Refused(ctx.path, f"{where(block)}: {found[element][0]} and {keyword} give two "
                                    f"different {element} values, which PDS4 cannot both state")
        found.setdefault(element, (keyword, number))
    return [(name, found[name][1]) for name in SPECIAL_ORDER if name in found]


def sample_value(value: Value, is_float: bool, bits: int) -> float | int:
    number = value.number
    if value.kind == "based" and is_float and bits in (32, 64):
        packed = int(number).to_bytes(bits // 8, "big", signed=number < 0)
        return struct.unpack(">f" if bits == 32 else ">d", packed)[0]
    return float(number) if is_float else number


def positive_int(ctx: FileContext, block: Block, key: str) -> int:
    number = block.number(key)
    if not isinstance(number, int) or number <= 0:
        raise Refused(ctx.path, f"{where(block)}: {key} is missing or not a positive integer")
    return number




def structure_file(ctx: FileContext, stmt: Statement, chain: tuple[Path, ...] = ()) -> tuple[Path, Block]:
    """The format file a ^STRUCTURE names, found beside the label (or in a LABEL directory),
    inside the trusted tree either way, and its parsed contents, included through the files of
    `chain`: one that includes itself or lies more than MAX_INCLUDE_DEPTH files deep is refused."""
    name = stmt.value.text
    exact, other = ctx.resolve(name)
    # beside the label (any case), else where a reader looks: the LABEL/ of the volume's root
    # (the directory holding VOLDESC.CAT, else the tree given), or of the label's parent's parent
    path = exact or other or find_reference(ctx.path.parent, name, "STRUCTURE", ctx.tree) \
        or find_beside(ctx.path.parent.parent / "LABEL", name, root=ctx.tree)
    if path is None:
        raise Refused(ctx.path, f"^STRUCTURE file {name} is missing")
    path = path.resolve()
    if path in chain:
        raise Refused(ctx.path, f"^STRUCTURE file {name} includes itself")
    if len(chain) >= MAX_INCLUDE_DEPTH:
        raise Refused(ctx.path, f"^STRUCTURE files included more than {MAX_INCLUDE_DEPTH} deep")
    try:
        return path, LabelFile.read(path).root
    except OSError as error:
        raise Refused(ctx.path, f"^STRUCTURE file {name}: {error.strerror or error}") from None


def with_structures(ctx: FileContext, block: Block) -> Block:
    """The block with the statements of its ^STRUCTURE files in their places (a Cassini VIMS
    SPECTRAL_QUBE keeps CORE_ITEM_TYPE and the suffix keywords in .FMT files): a copy, same name
    and line, for keyword look-ups; the label's own statement wins where both give one."""
    if not any(isinstance(i, Statement) and i.pointer and i.keyword.upper() == "STRUCTURE" for i in block.items):
        return block
    items: list[Statement | Block] = []
    for item in block.items:
        if isinstance(item, Statement) and item.pointer and item.keyword.upper() == "STRUCTURE":
            _, root = structure_file(ctx, item)
            items.extend(i for i in root.items if isinstance(i, Statement))
        else:
            items.append(item)
    own = [i for i in block.items if isinstance(i, Statement)]  # first statement of a key wins in look-ups
    return Block(block.kind, block.name, block.line, block.end_line, [*own, *items])
