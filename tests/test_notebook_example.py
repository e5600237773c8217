"""``examples/paper_pipeline.ipynb`` runs from top to bottom in a Jupyter kernel (nbclient).

The notebook is the paper's pipeline through ``import origami_cad as oc``; it is kept
without outputs. Executed here as Jupyter executes it, each object shows what a notebook
shows: the design as SVG, folded states and the fabrication as 3D views with PNG stills.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

nbformat = pytest.importorskip("nbformat")
nbclient = pytest.importorskip("nbclient")

NOTEBOOK = Path(__file__).resolve().parents[1] / "examples" / "paper_pipeline.ipynb"


def test_the_notebook_is_kept_without_outputs():
    nb = nbformat.read(NOTEBOOK, as_version=4)
    nbformat.validate(nb)
    code = [c for c in nb.cells if c.cell_type == "code"]
    assert code and all(not c.outputs and c.execution_count is None for c in code)


@pytest.fixture(scope="module")
def executed(tmp_path_factory):
    nb = nbformat.read(NOTEBOOK, as_version=4)
    cwd = tmp_path_factory.mktemp("notebook")  # not the examples folder: it reads, never writes
    client = nbclient.NotebookClient(
        nb, timeout=300, kernel_name="python3", resources={"metadata": {"path": str(cwd)}}
    )
    client.execute()
    return nb, cwd


def _outputs(nb, source_part: str) -> list[dict]:
    cell = next(c for c in nb.cells if c.cell_type == "code" and source_part in c.source)
    assert not [o for o in cell.outputs if o.output_type == "error"], cell.outputs
    return cell.outputs


def _data(outputs) -> dict:
    return next(o.data for o in outputs if o.output_type == "execute_result")


def test_the_pipeline_runs_and_each_object_shows_itself(executed):
    nb, cwd = executed
    design = _data(_outputs(nb, "oc.tg_design("))
    assert "image/svg+xml" in design and "<CreasePattern 'fig2'" in design["text/plain"]
    fold = _outputs(nb, "oc.fold_design(design, 0.5)")
    printed = "".join(o.get("text", "") for o in fold if o.output_type == "stream")
    # the README's figures: the main creases fold to 90 deg at p = 0.5
    assert re.search(r"M: \d+ creases, -\d+\.\d to -90\.0 deg", printed), printed
    assert re.search(r"V: \d+ creases, 90\.0 to \d+\.\d deg", printed), printed
    state = _data(fold)
    assert "oc-view" in state["text/html"] and "image/png" in state
    assert state["text/plain"].startswith("<FoldedState p=0.5")
    search = _data(_outputs(nb, "oc.design_arm("))["text/plain"]
    assert search.startswith("<ArmSearch: ") and "winner fitness" in search
    fab = _data(_outputs(nb, "oc.fabricate(miura)"))
    assert "oc-view" in fab["text/html"] and "24 panels" in fab["text/plain"]
    dcqc = _outputs(nb, "oc.simulate_dcqc(")
    p = float(re.search(r"DCQC: p = ([\d.]+)", dcqc[0]["text"]).group(1))
    assert 0.3 < p <= 1.0
    sim = _outputs(nb, "oc.simulate(")
    assert float(re.search(r"simulation: p = ([\d.]+)", sim[0]["text"]).group(1)) > 0.05
    assert _data(sim)["text/plain"].startswith("<SimulationResult: ")
    assert list(cwd.iterdir()) == []  # the notebook wrote nothing
