"""The load cases of ``ccu validate`` on the cone pair: equilibrium of every case, the tie and
the springs, the asymmetric case, per-case buckling and design values."""

from __future__ import annotations

import numpy as np
import pytest

from compas_ccu.cli import main
from compas_ccu.design import Design, load_design
from compas_ccu.fea.loads import GRAVITY
from compas_ccu.fea.validation import validate
from compas_ccu.model import CCUModel
from compas_ccu.thickness import ThickModel

pytestmark = pytest.mark.slow

LOADS = {
    "concrete_thickness": 0.05,
    "concrete_density": 2500.0,
    "concrete_area": "projected",
    "live": 750.0,
    "snow": 800.0,
    "wind": -300.0,
    "gamma_G": 1.35,
    "gamma_Q": 1.5,
}
FAST = {"element_size": 0.2, "steps": 3}


@pytest.fixture(scope="module")
def cone():
    """The cone pair in 8 mm: the FE figures below were measured at 8 mm (the example is 5 mm;
    there the FE holds its feet with 247 N for the kinematic 124 N, twice, not yet explained)."""
    document = load_design("examples/cone.toml").document
    document["plates"]["thickness"] = 0.008
    return CCUModel(Design(document))


@pytest.fixture(scope="module")
def pinned(cone):
    return validate(cone, engine="kratos", loads=LOADS, **FAST)


def plan_area(v) -> tuple:
    """Surface and plan area of the deployed plates (exact kinematic shape)."""
    x = v.kinematic[v.deployment_steps - 1]
    q = x[v.mesh.elements]
    n = np.cross(q[:, 2] - q[:, 0], q[:, 3] - q[:, 1]) / 2.0
    return np.linalg.norm(n, axis=1).sum(), np.abs(n @ v.model.axes[1]).sum()


def test_every_case_is_in_equilibrium_with_its_reactions(pinned):
    v = pinned
    c = v.summary()["checks"]
    surface, plan = plan_area(v)
    w = v.settings.material.density * GRAVITY * v.settings.thickness
    concrete = 2500.0 * GRAVITY * 0.05
    vertical = {  # the ULS vertical load of every case, N
        "self-weight": 1.35 * w * surface,
        "wet-concrete": 1.35 * w * surface + 1.5 * concrete * plan,
        "construction": 1.35 * w * surface + 1.5 * (concrete + 750.0) * plan,
        "snow": 1.35 * w * surface + 1.5 * 800.0 * plan,
        "snow-half": 1.35 * w * surface + 1.5 * 800.0 * plan / 2.0,
    }
    names = [k["name"] for k in c["cases"]]
    assert names == ["self-weight", "wet-concrete", "construction", "snow", "snow-half", "wind"]
    for k in c["cases"]:
        r = k["reactions_uls"]
        total = r["start_vertical_N"] + r["end_vertical_N"]
        if k["name"] in vertical:
            assert total == pytest.approx(vertical[k["name"]], rel=2e-3), k["name"]
        # vertical loads: the horizontal reactions balance each other
        assert (
            np.add(r["start_N"], r["end_N"])[[0, 1]] == pytest.approx([0, 0], abs=1e-3 * total)
            or k["name"] == "wind"
        )
    half = c["cases"][4]["reactions_uls"]
    assert half["start_vertical_N"] > 1.5 * half["end_vertical_N"]  # snow on the start half
    wind = c["cases"][5]
    assert wind["reactions_uls"]["start_vertical_N"] < 0.0  # suction lifts the light cone


def test_cases_have_their_own_design_strength_and_buckling_factor(pinned):
    c = pinned.summary()["checks"]
    by = {k["name"]: k for k in c["cases"]}
    assert by["self-weight"]["basis"]["k_mod"] == 0.6  # permanent
    assert by["wet-concrete"]["basis"]["k_mod"] == 0.9  # short-term
    assert by["wind"]["basis"]["k_mod"] == 1.1  # instantaneous
    for k in c["cases"]:
        assert k["utilisation_max"] == pytest.approx(
            k["stress_max_MPa"] / k["strength_MPa"], rel=1e-12
        )
        assert k["buckling_factor"] > 1.0
    # more load, less buckling margin; self-weight alone the largest
    assert by["construction"]["buckling_factor"] < by["wet-concrete"]["buckling_factor"]
    assert by["self-weight"]["buckling_factor"] == max(k["buckling_factor"] for k in c["cases"])
    assert c["buckling_factor"] == by["construction"]["buckling_factor"]
    assert c["governing"]["buckling"] == "construction"
    # deflection grows with the load; the state returns after every case (elastic)
    assert by["construction"]["deflection_max_m"] > by["wet-concrete"]["deflection_max_m"]
    assert c["deflection_ratio"] == max(k["deflection_ratio"] for k in c["cases"])
    # design stiffness (fea.design_values): lambda_d = lambda_mean / (gamma_M (1 + psi2 k_def))
    for k in c["cases"]:
        st = k["stiffness"]
        assert (st["gamma_M"], st["k_def"]) == (1.2, 0.8)
        assert k["buckling_factor_instantaneous"] == pytest.approx(
            k["buckling_factor_mean"] / 1.2, rel=1e-14
        )
        assert k["buckling_factor"] == pytest.approx(
            k["buckling_factor_mean"] / (1.2 * (1.0 + st["psi2"] * 0.8)), rel=1e-14
        )
    assert by["self-weight"]["stiffness"]["psi2"] == 1.0  # permanent only
    # final deflection: self-weight alone creeps by (1 + k_def)
    sw = by["self-weight"]
    assert sw["deflection_final_max_m"] == pytest.approx(1.8 * sw["deflection_max_m"], rel=1e-12)
    # snow (psi2 = 0): u_G (1 + k_def) + u_Q, between the instantaneous and 1.8 times it
    snow = by["snow"]
    assert snow["deflection_max_m"] < snow["deflection_final_max_m"]
    assert snow["deflection_final_max_m"] < 1.8 * snow["deflection_max_m"]
    r = pinned.result
    k0 = pinned.deployment_steps - 1
    for entry in pinned.history.load_steps[:-1]:
        back = entry["uls"] + 1
        assert np.abs(r.displacements[back] - r.displacements[k0]).max() < 1e-6


