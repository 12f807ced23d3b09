"""The example notebook runs top to bottom against the small config's results, and (CI) against
the results of the default run and of the small run made on a plain install
(``CLUTCHLAB_NOTEBOOK_RESULTS``: results folders separated by the path separator)."""

import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
pytestmark = pytest.mark.slow


def _run_notebook(results: Path, monkeypatch) -> str:
    """Execute notebooks/explore.ipynb against ``results``; its printed text."""
    import nbclient
    import nbformat

    monkeypatch.setenv("CLUTCHLAB_RESULTS", str(results))
    nb = nbformat.read(ROOT / "notebooks/explore.ipynb", as_version=4)
    assert not any(
        c.get("outputs") for c in nb.cells if c.cell_type == "code"
    )  # stored without outputs
    nbclient.NotebookClient(
        nb,
        timeout=300,
        kernel_name="python3",
        resources={"metadata": {"path": str(ROOT / "notebooks")}},
    ).execute()
    assert not [
        o for c in nb.cells if c.cell_type == "code" for o in c.outputs if o.output_type == "error"
    ]
    return "\n".join(
        str(o.get("text", "")) for c in nb.cells if c.cell_type == "code" for o in c.outputs
    )


def test_explore_notebook_runs(small_run, monkeypatch):
    text = _run_notebook(small_run / "results", monkeypatch)
    assert "spring designs meet both" in text and "MPa" in text
    assert "best compromise" in text  # the design the report's pages show, by its one function


GIVEN = [p for p in os.environ.get("CLUTCHLAB_NOTEBOOK_RESULTS", "").split(os.pathsep) if p]


@pytest.mark.skipif(not GIVEN, reason="CLUTCHLAB_NOTEBOOK_RESULTS not set (CI sets it)")
@pytest.mark.parametrize("results", GIVEN)
def test_explore_notebook_runs_on_given_results(results, monkeypatch):
    """The notebook against another run's results (CI: the default run's and the small run's,
    both made on a plain `pip install -e .`), whatever grid the run had."""
    text = _run_notebook(Path(results).resolve(), monkeypatch)
    assert "spring designs meet both" in text and "MPa" in text
