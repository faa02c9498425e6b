"""The notebooks run from top to bottom (so they never rot) and hold their figures.

A code cell that draws a figure carries the tag ``figure``. Executed here as in Jupyter
(inline backend), every such cell must put out exactly one PNG and no other cell any; the
stored notebook must hold the same figures, so that it shows them when opened without running.
"""

from pathlib import Path

import pytest

NOTEBOOKS = sorted((Path(__file__).resolve().parents[1] / "notebooks").glob("*.ipynb"))


def figures(nb):
    """PNG outputs per code cell, and the cells tagged ``figure``."""
    code = [c for c in nb.cells if c.cell_type == "code"]
    pngs = [sum("image/png" in o.get("data", {}) for o in c.get("outputs", [])) for c in code]
    tagged = ["figure" in c.get("metadata", {}).get("tags", []) for c in code]
    return pngs, tagged


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_notebook_runs_and_shows_its_figures(path):
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    nb = nbformat.read(path, as_version=4)
    stored, tagged = figures(nb)
    assert sum(tagged) >= 1, "tag the cells that draw with 'figure'"
    assert stored == [int(t) for t in tagged], "the stored notebook must hold its figures"
    for cell in nb.cells:                                  # run afresh
        if cell.cell_type == "code":
            cell.outputs = []
    client = nbclient.NotebookClient(nb, timeout=300, kernel_name="python3",
                                     resources={"metadata": {"path": str(path.parent)}})
    client.execute()
    outputs = [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", [])]
    errors = [f"{o['ename']}: {o['evalue']}" for o in outputs if o.get("output_type") == "error"]
    assert not errors
    # No warnings (tqdm's "IProgress not found", deprecations, ...); a one-off notice such as
    # matplotlib building its font cache on a fresh machine is not one.
    warned = [o["text"] for o in outputs
              if o.get("output_type") == "stream" and o.get("name") == "stderr"
              and ("Warning" in o["text"] or "IProgress" in o["text"])]
    assert not warned, warned
    executed, _ = figures(nb)
    assert executed == [int(t) for t in tagged]


def test_there_are_notebooks():
    assert len(NOTEBOOKS) >= 2