def test_a_tie_takes_the_thrust_and_springs_let_the_feet_settle(cone, pinned):
    base = pinned.summary()["checks"]["cases"][1]
    tie = validate(
        cone,
        engine="kratos",
        loads=LOADS,
        load_cases=["wet-concrete"],
        supports={"tie": True, "tie_stiffness": 1.0e6},
        **FAST,
    ).summary()["checks"]["cases"][0]
    r = tie["reactions_uls"]
    axis = int(np.argmax(np.abs(cone.axes[0])))
    # the end feet slide: no thrust on them; the start feet balance the loads alone
    assert abs(r["end_N"][axis]) < 1e-6 * r["tie_N"]
    assert abs(r["start_N"][axis]) < 1e-3 * r["tie_N"]
    assert r["tie_N"] > 100.0
    assert tie["deflection_max_m"] > base["deflection_max_m"]
    soft = validate(
        cone,
        engine="kratos",
        loads=LOADS,
        load_cases=["wet-concrete"],
        supports={"type": "springs", "stiffness": 1.0e6},
        **FAST,
    )
    case = soft.summary()["checks"]["cases"][0]
    rs = case["reactions_uls"]
    assert rs["start_vertical_N"] + rs["end_vertical_N"] == pytest.approx(
        base["reactions_uls"]["start_vertical_N"] + base["reactions_uls"]["end_vertical_N"],
        rel=1e-3,
    )
    # the feet moved by about their share of the load over the spring stiffness
    h = soft.history
    sls = h.load_steps[0]["sls"]
    feet = h.mesh.supports
    settle = np.linalg.norm(
        h.result.displacements[sls][feet] - h.result.displacements[2][feet], axis=1
    )
    per_foot = case["reactions_sls"]["start_vertical_N"] / (2 * 0.4 * 1.0e6)
    assert 0.3 * per_foot < settle.mean() < 3.0 * per_foot
    assert case["deflection_max_m"] > base["deflection_max_m"]


def test_the_kinematic_foot_force_is_the_fe_holding_force(cone, pinned):
    """The force between the feet from the plates' bending energy (thickness.actuation) is
    what the FE supports hold at the deployed state, and the FE work is that energy."""
    kin = ThickModel(cone).actuation(np.linspace(0.0, 40.0, 21))
    h = pinned.history
    k0 = h.deployment_steps - 1
    r = h.result.reactions[k0]
    axis = cone.axes[0]
    side = h.supports.side[np.searchsorted(h.mesh.supports, h.problem.fixed)]
    fe = abs(float(r[side == 0].sum(axis=0) @ axis))
    # the thrust of the held feet: 686 N on this coarse mesh (0.2 m), 596 N at 0.1 m, for 527
    assert fe == pytest.approx(abs(kin.force[-1]), rel=0.35)
    work = pinned.summary()["load_path"]["work_J"][-1]
    assert work == pytest.approx(kin.energy[-1], rel=0.25)  # 86 J (84 J at 0.1 m) for 108 J
    foot = pinned.summary()["load_path"]["foot_force_N"]
    assert foot[0] is None  # the flat stack: a 0/0 limit
    assert abs(foot[-1]) == pytest.approx(abs(kin.force[-1]), rel=0.2)  # 468 N (455 N) for 527


def test_validate_runs_the_chosen_case_from_the_command_line(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("CCU_CACHE_DIR", str(tmp_path / "cache"))
    design = tmp_path / "cone.toml"
    cone = open("examples/cone.toml", encoding="utf-8").read()
    assert cone.count("\n[loads]") == 1  # its last section: replaced by a snow load
    design.write_text(
        cone.split("\n[loads]")[0] + "\n[loads]\nsnow = 800.0\n\n[supports]\ntie = true\n"
    )
    args = ["validate", str(design), "--out", str(tmp_path / "fe"), "--no-figures"]
    # the 5 mm cone under half-span snow with a tie fails its final deflection (1.19): the
    # checks are not what this test is about
    args += ["--allow-exceeded"]
    assert main(args + ["--steps", "3", "--element-size", "0.2", "--load-case", "snow-half"]) == 0
    out = capsys.readouterr().out
    assert "load cases (feet pinned with a tie;" in out
    assert "  snow-half " in out and "  snow " not in out and "  self-weight " not in out
    assert "governing: deflection snow-half, utilisation snow-half, buckling snow-half" in out
    assert main(args + ["--load-case", "wind"]) == 2
    assert "load case(s) ['wind'] are not defined" in capsys.readouterr().err

    # the report of the design shows the load cases of its last validation
    report = ["report", str(design), "--out", str(tmp_path / "rep"), "--steps", "2"]
    assert main(report + ["--frames", "2", "--quiet"]) == 0
    page = (tmp_path / "rep" / "index.html").read_text(encoding="utf-8")
    assert '<h2 id="structural">Structural checks (FE, load cases)</h2>' in page
    assert (
        "<th>snow-half</th><td>self-weight 29 N/m² (surface, γ 1.35), snow (half span) 800" in page
    )  # 5 mm plywood: 600 kg/m3 x 9.81 x 0.005 m = 29.4 N/m2
    assert "feet pinned with a tie" in page
