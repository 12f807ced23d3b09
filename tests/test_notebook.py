"""The example notebook (issue 18 item 1) runs top to bottom against the small config's results."""

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
pytestmark = pytest.mark.slow


def test_explore_notebook_runs(small_run, monkeypatch):
    import nbclient
    import nbformat

    monkeypatch.setenv("CLUTCHLAB_RESULTS", str(small_run / "results"))
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
    text = "\n".join(
        str(o.get("text", "")) for c in nb.cells if c.cell_type == "code" for o in c.outputs
    )
    assert "spring designs meet both" in text and "MPa" in text
    assert not [
        o for c in nb.cells if c.cell_type == "code" for o in c.outputs if o.output_type == "error"
    ]
