"""The source papers' numbers in one module: well-formed records, and every validation row compares
against one of them (no study keeps a published number of its own)."""

import dataclasses
import math

import numpy as np

from clutchlab import published as pub
from clutchlab import studies


def _records():
    """(paper, source, value, units) of every published number, Table 2 field by field."""
    for table in (
        pub.DIAPHRAGM_CLUTCH,
        pub.CENTRIFUGAL_CLUTCH,
        pub.SPRAG_CLUTCH,
        pub.ROLLER_CLUTCH,
    ):
        for p in table.values():
            yield p.paper, p.source, p.value, p.units
    for row in pub.SPRAG_TABLE2.values():
        for field in dataclasses.fields(row):
            value = getattr(row, field.name)
            yield "002", pub.SPRAG_TABLE2_SOURCE, value, pub.SPRAG_TABLE2_UNITS[field.name]


def test_records_are_well_formed():
    """Each number names its paper, quantity, units and source; the dict keys of a paper are its
    names; Table 2 is keyed by its own torque and every field has units."""
    papers = {
        "000": pub.DIAPHRAGM_CLUTCH,
        "001": pub.CENTRIFUGAL_CLUTCH,
        "002": pub.SPRAG_CLUTCH,
        "003": pub.ROLLER_CLUTCH,
    }
    for paper, table in papers.items():
        for key, p in table.items():
            assert p.paper == paper and key.isidentifier(), key
            assert p.quantity and p.units and p.source, key
            assert isinstance(p.value, float) and math.isfinite(p.value), key
    for torque, row in pub.SPRAG_TABLE2.items():
        assert row.torque == torque
    names = {f.name for f in dataclasses.fields(pub.SpragTheory)}
    assert names == set(pub.SPRAG_TABLE2_UNITS)


def test_every_validation_row_compares_against_a_published_number():
    """Every row of every study's validation table: its seed, source, published value and units
    are those of a record of clutchlab.published (exact equality)."""
    known = set(_records())
    checked = 0
    for name in ("diaphragm_spring", "engagement", "centrifugal", "sprag", "roller"):
        study = studies.get(name)
        if study.validation is None:
            continue
        v = study.validation()
        for i in range(v.sizes["row"]):
            key = (
                str(v["seed"].values[i]),
                str(v["source"].values[i]),
                float(v["published"].values[i]),
                str(v["units"].values[i]),
            )
            assert key in known, (study.name, str(v["quantity"].values[i]), key)
            checked += 1
    assert checked >= 60  # the four papers' rows
    assert np.isfinite([r[2] for r in known]).all()
