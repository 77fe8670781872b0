"""The studio with a target or a scan (docs/studio.md, "Target and scan"): the distance of every
plate vertex to the target (against brute force), the folders a target is read from, the
colours of the view through the app's own frame, and a fit of free keys run from the session
in the background process and offered as one undoable edit."""

from __future__ import annotations

import dataclasses
import json
import os
import shutil

import numpy as np
import pytest

from compas_ccu.design import Design
from compas_ccu.errors import CCUError, GeometryError, OptionError
from compas_ccu.fit import plate_triangles, sample_triangles
from compas_ccu.limits import LIMITS
from compas_ccu.model import CCUModel, load_model
from compas_ccu.studio import StudioSession
from compas_ccu.studio.export import BackgroundProcess
from compas_ccu.studio.scene import colored_glb
from compas_ccu.studio.target import (
    DISTANCE_FLOOR,
    TARGET_COLORING,
    apply_fit,
    distance_colors,
    fit_html,
    fit_job,
    fit_request,
    load_target,
    suggested_free,
    target_state,
)
from conftest import EXAMPLES

pytest.importorskip("trimesh")

ALPHA = 27.0  # the target: the vault deployed to 27 degrees (its design angle is 30)


def plates_obj(model, alpha, path) -> None:
    """The plates of ``model`` at ``alpha`` as an OBJ mesh (two triangles per quad)."""
    tri, _ = plate_triangles(model.vertices([alpha])[0], model.faces)
    v = tri.reshape(-1, 3)
    lines = [f"v {x:.17g} {y:.17g} {z:.17g}" for x, y, z in v]
    lines += [f"f {3 * i + 1} {3 * i + 2} {3 * i + 3}" for i in range(len(tri))]
    path.write_text("\n".join(lines) + "\n")


def plate_points(model, alpha, count, *, seed=3):
    tri, _ = plate_triangles(model.vertices([alpha])[0], model.faces)
    flat = np.arange(len(tri) * 3).reshape(-1, 3)
    return sample_triangles(tri.reshape(-1, 3), flat, count, seed=seed)[0]


@pytest.fixture
def folders(tmp_path):
    design = tmp_path / "designs"
    design.mkdir()
    shutil.copy(EXAMPLES / "vault.toml", design / "vault.toml")
    plates_obj(load_model(EXAMPLES / "vault.toml"), ALPHA, design / "target27.obj")
    return design, tmp_path / "out"


@pytest.fixture
def session(folders):
    design, out = folders
    return StudioSession.start(design / "vault.toml", out=out)


def brute_force(vertices, target) -> np.ndarray:
    """The distance of :func:`compas_ccu.fit.target_distance`, with the nearest target point
    found by comparing every vertex with every target point (numpy, no k-d tree)."""
    v = vertices.reshape(-1, 3)
    points, normals = target.target.points, target.target.normals
    nearest = np.empty(len(v), dtype=np.int64)
    for s in range(0, len(v), 50):
        d2 = ((v[s : s + 50, None, :] - points[None]) ** 2).sum(axis=2)
        nearest[s : s + 50] = d2.argmin(axis=1)
    delta = v - points[nearest]
    normal = (delta * normals[nearest]).sum(axis=1)
    tangential = np.sqrt(np.maximum((delta**2).sum(axis=1) - normal**2, 0.0))
    excess = np.maximum(tangential - target.allowance, 0.0)
    return np.sqrt(normal**2 + excess**2).reshape(vertices.shape[:-1])


@pytest.mark.slow  # the distance over the whole path (~9 s)
def test_the_distance_is_zero_at_the_targets_angle_and_grows_away_from_it(session):
    target = load_target(session.files, "target27.obj")
    assert len(target.target) == 50_000 and target.target.kind == "mesh"
    assert 0.0 < target.spacing < target.allowance < 0.05
    model = session.model
    rms = {}
    for alpha in (ALPHA, 26.0, 25.0, 30.0, 40.0):
        vertices = model.vertices([alpha])[0]
        state = target_state(target, vertices, model.plate_ids, alpha)
        exact = brute_force(vertices, target)
        np.testing.assert_allclose(state.distance, exact, rtol=0, atol=1e-12)
        assert state.rms == pytest.approx(np.sqrt(np.mean(exact**2)), abs=1e-12)
        assert state.max == pytest.approx(exact.max(), abs=1e-12)
        assert [p[0] for p in state.plates] == list(model.plate_ids)
        assert state.plates[0][1] == pytest.approx(np.sqrt(np.mean(exact[0] ** 2)), abs=1e-12)
        rms[alpha] = state.rms
    assert rms[ALPHA] < 1e-4  # on the target (sampled: 0.1 mm)
    assert rms[ALPHA] < rms[26.0] < rms[25.0] < rms[30.0] < rms[40.0]  # away from 27 deg
    assert 0.005 < rms[26.0] < 0.02 and rms[40.0] > 0.05  # 1 deg: ~1 cm; 13 deg: ~11 cm


