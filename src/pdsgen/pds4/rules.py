"""The PDS4 rule ids, severities and summaries (listed by `pdsgen validate --list-rules`).

Ids never change meaning once published. The checks live in `validate.py`; this module
imports nothing, so the PDS3 rule table can list these without importing the checks.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Pds4Rule:
    id: str
    severity: str
    summary: str


RULES = (
    Pds4Rule("PDS4-001", "error", "a PDS4 label is well-formed XML with a Product_* root"),
    Pds4Rule("PDS4-002", "warning", "each schema the label names is found (beside the label, --schemas, the "
                                    "cache, shipped, or downloaded); otherwise its namespace is not checked"),
    Pds4Rule("PDS4-003", "error", "every schema import resolves (none silently skipped)"),
    Pds4Rule("PDS4-004", "error", "the label is valid against its XML Schemas"),
    Pds4Rule("PDS4-005", "error", "the label passes its Schematron rules (role error)"),
    Pds4Rule("PDS4-006", "warning", "the label passes its Schematron rules (role warning)"),
    Pds4Rule("PDS4-007", "warning", "Schematron ran (needs saxonche: pip install pdsgen[pds4])"),
    Pds4Rule("PDS4-008", "warning", "the label names its Schematron (an xml-model instruction with the "
                                    "Schematron schematypens); otherwise no rule checks are made"),
    Pds4Rule("PDS4-010", "error", "every File named by the label exists beside it"),
    Pds4Rule("PDS4-011", "error", "file_size equals the size of the file"),
    Pds4Rule("PDS4-012", "error", "md5_checksum equals the MD5 of the file"),
    Pds4Rule("PDS4-013", "error", "each array fits in its file (offset + elements x sample size)"),
    Pds4Rule("PDS4-020", "error", "no valid sample lies beyond Object_Statistics minimum or maximum"),
    Pds4Rule("PDS4-021", "warning", "Object_Statistics mean and standard_deviation match the valid samples"),
    Pds4Rule("PDS4-022", "error", "samples in the ISIS special-pixel range are declared Special_Constants"),
    Pds4Rule("PDS4-023", "warning", "each special constant can be stored in the array's data type (one that "
                                    "cannot flags nothing)"),
    Pds4Rule("PDS4-024", "warning", "Object_Statistics minimum and maximum equal the valid samples' extremes "
                                    "(not merely bound them)"),
    Pds4Rule("PDS4-050", "error", "table fields lie inside the record, do not overlap, and binary fields have "
                                  "their type's size"),
    Pds4Rule("PDS4-051", "error", "table records: each ends with the record delimiter, has record_length "
                                  "bytes, and the file holds the stated number"),
    Pds4Rule("PDS4-052", "error", "each table value parses as its field's data_type (and fits "
                                  "maximum_field_length)"),
    Pds4Rule("PDS4-053", "error", "numeric table values lie within their Field_Statistics minimum and maximum"),
    Pds4Rule("PDS4-054", "warning", "numeric table values lie within the field's valid_minimum/valid_maximum "
                                    "or are special constants"),
    Pds4Rule("PDS4-055", "error", "each delimited record has the number of fields the label defines, and no "
                                  "double-quoted value holds a double quote"),
    Pds4Rule("PDS4-056", "error", "inventory and bundle members: status P or S, a LIDVID or LID, none listed "
                                  "twice"),
    Pds4Rule("PDS4-057", "error", "the objects of a file (header, tables, arrays) do not overlap"),
    Pds4Rule("PDS4-058", "error", "table values have the precision of their field's validation_format"),
    Pds4Rule("PDS4-059", "warning", "table values have the precision of their field's field_format"),
    Pds4Rule("PDS4-060", "error", "no two labels of a run describe the same file of observational data"),
    Pds4Rule("PDS4-062", "error", "file names use only letters, digits, '-', '_' and '.', and directory paths "
                                  "are relative"),
    Pds4Rule("PDS4-061", "error", "a PDF a document product holds is identified as PDF/A (its XMP pdfaid:part)"),
    Pds4Rule("PDS4-063", "error", "context references (investigation, instrument, target ...) name registered "
                                  "context products (the registry snapshot NASA's validator ships)"),
    Pds4Rule("PDS4-030", "error", "cart: pixel_scale agrees with pixel_resolution and the body radius"),
    Pds4Rule("PDS4-031", "error", "cart: bounding coordinates agree with Geo_Transformation within half a pixel"),
    Pds4Rule("PDS4-032", "error", "cart: map_projection_name has the parameter block of that projection"),
    Pds4Rule("PDS4-040", "error", "an Encoded_Image JP2's GeoJP2 box agrees with cart: Geo_Transformation"),
)
