"""The suite's own set-up: the session's small Snakemake run is made once, whichever
pytest-xdist worker needs it first, and every worker reads that one folder (tests/conftest.py)."""

import os

import pytest


@pytest.mark.slow  # it needs the small run
def test_the_small_run_is_made_once_for_every_worker(small_run, tmp_path_factory):
    """Else every worker makes the small run (minutes each). Under xdist the run lives in the
    folder the workers share, not in this worker's own; the workers that did not make it waited
    for it (a file lock) instead of making their own. (Tests that rerun Snakemake in the run's
    folder take a copy of it: ``small_run_copy``.)"""
    base = tmp_path_factory.getbasetemp()
    shared = base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base
    assert small_run == shared / "small_run"
    made = (shared / "small_run.made").read_text().splitlines()
    assert len(made) == 1, made
    assert (small_run / "results/report/report.pdf").stat().st_size > 0