def test_a_point_cloud_target_gets_normals_and_the_same_measure(session, folders):
    design, _ = folders
    np.savetxt(design / "scan.xyz", plate_points(session.model, ALPHA, 20_000))
    target = load_target(session.files, "scan.xyz")
    assert target.target.kind == "points" and target.target.normals.shape == (20_000, 3)
    vertices = session.model.vertices([33.0])[0]
    state = target_state(target, vertices, session.model.plate_ids, 33.0)
    np.testing.assert_allclose(state.distance, brute_force(vertices, target), atol=1e-12)


@pytest.mark.parametrize(
    "name, words",
    [
        ("../outside.xyz", "'..' and backslashes are not allowed"),
        ("/etc/passwd.xyz", "give a name inside the design folder"),
        ("~/scan.xyz", "give a name inside the design folder"),
        ("vault.toml", "a target is one of .obj, .stl"),
        ("missing.xyz", "'missing.xyz': no such file"),
        (".ccu-studio/x.xyz", "is the studio's own folder"),
    ],
)
def test_a_target_outside_the_design_folder_is_refused_in_one_line(session, name, words):
    with pytest.raises((OptionError, GeometryError)) as info:
        load_target(session.files, name)
    assert words in str(info.value) and "\n" not in str(info.value)


def test_a_link_out_of_the_design_folder_is_refused(session, folders, tmp_path):
    design, _ = folders
    outside = tmp_path / "elsewhere"
    outside.mkdir()
    np.savetxt(outside / "scan.xyz", np.eye(3))
    os.symlink(outside / "scan.xyz", design / "link.xyz")
    with pytest.raises(OptionError, match="leads outside the design folder"):
        load_target(session.files, "link.xyz")
    # the command line names a file the user chose: read wherever it is
    assert len(load_target(session.files, outside / "scan.xyz", command_line=True).target) == 3


def test_ccu_studio_refuses_a_missing_target_in_one_line(tmp_path, capsys):
    from compas_ccu.cli import main

    argv = ["studio", str(EXAMPLES / "vault.toml"), "--target", str(tmp_path / "none.xyz"),
            "--out", str(tmp_path / "o"), "--no-browser"]  # fmt: skip
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "none.xyz': no such file" in err and err.count("\n") == 1
    assert not (tmp_path / "o").exists()


# -- the app's frame (a server on a free port, no browser) ----------------------------------------
@pytest.fixture
def studio(session):
    pytest.importorskip("viser")
    from compas_ccu.studio.app import Studio
    from studio_page import free_port

    app = Studio(session, port=free_port(), target=load_target(session.files, "target27.obj"))
    try:
        assert app.wait_idle(120)
        yield app
    finally:
        app.stop()


def _frame(app, alpha):
    app.alpha = alpha
    app.redraw()
    assert app.wait_idle(60)
    return app.last_view, app.target_panel.state


def test_the_colours_follow_the_slider_and_the_edits(studio):
    assert studio.coloring == TARGET_COLORING
    assert TARGET_COLORING in studio.coloring_menu.options
    view, state = _frame(studio, ALPHA)
    assert state.alpha == ALPHA and state.rms < 1e-4
    hi = max(state.max, DISTANCE_FLOOR)
    np.testing.assert_array_equal(view.vertex_colors, distance_colors(state.distance, hi))
    assert view.legend["scale"] == ("viridis", 0.0, hi * 1000.0, " mm")
    glb = studio.scene._handles["/ccu/colored"]  # the plates in their vertex colours
    assert glb.visible and not studio.scene._handles["/ccu/plates/0"].visible
    before = glb.glb_data
    assert before[:4] == b"glTF"
    assert "ccu-target-rms" in studio.target_panel.checks.content

    moved, far = _frame(studio, 35.0)  # the slider
    assert far.alpha == 35.0 and far.rms > 0.03
    assert np.abs(moved.vertex_colors.astype(int) - view.vertex_colors.astype(int)).max() > 50
    np.testing.assert_array_equal(
        moved.vertex_colors, distance_colors(far.distance, max(far.max, DISTANCE_FLOOR))
    )
    assert glb.glb_data != before  # sent to the page
    assert f"{far.rms * 1000:.2f} mm" in studio.target_panel.checks.content

    studio.apply_action(lambda: studio.session.edit("crease", "rise", 1.2))  # an edit
    edited, after = _frame(studio, 35.0)
    assert after.rms != pytest.approx(far.rms, rel=1e-3)

    studio.coloring = "crease kind"  # another colouring: the plates as before
    plain, _ = _frame(studio, 35.0)
    assert plain.vertex_colors is None
    handles = studio.scene._handles  # of the edited model
    assert not handles["/ccu/colored"].visible and handles["/ccu/plates/0"].visible
    studio.target_panel.show_target(None)  # no target: no colouring offered
    assert TARGET_COLORING not in studio.coloring_menu.options


