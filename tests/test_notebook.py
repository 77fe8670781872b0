"""The tour notebook runs top to bottom and shows its pictures."""

from __future__ import annotations

from pathlib import Path

import pytest

NOTEBOOK = Path(__file__).resolve().parents[1] / "notebooks" / "tour.ipynb"


def _executed(path, *, notebook: bool = False):
    """The outputs of the notebook ``path`` run top to bottom (committed without outputs, no
    error), and the executed notebook itself with ``notebook``."""
    # imported here, not at collection: nbformat's jsonschema builds a grammar (~1.5 s) that
    # every run of the quick loop, which skips these slow tests, would pay
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    pytest.importorskip("matplotlib")
    nb = nbformat.read(path, as_version=4)
    assert all(not c.get("outputs") for c in nb.cells if c.cell_type == "code"), (
        "commit the notebook without outputs"
    )
    client = nbclient.NotebookClient(
        nb,
        timeout=300,
        kernel_name="python3",
        resources={"metadata": {"path": str(NOTEBOOK.parent)}},
    )
    client.execute()
    outputs = [o for c in nb.cells if c.cell_type == "code" for o in c.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    return (nb, outputs) if notebook else outputs


@pytest.mark.slow
def test_tour_notebook_runs_top_to_bottom(tmp_path, monkeypatch):
    monkeypatch.setenv("CCU_NOTEBOOK_OUT", str(tmp_path))
    outputs = _executed(NOTEBOOK)
    images = [o for o in outputs if "image/png" in o.get("data", {})]
    assert len(images) == 4  # two views, the sequence, the cut patterns
    text = "".join(o.get("text", "") for o in outputs if o.output_type == "stream")
    assert "10 plates, 64 segments per crease" in text
    assert "crease kinds: anticlastic, synclastic" in text
    for name in ("structure.json", "structure.obj", "viewer.html", "deployment.gif"):
        assert (tmp_path / name).is_file(), name
    assert (tmp_path / "report" / "index.html").is_file()
    # the live studio shown inline: an IFrame of the studio's server on this machine
    frames = [o["data"]["text/html"] for o in outputs if "text/html" in o.get("data", {})]
    assert any("<iframe" in f and "http://127.0.0.1:" in f for f in frames), frames
    assert "studio at http://127.0.0.1:" in text


SCENE_NOTEBOOK = NOTEBOOK.with_name("scene.ipynb")


@pytest.mark.slow
def test_scene_notebook_stays_small():
    """The vault in a compas_notebook scene: 39 widget models and 221 kB executed (one pythreejs
    line per ruling made 2,763 models and 3.9 MB; docs/benchmarks.md)."""
    pytest.importorskip("compas_notebook")
    nb, outputs = _executed(SCENE_NOTEBOOK, notebook=True)
    text = "".join(o.get("text", "") for o in outputs if o.output_type == "stream")
    assert "scene children: {'plate': 10, 'crease': 9, 'ruling': 10}" in text
    views = [o for o in outputs if "application/vnd.jupyter.widget-view+json" in o.get("data", {})]
    assert len(views) == 1
    state = nb.metadata["widgets"]["application/vnd.jupyter.widget-state+json"]["state"]
    assert 0 < len(state) <= 50
    assert len(pytest.importorskip("nbformat").writes(nb).encode()) <= 500_000
