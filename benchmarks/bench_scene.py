"""How light the COMPAS scene of a CCU structure is (docs/benchmarks.md, "Light scenes").

For one design (default: the vault): the children of ``Scene().add(model)`` and its time in
plain Python; with compas_notebook installed, the ipywidgets models created by adding the
structure to a notebook viewer and drawing it (``scene.draw()``) and by the whole
``Viewer.show()`` (the viewer's page included); with ``--notebook``, the size of the executed
``notebooks/scene.ipynb`` and the widget models saved in it.

    .venv/bin/python benchmarks/bench_scene.py [--design examples/vault.toml] [--notebook]
"""

from __future__ import annotations

import argparse
import contextlib
import io
import os
import statistics
import time
from pathlib import Path

from compas_ccu.model import load_model

ROOT = Path(__file__).resolve().parents[1]


def _widget_registry():
    import ipywidgets

    registry = getattr(ipywidgets.widgets.widget, "_instances", None)  # ipywidgets 8
    return ipywidgets.Widget.widgets if registry is None else registry


def plain(model, repeats: int = 5) -> dict:
    from compas.scene import Scene

    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        obj = Scene().add(model)
        times.append(time.perf_counter() - t)
    roles = ("plate", "crease", "ruling")
    return {
        "children": {r: len(obj.children_by_role(r)) for r in roles},
        "scene objects": 1 + len(obj.children),
        "Scene().add (median s)": round(statistics.median(times), 3),
    }


def notebook(model) -> dict:
    from compas_notebook.viewer import Viewer

    registry = _widget_registry()
    before = len(registry)
    viewer = Viewer()
    t = time.perf_counter()
    viewer.scene.add(model)
    viewer.scene.draw()
    drawn = time.perf_counter() - t
    after_draw = len(registry)
    shown = Viewer()
    shown.scene.add(model)
    start = len(registry)
    with contextlib.redirect_stdout(io.StringIO()):  # no frontend: display() prints a repr
        shown.show()
    return {
        "widget models, scene.add + draw": after_draw - before,
        "widget models, Viewer.show() (page included)": len(registry) - start,
        "add + draw (s)": round(drawn, 3),
    }


def executed_notebook(path: Path) -> dict:
    import nbclient
    import nbformat

    nb = nbformat.read(path, as_version=4)
    t = time.perf_counter()
    client = nbclient.NotebookClient(
        nb, timeout=600, kernel_name="python3", resources={"metadata": {"path": str(path.parent)}}
    )
    client.execute()
    state = nb.metadata.get("widgets", {}).get("application/vnd.jupyter.widget-state+json", {})
    return {
        "executed notebook (bytes)": len(nbformat.writes(nb).encode()),
        "widget models saved": len(state.get("state", {})),
        "execution (s)": round(time.perf_counter() - t, 1),
    }


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--design", default=str(ROOT / "examples" / "vault.toml"))
    parser.add_argument("--notebook", action="store_true", help="execute notebooks/scene.ipynb")
    args = parser.parse_args(argv)
    model = load_model(args.design)
    print(f"{Path(args.design).name}, load average {os.getloadavg()[0]:.2f}")
    for key, value in plain(model).items():
        print(f"  {key}: {value}")
    try:
        import compas_notebook  # noqa: F401
    except ImportError:
        print("  compas_notebook is not installed: no widget counts")
        return
    for key, value in notebook(model).items():
        print(f"  {key}: {value}")
    if args.notebook:
        for key, value in executed_notebook(ROOT / "notebooks" / "scene.ipynb").items():
            print(f"  notebooks/scene.ipynb {key}: {value}")


if __name__ == "__main__":
    main()
