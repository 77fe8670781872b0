"""Axis-shift hinges in the FE (compas_ccu.fea.eccentric): eccentric shell sections checked
against the closed form of an eccentric cantilever, the reference surface against the thick
kinematics, and the deployment against the hinges on the mid-surfaces."""

from __future__ import annotations

import numpy as np
import pytest
from tests.test_fea_engines import OPTIONS, column, grid

from compas_ccu.fea.eccentric import FaceHinges
from compas_ccu.fea.mesh import mesh_model
from compas_ccu.fea.problem import FEError, FEProblem, LoadPattern
from compas_ccu.fea.settings import FESettings
from compas_ccu.materials import Material
from compas_ccu.model import load_model
from compas_ccu.thickness import ThickModel

STRIP = Material.isotropic("strip", 1.0e9, 0.0, 1.0, 1.0e9)  # nu = 0: a plate strip is a beam


def eccentric_cantilever(e: float, P: float):
    """A clamped strip, its material ``e`` below its nodes, pulled by P at the nodes' line."""
    L, b, t, nx, ny = 1.0, 0.2, 0.01, 16, 2
    nodes, elements = grid(0.0, L, b, nx, ny)  # normals +z: the material at z = -e
    root, tip = column(0, ny), column(nx, ny)
    loads = np.zeros((len(nodes), 6))
    loads[tip, 0] = P / len(tip)
    problem = FEProblem(
        nodes,
        elements,
        STRIP,
        t,
        1,
        fixed=root,
        fixed_rotations=root,
        offsets=np.full(len(elements), e),
        patterns=[LoadPattern("P", loads, np.array([1.0]))],
    )
    return problem, tip, L, b, t


@pytest.mark.slow
def test_an_eccentric_cantilever_bends_by_the_lever_arm_of_its_load():
    """Axial pull P applied e above the material's axis: uniform moment P e, so the tip
    deflects w = -P e L² / (2 EI) (downwards), moves u = P L / EA + e θ along the axis with
    θ = P e L / EI, and the moment about the mid-surface is P e per width (the engine reports
    the moments about the mid-surface, not about the nodes: there it would be 0)."""
    from compas_ccu.fea.engines import solve

    e, P = 0.005, 0.1  # a small load: the linear closed form (P L² / EI = 0.006)
    problem, tip, L, b, t = eccentric_cantilever(e, P)
    result = solve(problem, "kratos", **OPTIONS)
    assert result.converged, result.message
    EI, EA = STRIP.E1 * b * t**3 / 12.0, STRIP.E1 * b * t
    w = result.displacements[-1][tip, 2].mean()
    u = result.displacements[-1][tip, 0].mean()
    theta = P * e * L / EI
    assert w == pytest.approx(-P * e * L**2 / (2.0 * EI), rel=0.01)
    assert u == pytest.approx(P * L / EA + e * theta, rel=0.02)
    forces = result.forces[-1]
    assert forces[:, 0] == pytest.approx(P / b, rel=1e-6)
    assert forces[:, 3] == pytest.approx(P * e / b, rel=0.01)
    # without the offset the same pull only stretches the strip
    plain, _, _, _, _ = eccentric_cantilever(0.0, P)
    straight = solve(plain, "kratos", **OPTIONS)
    assert abs(straight.displacements[-1][tip, 2]).max() < 1e-3 * abs(w)


def test_opensees_refuses_eccentric_shells():
    pytest.importorskip("openseespy")
    from compas_ccu.fea.engines import solve

    problem, _, _, _, _ = eccentric_cantilever(0.004, 1.0)
    with pytest.raises(FEError, match=r"offsets up to 0.004 m\) need engine 'kratos'"):
        solve(problem, "opensees", **OPTIONS)


def test_axis_shift_settings_name_the_engine_and_the_value():
    with pytest.raises(FEError, match="'axis-shift' needs engine 'kratos'.*'opensees'"):
        FESettings(engine="opensees", hinge_eccentricity="axis-shift")
    with pytest.raises(FEError, match="hinge_eccentricity must be one of .*'faces'"):
        FESettings(hinge_eccentricity="faces")


def test_offsets_problem_checks():
    problem, _, _, _, t = eccentric_cantilever(0.0, 1.0)
    with pytest.raises(FEError, match="offsets must be"):
        FEProblem(problem.nodes, problem.elements, STRIP, t, 1, offsets=np.zeros(3))
    with pytest.raises(FEError, match="offsets must be"):
        FEProblem(problem.nodes, problem.elements, STRIP, t, 1, offsets=np.full(32, 2 * t))


