"""Every COMPAS Data class of the package round-trips through COMPAS JSON byte for byte."""

from __future__ import annotations

import hashlib

import compas
import numpy as np
import pytest

from compas_ccu.design import Design
from compas_ccu.materials import DesignFactors, Material
from compas_ccu.model import CCUModel, load_model
from compas_ccu.structure import Structure
from compas_ccu.thickness import ThickModel
from conftest import EXAMPLES

EXAMPLE_NAMES = ["cone.toml", "vault.toml", "quadrants.toml"]


def _sha(text: str) -> str:
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def _objects(name: str) -> dict:
    model = load_model(EXAMPLES / name)
    out = {"Design": model.design, "CCUModel": model, "Structure": model.deploy()}
    if name != "quadrants.toml":  # CCF creases have no thick model (paper Fig. 8c)
        out["ThickModel"] = ThickModel(model, thickness=0.004 if name == "cone.toml" else None)
    return out


@pytest.mark.parametrize("name", EXAMPLE_NAMES)
def test_json_round_trip_is_byte_identical(name):
    for cls_name, obj in _objects(name).items():
        text = compas.json_dumps(obj)
        again = compas.json_loads(text)
        assert type(again).__name__ == cls_name
        assert _sha(compas.json_dumps(again)) == _sha(text), (name, cls_name)
        assert again.sha256() == obj.sha256()
        assert again.guid == obj.guid


def test_json_files_round_trip_too(tmp_path, vault_model):
    structure = vault_model.deploy(25.0)
    path = tmp_path / "vault.json"
    compas.json_dump(structure, path)
    again = compas.json_load(path)
    assert isinstance(again, Structure)
    assert again.alpha == 25.0
    assert np.array_equal(again.deployed, structure.deployed)
    assert again.creases == structure.creases


def test_the_dtypes_name_importable_classes(vault_model):
    dtypes = {
        type(obj).__name__: compas.json_loads(compas.json_dumps(obj)).__class__.__module__
        for obj in _objects("vault.toml").values()
    }
    assert dtypes == {
        "Design": "compas_ccu.design.document",
        "CCUModel": "compas_ccu.model.ccu_model",
        "Structure": "compas_ccu.structure",
        "ThickModel": "compas_ccu.thickness.model",
    }
    assert '"dtype": "compas_ccu.thickness/ThickModel"' in compas.json_dumps(
        ThickModel(vault_model)
    )


def test_a_thick_model_keeps_its_options_through_json(cone_model):
    thick = ThickModel(
        cone_model, thickness=0.006, material="birch-plywood", grain=30.0,
        design_code={"service_class": 2, "load_duration": "medium-term"},
    )  # fmt: skip
    again = compas.json_loads(compas.json_dumps(thick))
    assert isinstance(again.model, CCUModel) and isinstance(again.model.design, Design)
    assert (again.thickness, again.grain) == (0.006, 30.0)
    assert isinstance(again.material, Material) and again.material == thick.material
    assert isinstance(again.factors, DesignFactors) and again.factors == thick.factors
    assert again.factors.k_mod == 0.8  # EN 1995-1-1 Table 3.1, plywood, SC2 medium-term
    assert again.stack_height == thick.stack_height
    assert np.array_equal(again.deploy(20.0).solids, thick.deploy(20.0).solids)


def test_a_structure_document_of_another_format_is_refused():
    text = compas.json_dumps(load_model(EXAMPLES / "cone.toml").deploy())
    with pytest.raises(ValueError, match="not a ccu.structure v1 document: format='other'"):
        compas.json_loads(text.replace('"format": "ccu.structure"', '"format": "other"'))
