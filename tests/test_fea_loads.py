"""Load cases, their nodal loads and the support model (no engine needed)."""

from __future__ import annotations

import numpy as np
import pytest

from compas_ccu.design import load_design
from compas_ccu.design.schema import DesignError, validate
from compas_ccu.fea.loads import CASE_NAMES, GRAVITY, Action, LoadCase, load_cases, nodal_loads
from compas_ccu.fea.mesh import mesh_model
from compas_ccu.fea.problem import FEError
from compas_ccu.fea.settings import DEFAULT_AREA_LOAD, FESettings
from compas_ccu.fea.supports import support_model
from compas_ccu.model import CCUModel

LOADS = {
    "concrete_thickness": 0.08,
    "concrete_density": 2500.0,
    "concrete_area": "projected",
    "live": 750.0,
    "snow": 800.0,
    "wind": -300.0,
    "gamma_G": 1.35,
    "gamma_Q": 1.5,
}
UP = np.array([0.0, 0.0, 1.0])
X = np.array([1.0, 0.0, 0.0])


def tilted_plate(angle_deg: float, n: int = 4):
    """A 2 x 1 m plate, n x n quads, tilted about the y axis by angle; x from 0 to 2 cos."""
    a = np.radians(angle_deg)
    u, v = np.meshgrid(np.linspace(0.0, 2.0, n + 1), np.linspace(0.0, 1.0, n + 1), indexing="ij")
    nodes = np.c_[u.ravel() * np.cos(a), v.ravel(), u.ravel() * np.sin(a)]
    k = n + 1
    elements = np.array(
        [
            [i * k + j, (i + 1) * k + j, (i + 1) * k + j + 1, i * k + j + 1]
            for i in range(n)
            for j in range(n)
        ]
    )
    return nodes, elements


def test_the_cases_of_a_loads_section():
    cases = load_cases(LOADS, self_weight=47.088)
    assert [c.name for c in cases] == [
        "self-weight",
        "wet-concrete",
        "construction",
        "snow",
        "snow-half",
        "wind",
    ]
    assert [c.duration for c in cases] == ["permanent", *["short-term"] * 4, "instantaneous"]
    concrete = cases[1].actions[1]
    assert concrete.value == pytest.approx(2500.0 * GRAVITY * 0.08, rel=1e-15)
    assert [a.name for a in cases[2].actions] == ["self-weight", "wet concrete", "live"]
    assert cases[4].actions[1].half and not cases[3].actions[1].half
    # gamma: the permanent 1.35, the variable 1.5; under suction the weight is favourable
    assert cases[1].factor(cases[1].actions[0]) == 1.35
    assert cases[1].factor(concrete) == 1.5
    assert cases[5].gamma_G == 1.0
    assert load_cases({**LOADS, "wind": 300.0}, self_weight=1.0)[-1].gamma_G == 1.35
    # only the actions that are not zero; the area load last
    only = load_cases({"live": 500.0}, self_weight=1.0, area_load=1500.0)
    assert [c.name for c in only] == ["self-weight", "construction", "area-load"]
    assert set(c.name for c in cases) | {"area-load"} == set(CASE_NAMES)


@pytest.mark.parametrize("angle", [0.0, 30.0, 60.0])
def test_nodal_loads_add_up_to_the_action_on_its_area(angle):
    nodes, elements = tilted_plate(angle)
    a = np.radians(angle)
    kw = dict(up=UP, span_axis=X, middle=np.cos(a))
    surface = nodal_loads(elements, nodes, Action("g", 100.0, "surface"), **kw)
    projected = nodal_loads(elements, nodes, Action("s", 100.0, "projected"), **kw)
    normal = nodal_loads(elements, nodes, Action("w", 100.0, "normal"), **kw)
    assert surface[:, :3].sum(axis=0) == pytest.approx([0.0, 0.0, -200.0], abs=1e-9)
    assert projected[:, :3].sum(axis=0) == pytest.approx([0.0, 0.0, -200.0 * np.cos(a)], abs=1e-9)
    # a pressure presses onto the upper face: against the upward normal (-sin a, 0, cos a)
    assert normal[:, :3].sum(axis=0) == pytest.approx(
        [200.0 * np.sin(a), 0.0, -200.0 * np.cos(a)], abs=1e-9
    )
    assert np.all(surface[:, 3:] == 0.0)
    half = nodal_loads(elements, nodes, Action("s", 100.0, "projected", half=True), **kw)
    assert half[:, 2].sum() == pytest.approx(projected[:, 2].sum() / 2.0, rel=1e-12)
    loaded = np.flatnonzero(half[:, 2])
    assert nodes[loaded, 0].max() == pytest.approx(np.cos(a))  # up to the middle only


