"""The Schematron -> XSLT 3.0 translation keeps ISO Schematron's semantics (run by Saxon)."""

from __future__ import annotations

import pytest

from pdsgen.validate.pds4 import schematron

pytestmark = pytest.mark.skipif(not schematron.available(), reason="saxonche (pdsgen[pds4]) is not installed")

SCH = """<sch:schema xmlns:sch="http://purl.oclc.org/dsdl/schematron" queryBinding="xslt2">
  <sch:ns uri="urn:t" prefix="t"/>
  <sch:pattern>
    <sch:let name="n" value="count(//t:b)"/>
    <sch:rule context="t:b">
      <sch:assert test=". = 'x'">b is <sch:value-of select="."/>, not x (of <sch:value-of select="$n"/>)</sch:assert>
      <sch:report test=". = 'y'" role="warning">b is y</sch:report>
    </sch:rule>
    <sch:rule context="t:*"><sch:assert test="false()">later rule of the pattern</sch:assert></sch:rule>
  </sch:pattern>
  <sch:pattern>
    <sch:let name="n" value="'another pattern'"/>
    <sch:rule context="t:b">
      <sch:assert test="string-length(.) = 1">long b in <sch:value-of select="$n"/></sch:assert>
    </sch:rule>
  </sch:pattern>
</sch:schema>"""


def test_first_rule_of_a_pattern_wins_patterns_are_independent_lets_are_scoped(tmp_path):
    (tmp_path / "t.sch").write_text(SCH)
    found = schematron.compiled([tmp_path / "t.sch"]).check('<a xmlns="urn:t"><b>y</b><b>x</b><b>zz</b></a>')
    got = sorted((f.location.rsplit("/", 1)[-1], f.role, f.message) for f in found)
    assert got == [
        ("Q{urn:t}a[1]", "error", "later rule of the pattern"),  # b elements are taken by the first rule
        ("Q{urn:t}b[1]", "error", "b is y, not x (of 3)"),
        ("Q{urn:t}b[1]", "warning", "b is y"),
        ("Q{urn:t}b[3]", "error", "b is zz, not x (of 3)"),
        ("Q{urn:t}b[3]", "error", "long b in another pattern"),
    ]


ROLES = """<sch:schema xmlns:sch="http://purl.oclc.org/dsdl/schematron" queryBinding="xslt2">
  <sch:ns uri="urn:t" prefix="t"/>
  <sch:pattern>
    <sch:rule context="t:b" role="warning">
      <sch:assert test="false()">rule says warning</sch:assert>
      <sch:assert test="false()" role="error">assert says error</sch:assert>
    </sch:rule>
  </sch:pattern>
  <sch:pattern role="info">
    <sch:rule context="t:b"><sch:assert test="false()">pattern says info</sch:assert></sch:rule>
  </sch:pattern>
  <sch:pattern>
    <sch:rule context="t:b"><sch:assert test="false()">nothing said</sch:assert></sch:rule>
  </sch:pattern>
</sch:schema>"""


def test_role_comes_from_the_assert_else_its_rule_else_its_pattern(tmp_path):
    """PDS's .sch files mark deprecated elements with role="warning" on the sch:rule."""
    (tmp_path / "r.sch").write_text(ROLES)
    found = schematron.compiled([tmp_path / "r.sch"]).check('<a xmlns="urn:t"><b/></a>')
    assert sorted((f.message, f.role) for f in found) == [
        ("assert says error", "error"), ("nothing said", "error"),
        ("pattern says info", "info"), ("rule says warning", "warning")]

