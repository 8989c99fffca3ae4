"""PDS4 family: PDS4 labels against their XML Schemas, Schematron and the data they describe.

A family like every other: one `Rule` per id in the registry (one severity each), checks
that take a context and yield `Hit`s, findings made by the runner. Its context is a
`Pds4LabelContext` (pdsgen.validate.pds4.label_checks), which the runner opens for a file that is a PDS4 label
(`open_label`). The PDS4 checks do not map one function to one rule: parsing, the XML
Schema pass, Schematron and a content check each find problems of several rules at once.
So the label is checked once, on the first rule's call, and each rule takes its own hits.

Two rules look across the run (`run_check`, in the parent process, for each PDS4 label
in report order): PDS4-007 tells once that Schematron could not run; PDS4-060 finds two
labels describing one file of observational data.

lxml, the schema catalog and the checks are imported only when a PDS4 label turns up:
a run over PDS3 labels, or `--list-rules`, loads none of them.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..model import Hit
from ..registry import Rule, register

if TYPE_CHECKING:
    from ...label.read import LabelCache
    from ..pds4.label_checks import Pds4LabelContext


def open_label(path: Path, labels_only: bool, schemas: tuple[str, ...], schema_cache: str | None,
               download_schemas: bool, tree: Path | None = None) -> Pds4LabelContext:
    """The context the PDS4 rules take (nothing is read until the first rule asks). `tree`: the
    trusted tree the label's files must stay in (the directory given, or --root), as for PDS3."""
    from ..pds4.label_checks import Pds4LabelContext, catalog_for

    return Pds4LabelContext(path, catalog_for(schemas, schema_cache, download_schemas), labels_only, tree=tree)


def check_schema_dirs(directories: tuple[str, ...]) -> tuple[str, ...]:
    """`--schemas` directories, refused before the run (a usage error) if one is not a directory."""
    if not directories:
        return ()
    from ..pds4.label_checks import check_schema_dirs as checked

    return checked(directories)


def _hits_of(rule_id: str) -> Callable[[Pds4LabelContext], Iterable[Hit]]:
    """The check of one PDS4 rule: its share of the label's hits."""

    def check(label: Pds4LabelContext) -> Iterable[Hit]:
        return label.hits(rule_id)

    check.__name__ = f"check_{rule_id.replace('-', '_').lower()}"
    return check


def schematron_note(labels: LabelCache | None = None) -> Callable[[str], list[Hit]]:
    """PDS4-007 across the run: one warning, on the first PDS4 label, when Saxon is missing."""
    told: list[bool] = []

    def observe(path: str) -> list[Hit]:
        if told:
            return []
        told.append(True)
        from ..pds4 import schematron

        if schematron.available():
            return []
        return [Hit("Schematron not run: saxonche is not installed (pip install '.[pds4]' in pdsgen's "
                    "checkout, or pip install saxonche); "
                    "PDS4 labels were checked against their XML Schemas only")]

    return observe


def shared_data_files(labels: LabelCache | None = None) -> Callable[[str], list[Hit]]:
    """PDS4-060 across the run: the labels' data files, and which label named each first."""
    from ..pds4.document_checks import DataFileRegister

    return DataFileRegister().add


def _rule(rule_id: str, severity: str, summary: str, **fields: Any) -> Rule[Any]:
    if "run_check" in fields:
        return Rule(rule_id, severity, summary, None, target="pds4", **fields)
    return Rule(rule_id, severity, summary, _hits_of(rule_id), target="pds4", **fields)


