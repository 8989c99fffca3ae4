"""A label's statement (products/dispatch.ProductStatement) and how it reaches a writer (dispatch.stating)."""

from __future__ import annotations

import functools

from pdsgen.missions import get_mission
from pdsgen.products.dispatch import NO_STATEMENT, ProductStatement, stating
from pdsgen.products.hrsc import write_hrsc_dtm


def test_a_product_of_one_input_says_its_missions_words():
    mission = get_mission("hirise")
    assert NO_STATEMENT.note(mission) == mission.dtm_note
    assert NO_STATEMENT.description(mission) == mission.ortho_description
    assert NO_STATEMENT.projection_note(mission) == mission.map_projection_note


def test_a_mosaic_says_how_its_sources_were_put_together_after_the_missions_or_the_tiles_words():
    mission = get_mission("hirise")
    mosaic = ProductStatement(mosaic="Mosaic of 2 products.")
    assert mosaic.note(mission) == f"{mission.dtm_note} Mosaic of 2 products.".strip()
    assert mosaic.description(mission) == f"{mission.ortho_description} Mosaic of 2 products."
    tiles = ProductStatement(mosaic="Mosaic of 2 products.", dtm_note="Heights.", map_projection_note=("/* x */",))
    assert tiles.note(mission) == "Heights. Mosaic of 2 products."
    assert tiles.projection_note(mission) == ("/* x */",)


def test_a_statement_reaches_a_writer_that_takes_one_and_no_other():
    statement = ProductStatement(mosaic="Mosaic of 2 products.")

    def own_words(input_path, outdir, options):
        return None

    assert stating(own_words, statement) is own_words
    assert stating(write_hrsc_dtm, None) is write_hrsc_dtm
    given = stating(write_hrsc_dtm, statement)
    assert isinstance(given, functools.partial) and given.keywords == {"statement": statement}