# -- the fit ------------------------------------------------------------------------------------
def test_suggested_bounds_hold_the_design_values(session):
    assert suggested_free(session.model) == "crease.rise=0.75:1.25, deployment.alpha=20:40"


def test_a_fit_that_fails_says_why_and_changes_nothing(session):
    target = load_target(session.files, "target27.obj")
    with pytest.raises(CCUError, match="crease.height"):
        fit_request(session, target, "crease.height=1:2")
    with pytest.raises(OptionError, match="crease.rise: a free key needs bounds"):
        fit_request(session, target, "crease.rise")
    with pytest.raises(OptionError, match="load a target"):
        fit_request(session, None, "crease.rise=0.5:1.5")
    request = fit_request(session, target, "crease.rise=0.5:1.5", points=300, max_evaluations=2)
    outcome = fit_job(**request.job(dataclasses.asdict(LIMITS)))  # what the process runs
    assert "did not converge within 2 evaluations" in outcome["error"]
    assert "the fit failed: the fit did not converge" in fit_html(outcome)
    before = session.generation
    with pytest.raises(OptionError, match="the fit failed"):
        apply_fit(session, request, outcome)
    assert session.generation == before
    session.edit("crease", "span", 2.6)  # an edit while the fit ran
    fitted = {"record": {"parameters": {"crease.rise": 1.1}}}
    with pytest.raises(OptionError, match="the design changed while fitting: fit again"):
        apply_fit(session, request, fitted)
    assert session.model.design.crease.rise == 1.0


def test_a_fitted_value_is_written_in_the_files_units(tmp_path):
    folder = tmp_path / "d"
    folder.mkdir()
    text = (EXAMPLES / "vault.toml").read_text()
    text = text.replace("[design]\n", '[design]\nunits = "mm"\n')
    text = text.replace("span = 2.5 ", "span = 2500.0 ").replace("rise = 1.0 ", "rise = 1000.0 ")
    text = text.replace("spacing = 0.12 ", "spacing = 120.0 ")
    text = text.replace("thickness = 0.006 ", "thickness = 6.0 ")
    text = text.replace("hinge_width = 0.05 ", "hinge_width = 50.0 ")
    text = text.replace("concrete_thickness = 0.08 ", "concrete_thickness = 80.0 ")
    (folder / "mm.toml").write_text(text)
    session = StudioSession.start(folder / "mm.toml", out=tmp_path / "o")
    assert session.problem is None, session.problem
    np.savetxt(folder / "t.xyz", np.eye(3))
    request = fit_request(session, load_target(session.files, "t.xyz"), "crease.rise=0.5:1.5")
    apply_fit(session, request, {"record": {"parameters": {"crease.rise": 1.1}}})
    assert session.valid_document["crease"]["rise"] == 1100.0
    assert session.model.design.crease.rise == pytest.approx(1.1)