@pytest.mark.parametrize("design", ["examples/cone.toml", "examples/vault.toml"])
def test_the_reference_surface_deploys_with_the_thick_plates(design):
    """The nodes lie on the hinge lines at the creases, the tied crease nodes of two plates
    coincide along the whole path, every element's offset is its nodes' mean distance from
    the mid-surface, at most t/2, and the inner plates go from one face to the other."""
    model = load_model(design)
    t = 0.008
    mesh = mesh_model(model, element_size=0.1)
    faces = FaceHinges.build(mesh, ThickModel(model, thickness=t))
    alphas = [0.0, 10.0, model.design.alpha]
    nodes = faces.positions(mesh, alphas)
    a, b = mesh.ties[:, 0], mesh.ties[:, 1]
    assert np.abs(nodes[:, a] - nodes[:, b]).max() < 1e-12
    assert np.abs(faces.offsets).max() <= 0.5 * t + 1e-15
    # the flat stack: a plate's crease nodes lie t/2 off its (plane) mid-surface, the rest
    # at most t/2 (the reference surface is ruled, not a plane, where rulings fan out)
    mid = mesh.kinematic(faces.thick.hinge_points([0.0])[0][0])
    creased = np.zeros(len(mesh.nodes), dtype=bool)
    creased[mesh.ties.ravel()] = True
    for plate in np.unique(mesh.node_plate):
        on = mesh.node_plate == plate
        centre = mid[on].mean(axis=0)
        normal = np.linalg.svd(mid[on] - centre)[2][-1]
        assert np.abs((mid[on] - centre) @ normal).max() < 1e-12  # the flat plate
        away = np.abs((nodes[0][on] - centre) @ normal)
        assert away.max() <= 0.5 * t + 1e-12
        assert away[creased[on]] == pytest.approx(0.5 * t, abs=1e-12)
    # lengths along the rulings (straight lines of the thick placement) are kept exactly
    edge = mesh.elements[:, [0, 1]]
    lengths = np.linalg.norm(nodes[:, edge[:, 0]] - nodes[:, edge[:, 1]], axis=-1)
    ruling_like = np.abs(lengths - lengths[0]).max(axis=0) < 1e-12
    assert ruling_like.sum() > 0
    if design.endswith("vault.toml"):  # inner plates: offsets of both signs on one plate
        assert faces.offsets.max() > 0.25 * t and faces.offsets.min() < -0.25 * t


@pytest.mark.slow
def test_the_cone_deploys_with_axis_shift_hinges():
    """The cone pair with hinges on the faces: the same deployment as on the mid-surfaces
    (kinematic deviation below 0.5 %, stresses within 10 %), hinge forces changed by the
    lever arm (the resultant within 25 %), and the summary says which hinges were used."""
    from compas_ccu.fea.validation import validate

    model = load_model("examples/cone.toml")
    runs = {
        e: validate(model, engine="kratos", hinge_eccentricity=e, checks=False, steps=8)
        for e in ("none", "axis-shift")
    }
    mid, face = (runs[e].summary() for e in ("none", "axis-shift"))
    assert face["deviation"]["max_percent"] < 0.5
    assert face["stresses"]["max_von_mises_MPa"] == pytest.approx(
        mid["stresses"]["max_von_mises_MPa"], rel=0.1
    )
    r_mid = np.linalg.norm(mid["hinges"][0]["resultant_N"])
    r_face = np.linalg.norm(face["hinges"][0]["resultant_N"])
    assert r_face == pytest.approx(r_mid, rel=0.25) and r_face != pytest.approx(r_mid, rel=0.01)
    assert face["settings"]["hinge_eccentricity"] == "axis-shift"


def test_the_console_says_where_the_hinges_are():
    from compas_ccu.cli.fea import _hinge_line

    face = {"hinge_eccentricity": "axis-shift", "hinge_stiffness": 0.0}
    assert _hinge_line(face) == (
        "hinges: on the plates' faces (axis-shift, eccentric shells), tied, free to turn"
    )
    springs = {"hinge_translational_stiffness": 1e9, "hinge_stiffness": 50.0}
    assert _hinge_line(springs) == (
        "hinges: on the mid-surfaces, translational springs 1e+09 N/m/m, rotational springs "
        "50 Nm/rad/m"
    )
