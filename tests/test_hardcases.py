"""Hard cases (issue 17 item 2): every case has its right answer and source, and passes."""

import numpy as np
import pytest

from clutchlab import hardcases, store


@pytest.fixture(scope="module")
def cases():
    return hardcases.run()


def test_every_hard_case_passes(cases):
    failed = [
        (c.case, c.right_answer, c.computed, c.error, c.tolerance) for c in cases if not c.passed
    ]
    assert not failed, failed


def test_every_case_of_the_physics_notes_is_there(cases):
    """PHYSICS.md's hard-case table and those found since (issue 17's list)."""
    names = " ".join(c.case for c in cases)
    for words in (
        "start of motion",
        "step clamp",
        "never locking",
        "break-away",
        "tiny driven inertia",
        "zero initial slip",
        "restart at an event",
        "judder",
        "Hertz",
        "f tan α = 1",
        "monotone spring",
        "roll-over",
        "held engine at rest",
    ):
        assert words in names, words
    for c in cases:
        assert c.right_answer and c.source and c.computed
        assert np.isnan(c.error) or c.tolerance >= 0


def test_a_wrong_value_fails():
    c = hardcases.Case("x", "y", "1 s", "analytic", "1.1 s", 0.1, 1e-9, True)
    assert not c.passed and c.error_kind == "absolute"
    assert not hardcases.Case("x", "y", "jammed", "s", "ok", np.nan, 0.0, False).passed


def test_only_the_studies_run(cases):
    assert {c.study for c in hardcases.run(["sprag", "centrifugal"])} == {"sprag", "centrifugal"}
    assert [c.study for c in hardcases.run(["sprag", "engagement"])][
        0
    ] == "sprag"  # in the run's order


def test_dataset_and_csv(tmp_path, cases):
    import csv

    ds = hardcases.to_dataset(cases)
    path = store.write(ds, tmp_path / "hard_cases.h5")
    back = store.load(path)
    assert back.sizes["case"] == len(cases) and int(back["passed"].sum()) == len(cases)
    hardcases.to_csv(back, tmp_path / "hard_cases.csv")
    with open(tmp_path / "hard_cases.csv") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == len(cases) and list(rows[0]) == hardcases.COLUMNS
    assert all(r["right_answer"] and r["source"] and r["passed"] == "1" for r in rows)