def test_a_turned_plate_gets_the_same_pressure():
    """The normal's sign in the element order does not matter: the upper face is loaded."""
    nodes, elements = tilted_plate(30.0)
    kw = dict(up=UP, span_axis=X, middle=0.0)
    a = nodal_loads(elements, nodes, Action("w", 50.0, "normal"), **kw)
    b = nodal_loads(elements[:, ::-1], nodes, Action("w", 50.0, "normal"), **kw)
    np.testing.assert_allclose(a, b, atol=1e-12)


def test_actions_and_settings_refuse_what_they_cannot_use():
    with pytest.raises(FEError, match="where must be one of"):
        Action("x", 1.0, "vertical")
    with pytest.raises(FEError, match="duration"):
        Action("x", 1.0, "surface", duration="weekly")
    with pytest.raises(FEError, match=r"load case\(s\) \['snow'\] are not defined.*'wet-concrete'"):
        FESettings(loads={"concrete_thickness": 0.05}, load_cases=["snow"])
    with pytest.raises(FEError, match=r"unknown supports key\(s\) \['kind'\]"):
        FESettings(supports={"kind": "pinned"})
    with pytest.raises(FEError, match="supports.type must be one of"):
        FESettings(supports={"type": "clamped"})


def test_the_area_load_case_is_there_only_without_actions_of_the_design():
    assert FESettings().area_load == DEFAULT_AREA_LOAD
    assert [c.name for c in FESettings().cases()] == ["self-weight", "area-load"]
    s = FESettings(loads={"concrete_thickness": 0.05})
    assert s.area_load == 0.0
    assert [c.name for c in s.cases()] == ["self-weight", "wet-concrete"]
    s = FESettings(loads={"concrete_thickness": 0.05}, area_load=900.0, load_cases=["area-load"])
    assert [c.name for c in s.cases()] == ["area-load"]
    assert FESettings(checks=False).cases() == []
    case = s.cases()[0]
    assert isinstance(case, LoadCase) and case.to_dict()["actions"][1]["value_N_per_m2"] == 900.0


def test_design_sections_of_loads_supports_and_hinges():
    design = load_design("examples/cone.toml")
    assert design.loads.deflection_limit == 500.0 and design.supports.type == "pinned"
    assert design.hinges.translational_stiffness is None
    base = {
        "crease": {"profile": "arc", "span": 2.0, "rise": 0.6},
        "rulings": {"type": "orthogonal"},
        "deployment": {"alpha": 30.0},
        "layout": {"width": 0.3},
    }
    with pytest.raises(DesignError, match="supports.type"):
        validate({**base, "supports": {"type": "clamped"}})
    with pytest.raises(DesignError, match="loads.concrete_area"):
        validate({**base, "loads": {"concrete_area": "vertical"}})
    with pytest.raises(DesignError, match="loads.snow"):
        validate({**base, "loads": {"snow": -1.0}})
    with pytest.raises(DesignError, match="loads.stiffnes|unknown"):
        validate({**base, "loads": {"stiffnes": 1.0}})


@pytest.fixture(scope="module")
def cone_mesh():
    model = CCUModel(load_design("examples/cone.toml"))
    mesh = mesh_model(model, element_size=0.2)
    deployed = mesh.kinematic(model.deploy(40.0).deployed)
    return model, mesh, deployed


def test_support_models(cone_mesh):
    model, mesh, deployed = cone_mesh
    pinned = support_model(mesh, deployed)
    assert not pinned.released.any() and len(pinned.ground) == 0
    assert np.bincount(pinned.side).tolist() == [len(mesh.supports) // 2] * 2
    springs = support_model(mesh, deployed, kind="springs", stiffness=2.0e6)
    assert springs.released.all() and len(springs.ground) == len(mesh.supports)
    # k per metre of foot line: the feet are the end rulings, 0.4 m each, 2 plates x 2 ends
    assert springs.stiffness[:, 0].sum() == pytest.approx(2.0e6 * 4 * 0.4, rel=1e-9)
    tie = support_model(mesh, deployed, tie=True, tie_stiffness=1.0e6, span_axis=model.axes[0])
    end = tie.side == 1
    axis = int(np.argmax(np.abs(model.axes[0])))
    assert tie.released[end, axis].all() and not tie.released[~end].any()
    assert tie.released.sum() == end.sum()
    # every plate's tie: its stiffness shared among the plate's end feet
    assert tie.stiffness[:, axis].sum() == pytest.approx(2 * 1.0e6, rel=1e-12)
    assert np.all(np.delete(tie.stiffness, axis, axis=1) == 0.0)
    with pytest.raises(FEError, match="a tie needs the span along a global axis"):
        support_model(mesh, deployed, tie=True, span_axis=np.array([0.6, 0.8, 0.0]))
    with pytest.raises(FEError, match="supports.stiffness must be > 0"):
        support_model(mesh, deployed, kind="springs", stiffness=0.0)
