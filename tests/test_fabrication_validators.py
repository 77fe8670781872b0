"""``ccu fabricate`` files read by independent readers: the npm packages in tools/validators.

* ``solids.glb``: the Khronos glTF-Validator (``gltf-validator``), 0 errors and 0 warnings, and
  the glTF is Y up (its position bounds are the world's, rotated);
* ``<name>.fold``: the FOLD reference library (``fold``) and Rabbit Ear: a valid graph, the same
  vertex / edge / face counts, ``edges_faces`` as ``fold`` builds them, and every
  ``edges_foldAngle`` equal to the angle ``fold``'s geometry gives from the coordinates;
* the DXFs: ``dxf-parser`` (not ezdxf), the same entities per layer, the same geometry and
  header extents as ezdxf reads, the extents containing the drawing;
* every ``.json`` and ``.fold`` file: strict JSON (no NaN / Infinity).

Designs: the vault, the cone (2 plates), fig12a (inclined planes), fig12b and fig12c (radial)
and a 22-plate vault. The node tests need ``make validators`` (``npm ci`` in tools/validators);
without node or the packages they fail saying so, unless ``CCU_SKIP_VALIDATORS=1``.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from conftest import EXAMPLES

pytest.importorskip("ezdxf")
pytest.importorskip("rhino3dm")
pytest.importorskip("trimesh")

import ezdxf  # noqa: E402

from compas_ccu.catalog import catalog_path  # noqa: E402
from compas_ccu.fabrication.fabricate import fabricate  # noqa: E402
from compas_ccu.fabrication.workshop import WorkshopOptions  # noqa: E402
from compas_ccu.model import load_model  # noqa: E402

pytestmark = pytest.mark.slow

VALIDATORS = Path(__file__).resolve().parents[1] / "tools" / "validators"
PACKAGES = ("gltf-validator", "fold", "rabbit-ear", "dxf-parser")
DESIGNS = {  # name: (design file, plates)
    "vault": (EXAMPLES / "vault.toml", 10),
    "cone": (EXAMPLES / "cone.toml", 2),
    "fig12a": (catalog_path("fig12a-asymmetric"), 10),
    "fig12b": (catalog_path("fig12b-dome"), 12),
    "fig12c": (catalog_path("fig12c-funnel"), 12),
    "vault22": (None, 22),  # the vault with 22 plates, written below
}


@pytest.fixture(scope="session")
def node():
    """The node executable, with the validator packages installed (else the test fails)."""
    if os.environ.get("CCU_SKIP_VALIDATORS") == "1":
        pytest.skip("CCU_SKIP_VALIDATORS=1")
    exe = shutil.which("node")
    missing = [p for p in PACKAGES if not (VALIDATORS / "node_modules" / p).is_dir()]
    if exe is None or missing:
        what = "node is not on PATH" if exe is None else f"missing npm packages {missing}"
        pytest.fail(
            f"{what}: run `make validators` (npm ci in tools/validators; needs Node.js >= 18) "
            "or set CCU_SKIP_VALIDATORS=1 to skip the independent file readers",
            pytrace=False,
        )
    return exe


def run(node, script: str, files) -> list:
    proc = subprocess.run(
        [node, str(VALIDATORS / script), *(str(f) for f in files)],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    verdicts = json.loads(proc.stdout)
    assert len(verdicts) == len(files)
    return verdicts


def strict_json(text: str):
    def refuse(name):
        raise ValueError(f"non-standard JSON constant {name}")

    return json.loads(text, parse_constant=refuse)


def vault22(folder: Path) -> Path:
    text = (EXAMPLES / "vault.toml").read_text(encoding="utf-8")
    assert "plates = 10" in text and 'name = "vault"' in text
    text = text.replace("plates = 10", "plates = 22").replace('name = "vault"', 'name = "vault22"')
    path = folder / "vault22.toml"
    path.write_text(text, encoding="utf-8")
    return path


@pytest.fixture(scope="module", params=list(DESIGNS))
def fabricated(request, tmp_path_factory):
    """(name, out folder, manifest, model) of every design, fabricated once."""
    folder = tmp_path_factory.mktemp(request.param)
    path = DESIGNS[request.param][0] or vault22(folder)
    model = load_model(path)
    out = folder / "fab"
    # the sheets of the vault nested by spyrrow, of the others by shelves (fast; same entities)
    nesting = "spyrrow" if request.param == "vault" else "shelf"
    manifest = fabricate(model, out, workshop=WorkshopOptions(nesting=nesting))
    return request.param, out, manifest, model


def test_every_json_file_is_strict_and_listed(fabricated):
    name, out, manifest, model = fabricated
    written = sorted(str(p.relative_to(out)) for p in out.rglob("*") if p.is_file())
    assert written == sorted(manifest["files"])
    assert manifest["plates"] == len(model.plate_ids) == DESIGNS[name][1]
    for f in written:
        if f.endswith((".json", ".fold")):
            strict_json((out / f).read_text(encoding="utf-8"))
    c = strict_json((out / "fabrication.json").read_text())["collisions"]
    assert (c["min_clearance"] is None) == (c["clearance_pairs"] == 0) == (name == "cone")


def test_gltf_validator(node, fabricated):
    name, out, manifest, model = fabricated
    (v,) = run(node, "gltf.js", [out / "solids.glb"])
    assert v["errors"] == v["warnings"] == v["infos"] == v["hints"] == 0, v["messages"]
    assert v["nodes"] == v["meshes"] == manifest["plates"]
    assert v["nodesWithTransform"] == 0
    # Y up: the glTF bounds are the world bounds of solids.obj rotated by -90 deg about X
    world = np.array(
        [
            [float(x) for x in line.split()[1:]]
            for line in (out / "solids.obj").read_text().splitlines()
            if line.startswith("v ")
        ]
    )
    lo, hi = world.min(axis=0), world.max(axis=0)
    want_min = [lo[0], lo[2], -hi[1]]
    want_max = [hi[0], hi[2], -lo[1]]
    size = float(np.abs(world).max())
    np.testing.assert_allclose(v["bounds"]["min"], want_min, rtol=0, atol=1e-6 * size)
    np.testing.assert_allclose(v["bounds"]["max"], want_max, rtol=0, atol=1e-6 * size)


def test_fold_reference_libraries(node, fabricated):
    name, out, manifest, model = fabricated
    path = next(out.glob("*.fold"))
    (v,) = run(node, "fold.js", [path])
    assert v["errors"] == 0 and v["warnings"] == 0, v["messages"]
    assert v["spec"] == 1.2
    doc = json.loads(path.read_text())
    frames = [doc, *doc["file_frames"]]
    assert len(v["frames"]) == 3
    p, n = manifest["plates"], model.segments
    for got, frame in zip(v["frames"], frames):
        counts = [len(frame[k]) for k in ("vertices_coords", "edges_vertices", "faces_vertices")]
        assert [got["vertices"], got["edges"], got["faces"]] == counts
        assert got["faces"] == p * n
        assert sum(got["assignments"].values()) == got["edges"]
    key, cp, stack = v["frames"]
    for got in (key, stack):
        assert got["dimension"] == 3
        assert got["maxFoldAngleDifference"] < 1e-6
        assert got["vertices"] - got["edges"] + got["faces"] == 1  # one corrugated sheet
        assert {"B", "M"} <= set(got["assignments"]) <= {"B", "M", "V"}  # cone: no valley
    assert cp["dimension"] == 2 and set(cp["assignments"]) == {"B", "F"}
    assert cp["vertices"] - cp["edges"] + cp["faces"] == p  # separate cut patterns


def ezdxf_summary(path: Path) -> dict:
    doc = ezdxf.readfile(path)
    entities, pts = {}, []
    for e in doc.modelspace():
        key = f"{e.dxf.layer}/{e.dxftype()}"
        entities[key] = entities.get(key, 0) + 1
        if e.dxftype() == "LWPOLYLINE":
            pts += [p[:2] for p in e.get_points("xy")]
        elif e.dxftype() == "LINE":
            pts += [tuple(e.dxf.start)[:2], tuple(e.dxf.end)[:2]]
    pts = np.array(pts, dtype=float)
    return {
        "entities": entities,
        "geometry": (pts.min(axis=0), pts.max(axis=0)),
        "header": (doc.header["$EXTMIN"], doc.header["$EXTMAX"]),
        "units": doc.header["$INSUNITS"],
    }


def test_dxf_second_reader(node, fabricated):
    name, out, manifest, model = fabricated
    files = [out / f for f in manifest["files"] if f.endswith(".dxf")]
    sheets = manifest["workshop"]["sheets"]
    assert len(files) == manifest["plates"] + 1 + len(sheets)
    for path, v in zip(files, run(node, "dxf.js", files)):
        assert v["errors"] == 0 and v["warnings"] == 0, (path, v["messages"])
        ref = ezdxf_summary(path)
        assert v["units"] == ref["units"] == 4
        assert v["entities"] == ref["entities"], path
        np.testing.assert_allclose(v["geometry"]["min"], ref["geometry"][0], rtol=0, atol=1e-9)
        np.testing.assert_allclose(v["geometry"]["max"], ref["geometry"][1], rtol=0, atol=1e-9)
        np.testing.assert_allclose(v["header"]["extmin"], ref["header"][0], rtol=0, atol=1e-9)
        np.testing.assert_allclose(v["header"]["extmax"], ref["header"][1], rtol=0, atol=1e-9)
        if path.name == "hinges.dxf":
            assert v["entities"]["HINGE_CUT/LWPOLYLINE"] == manifest["hinge_strips"]
            assert v["closed"] == {"HINGE_CUT": manifest["hinge_strips"]}
        elif path.parent.name == "sheets":
            parts = len(sheets[int(path.stem.split("_")[1]) - 1]["parts"])
            assert v["entities"]["OUTER_CUT/LWPOLYLINE"] == parts
            assert v["entities"]["PART_OUTLINE/LWPOLYLINE"] == parts
            assert v["closed"]["OUTER_CUT"] == v["closed"]["PART_OUTLINE"] == parts
            assert v["closed"]["SHEET"] == 1 and "SCORE/LINE" not in v["entities"]
        else:
            assert v["entities"]["CUT/LWPOLYLINE"] == 1
            # the rulings are not scored by default: on the reference layer RULING
            assert v["entities"]["RULING/LINE"] == model.segments - 1
            # the cut outline is the drawing: labels inside, extents = the outline's box
            np.testing.assert_allclose(v["header"]["extmin"][:2], v["geometry"]["min"], atol=1e-9)
            np.testing.assert_allclose(v["header"]["extmax"][:2], v["geometry"]["max"], atol=1e-9)