register(
    _rule("PDS4-001", "error", "a PDS4 label is well-formed XML with a Product_* root"),
    _rule("PDS4-002", "warning", "each schema the label names is found (--schemas, shipped, the cache, "
                                 "or downloaded from PDS); otherwise its namespace is not checked"),
    _rule("PDS4-003", "error", "every schema import resolves (none silently skipped)"),
    _rule("PDS4-004", "error", "the label is valid against its XML Schemas"),
    _rule("PDS4-005", "error", "the label passes its Schematron rules (role error)"),
    _rule("PDS4-006", "warning", "the label passes its Schematron rules (role warning)"),
    _rule("PDS4-007", "warning", "Schematron ran (needs saxonche: pip install '.[pds4]' in pdsgen's checkout)",
          run_check=schematron_note),
    _rule("PDS4-008", "warning", "the label names its Schematron (an xml-model instruction with the "
                                 "Schematron schematypens); otherwise no rule checks are made"),
    _rule("PDS4-010", "error", "every File named by the label exists beside it"),
    _rule("PDS4-011", "error", "file_size equals the size of the file"),
    _rule("PDS4-012", "error", "md5_checksum equals the MD5 of the file"),
    _rule("PDS4-013", "error", "each array fits in its file (offset + elements x sample size)"),
    _rule("PDS4-020", "error", "no valid sample lies beyond Object_Statistics minimum or maximum"),
    _rule("PDS4-021", "warning", "Object_Statistics mean and standard_deviation match the valid samples"),
    _rule("PDS4-022", "error", "samples in the ISIS special-pixel range are declared Special_Constants"),
    _rule("PDS4-023", "warning", "each special constant can be stored in the array's data type (one that "
                                 "cannot flags nothing)"),
    _rule("PDS4-024", "warning", "Object_Statistics minimum and maximum equal the valid samples' extremes "
                                 "(not merely bound them)"),
    _rule("PDS4-050", "error", "table fields lie inside the record, do not overlap, and binary fields have "
                               "their type's size"),
    _rule("PDS4-051", "error", "table records: each ends with the record delimiter, has record_length "
                               "bytes, and the file holds the stated number"),
    _rule("PDS4-052", "error", "each table value parses as its field's data_type (and fits "
                               "maximum_field_length)"),
    _rule("PDS4-053", "error", "numeric table values lie within their Field_Statistics minimum and maximum"),
    _rule("PDS4-054", "warning", "numeric table values lie within the field's valid_minimum/valid_maximum "
                                 "or are special constants"),
    _rule("PDS4-055", "error", "each delimited record has the number of fields the label defines, and no "
                               "double-quoted value holds a double quote"),
    _rule("PDS4-056", "error", "inventory and bundle members: status P or S, a LIDVID or LID, none listed "
                               "twice"),
    _rule("PDS4-057", "error", "the objects of a file (header, tables, arrays) do not overlap"),
    _rule("PDS4-058", "error", "table values have the precision of their field's validation_format"),
    _rule("PDS4-059", "warning", "table values have the precision of their field's field_format"),
    _rule("PDS4-060", "error", "no two labels of a run describe the same file of observational data",
          run_check=shared_data_files),
    _rule("PDS4-062", "error", "file names use only letters, digits, '-', '_' and '.', and directory paths "
                               "are relative"),
    _rule("PDS4-064", "error", "every file a label names (file_name) lies inside its directory: no ../, "
                                 "absolute path or link leading out; such a file is not read"),
    _rule("PDS4-061", "error", "a PDF a document product holds is identified as PDF/A (its XMP pdfaid:part)"),
    _rule("PDS4-063", "error", "context references (investigation, instrument, target ...) name registered "
                               "context products (the registry snapshot NASA's validator ships)"),
    _rule("PDS4-065", "warning", "a target's type is the one PDS registers for it (its context reference, "
                                 "else its registered name)"),
    _rule("PDS4-066", "info", "No Specific Investigation beside an instrument host named like a registered "
                              "investigation"),
    _rule("PDS4-030", "error", "cart: pixel_scale agrees with pixel_resolution and the body radius"),
    _rule("PDS4-031", "error", "cart: bounding coordinates agree with Geo_Transformation within half a pixel"),
    _rule("PDS4-032", "error", "cart: map_projection_name has the parameter block of that projection"),
    _rule("PDS4-040", "error", "an Encoded_Image JP2's GeoJP2 box agrees with cart: Geo_Transformation"),
)
