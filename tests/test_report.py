"""Report built from stored Datasets; validation rows of seed 000."""
import csv

import pytest

from clutchlab import doe, report, store
from clutchlab.config import resolve
from clutchlab.studies import diaphragm_spring


def test_seed000_validation_rows_all_pass():
    v = diaphragm_spring.validation()
    failed = [str(q) for q, ok in zip(v["quantity"].values, v["passed"].values) if not ok]
    assert not failed
    assert v.sizes["row"] >= 10


@pytest.mark.parametrize("design", ["factorial", "lhs"])
def test_report_pages(tmp_path, design):
    params = ({"sheet_thickness": {"values": ["2 mm", "2.4 mm"]}, "cone_height_ratio": {"values": [1.3, 1.7]},
               "radius_ratio": {"values": [1.25, 1.3]}} if design == "factorial" else
              {"sheet_thickness": {"min": "2 mm", "max": "2.6 mm"}, "cone_height_ratio": {"min": 1.2, "max": 2.0}})
    sec = {"design": design, "parameters": params}
    if design == "lhs":
        sec["samples"] = 50
    cfg = resolve({"studies": ["diaphragm_spring"], "diaphragm_spring": sec})
    spring = store.write(doe.run_study(cfg["diaphragm_spring"]), tmp_path / "spring.h5")
    val = store.write(diaphragm_spring.validation(), tmp_path / "val.h5")
    written = report.build({"diaphragm_spring": spring}, [val], tmp_path / "report")
    stems = sorted(p.stem for p in written if p.suffix == ".png")
    assert stems == sorted(report.figure_stems(["diaphragm_spring"]))
    pdf = (tmp_path / "report" / "report.pdf").read_bytes()
    assert pdf.startswith(b"%PDF") and pdf.count(b"/Type /Page\n") + pdf.count(b"/Type /Page ") >= len(stems) - 1
    rows = list(csv.DictReader(open(tmp_path / "report" / "validation.csv")))
    assert len(rows) == 14 and all(r["passed"] == "yes" for r in rows)