@pytest.mark.slow
def test_the_fit_from_the_session_recovers_rise_and_alpha(session, folders):
    design, out = folders
    doc = session.model.design.metric_document()
    doc["crease"]["rise"], doc["deployment"]["alpha"] = 1.1, 28.0
    np.savetxt(design / "target.xyz", plate_points(CCUModel(Design(doc)), 28.0, 5000))
    target = load_target(session.files, "target.xyz")
    request = fit_request(session, target, suggested_free(session.model), points=1500)
    process = BackgroundProcess()  # as the page runs it
    try:
        outcome = process.run(fit_job, **request.job(dataclasses.asdict(LIMITS))).result(600)
    finally:
        process.stop()
    assert outcome["pid"] != os.getpid() and "error" not in outcome, outcome
    written = apply_fit(session, request, outcome, out=out)
    fitted = session.model.design
    assert fitted.crease.rise == pytest.approx(1.1, rel=0.01)  # docs/fit.md: within 1 %
    assert fitted.deployment.alpha == pytest.approx(28.0, abs=0.2)
    record = json.loads(written.read_text())
    assert written == out / "vault" / "fit" / "fit.json" and record["rms"] < 0.003
    assert record["start"] == {"crease.rise": 1.0, "deployment.alpha": 30.0}
    fitted_rms = target_state(target, design_vertices(session), (), 28.0).rms
    assert session.undo() and session.model.design.crease.rise == 1.0  # one undoable edit
    start_rms = target_state(target, design_vertices(session), (), 30.0).rms
    # the colours of the design state: the fitted one far nearer the target (a 5,000-point
    # cloud with estimated normals keeps a floor of about its spacing, 18 mm, at the creases)
    assert fitted_rms < 0.3 * start_rms, (fitted_rms, start_rms)


def design_vertices(session):
    model = session.model
    return model.vertices([model.alpha_design])[0]


def test_the_colored_mesh_is_a_glb_with_a_colour_per_vertex():
    import io
    import struct

    import trimesh

    vertices = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]])
    colors = np.array([[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 255]], np.uint8)
    data = colored_glb(vertices, [[0, 1, 2], [1, 3, 2]], colors)
    length = struct.unpack("<I", data[12:16])[0]
    gltf = json.loads(data[20 : 20 + length])
    assert gltf["meshes"][0]["primitives"][0]["attributes"] == {"POSITION": 0, "COLOR_0": 1}
    assert len(data) % 4 == 0 and struct.unpack("<I", data[8:12])[0] == len(data)
    mesh = trimesh.load(io.BytesIO(data), file_type="glb").to_geometry()
    np.testing.assert_allclose(mesh.vertices, vertices)
    np.testing.assert_array_equal(mesh.faces, [[0, 1, 2], [1, 3, 2]])
    body = data[20 + length + 8 :]
    rgba = np.frombuffer(body[48:64], np.uint8).reshape(4, 4)
    assert rgba[:, 3].tolist() == [255] * 4 and rgba[0, :3].tolist() == [255, 0, 0]
    assert rgba[3, :3].tolist() == [255, 255, 255]  # linear values: white and primaries stay


# -- in a real browser (``make browser``; ~20 s) ------------------------------------------------
def _near(img, rgb, tol: int = 40) -> int:
    return int((np.abs(img.astype(int) - np.array(rgb)).max(axis=2) <= tol).sum())


@pytest.mark.slow
def test_the_page_loads_a_target_and_colours_the_plates(session):
    pytest.importorskip("viser")
    pytest.importorskip("playwright")
    from playwright.sync_api import sync_playwright

    from browser import CHROMIUM_ARGS, chromium
    from compas_ccu.studio.app import Studio
    from studio_page import canvas, changed, field, free_port, open_page, settle, tab

    exe = chromium()
    if not exe:
        pytest.fail("no chromium for the studio browser tests: run `make browser`")
    app = Studio(session, port=free_port())
    errors = []
    try:
        assert app.wait_idle(60)
        with sync_playwright() as p:
            browser_ = p.chromium.launch(executable_path=exe, args=CHROMIUM_ARGS, headless=True)
            page = open_page(browser_, app.url, log=errors)
            before = canvas(page, "target-before")
            tab(page, "Target")
            field(page, "target file").fill("../vault.toml")
            page.get_by_role("button", name="Load", exact=True).click()
            page.get_by_text("'..' and backslashes are not allowed").wait_for(timeout=10_000)
            field(page, "target file").fill("target27.obj")
            page.get_by_role("button", name="Load", exact=True).click()
            page.get_by_text("distance to the target target27.obj").wait_for(timeout=30_000)
            assert app.wait_idle(60)
            settle(page, 500)
            after = canvas(page, "target-after")
            assert changed(before, after) > 2.0
            # the ends of the colour scale (viridis) on the plates: near (dark violet) at the
            # middle plates, far (yellow) at the ends, as the legend says
            r, g, b = (after[..., i].astype(int) for i in range(3))
            yellow = int(((r > 150) & (g > 170) & (b < 120)).sum())  # shaded viridis top
            assert _near(after, (68, 1, 84)) > 200 and yellow > 200, yellow
            tab(page, "Checks")
            rms = app.target_panel.state.rms
            assert f"RMS {rms * 1000:.2f} mm" in page.locator("#ccu-target").inner_text()
            browser_.close()
    finally:
        app.stop()
    assert errors == []
