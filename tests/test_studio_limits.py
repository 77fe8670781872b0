"""The path limits a studio edit shows, fast (issue 31 item 3): the overlap angle by bisection
levels placed in one vectorised deploy, the crease overlap test of all suspects in one GEOS call,
the thick plates' first collision measured once per model, and the limits kept between models
whose geometry an edit did not change."""

from __future__ import annotations

import math
import shutil

import numpy as np
import pytest

import compas_ccu.model.ccu_model as ccu_model
import compas_ccu.thickness.model as thick_module
from compas_ccu.catalog import catalog_path
from compas_ccu.kinematics.checks import self_intersecting, total_turning
from compas_ccu.kinematics.invariants import bisection_tree, overlap_limit, overlapping_creases
from compas_ccu.model import load_model
from compas_ccu.model.self_intersection import adopt_limits, geometry_key
from compas_ccu.studio import StudioSession
from compas_ccu.studio.checks import design_checks
from conftest import EXAMPLES, sequential_overlap_limit

DESIGNS = {
    "vault": EXAMPLES / "vault.toml",  # parallel, 10 plates
    "dome": catalog_path("fig12b-dome"),  # radial
    "inclined": catalog_path("fig11a-constant-apex"),  # inclined
    "two plates": EXAMPLES / "cone.toml",  # a single crease: 2 plates
}


def looped_self_intersecting(points, origins, normals):
    """The former crease overlap test: one GEOS call per suspect."""
    import shapely

    out = np.zeros(len(points), dtype=bool)
    for k in np.flatnonzero(total_turning(points) > np.pi):
        n = normals[k]
        x = np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0])
        x /= np.linalg.norm(x)
        y = np.cross(n, x)
        rel = points[k] - origins[k]
        out[k] = not shapely.is_simple(shapely.linestrings(np.c_[rel @ x, rel @ y]))
    return out


@pytest.mark.parametrize("name", list(DESIGNS))
def test_the_overlap_limit_is_the_sequential_bisections_and_conservative(name):
    mech = load_model(DESIGNS[name]).mechanism
    reference = sequential_overlap_limit(mech)
    tolerance = mech.alpha_limit / 2**40
    for levels in (1, 3, 4, 7):
        found = overlap_limit(mech, levels=levels)
        assert abs(found - reference) <= tolerance
        assert found <= reference + 1e-15 * mech.alpha_limit  # never a larger safe angle
    found = overlap_limit(mech)
    if found < mech.alpha_limit:
        # clear at the angle found, overlapping within the tolerance beyond it
        assert not overlapping_creases(mech, mech.deploy(found)).any()
        assert overlapping_creases(mech, mech.deploy(found + 2 * tolerance)).any()


def test_the_bisection_tree_holds_the_angles_a_sequential_bisection_visits():
    lo, hi = 0.0, 1.2345678901234567
    nodes = bisection_tree(lo, hi, 4)
    assert len(nodes) == 15
    for path in range(16):  # every sequence of 4 answers
        a, b, i = lo, hi, 0
        for level in range(4):
            mid = 0.5 * (a + b)
            assert nodes[i] == mid  # bit for bit
            if (path >> level) & 1:
                b, i = mid, 2 * i + 1
            else:
                a, i = mid, 2 * i + 2


def test_the_vectorised_overlap_test_agrees_with_the_looped_one():
    model = load_model(EXAMPLES / "overbent.toml")
    mech = model.mechanism
    from compas_ccu.kinematics.invariants import crease_polylines

    alphas = np.linspace(0.3, mech.alpha_limit, 13)
    hinges, origins, normals, turning = crease_polylines(mech, mech.deploy(alphas))
    points = hinges.reshape((-1,) + hinges.shape[2:])
    o, n = origins.reshape(-1, 3), normals.reshape(-1, 3)
    vectorised = self_intersecting(points, o, n)
    assert vectorised.any() and not vectorised.all()
    assert np.array_equal(vectorised, looped_self_intersecting(points, o, n))


def test_the_thick_first_collision_is_measured_once_per_model(monkeypatch):
    calls = []
    scan = thick_module.scan_first_collision

    def counted(*args):
        calls.append(args[1:])
        return scan(*args)

    monkeypatch.setattr(thick_module, "scan_first_collision", counted)
    model = load_model(EXAMPLES / "vault.toml")
    checks = design_checks(model)  # the key figures and the collision row ask for the same scan
    assert len(calls) == 1
    assert checks.collision is None  # clear to the collision-free angle (the doctest)
    assert checks.figures.collision_free_alpha_thick == calls[0][0]


@pytest.fixture
def session(tmp_path):
    design = tmp_path / "designs"
    design.mkdir()
    shutil.copy(EXAMPLES / "vault.toml", design / "vault.toml")
    return StudioSession.start(design / "vault.toml", out=tmp_path / "out")


def test_an_edit_that_keeps_the_geometry_keeps_the_limits(session, monkeypatch):
    calls = []

    def counted(mechanism, **options):
        calls.append(mechanism)
        return overlap_limit(mechanism, **options)

    monkeypatch.setattr(ccu_model, "overlap_limit", counted)
    first = session.model
    design_checks(first)
    assert len(calls) == 1
    measured = dict(first.limits)
    assert {"overlap_alpha", "collision_free_alpha"} <= set(measured)
    # material, loads, name: the same geometry, nothing measured again
    for section, key, value in (
        ("plates", "material", "birch-plywood"),
        ("loads", "live", 500.0),
        ("design", "description", "renamed"),
    ):
        assert session.edit(section, key, value) is None, (section, key)
        model = session.model
        assert model is not first and geometry_key(model) == geometry_key(first)
        assert model.overlap_alpha == measured["overlap_alpha"]
        assert model.collision_free_alpha == measured["collision_free_alpha"]
        design_checks(model)
        assert model.certificate is first.certificate  # scanned once, as far as either asked
    assert len(calls) == 1
    # the rise changes the geometry: measured again
    assert session.edit("crease", "rise", 0.9) is None
    model = session.model
    assert geometry_key(model) != geometry_key(first)
    assert "overlap_alpha" not in model.limits
    design_checks(model)
    assert len(calls) == 2
    assert model.overlap_alpha != measured["overlap_alpha"]
    assert model.certificate is not first.certificate


def test_threads_sharing_a_certificate_find_what_one_scan_finds():
    """A certificate asked by several threads at once (the studio's workers, the models of one
    geometry) gives each the event of one thread's scan, and the same state count."""
    import threading

    alone = load_model(EXAMPLES / "vault.toml").certificate
    want = alone.result()
    shared = load_model(EXAMPLES / "vault.toml").certificate
    got = []
    goals = [want.clear * f for f in (0.3, 1.0, 0.6, 2.0)]
    threads = [threading.Thread(target=lambda g=g: got.append(shared.certify(g))) for g in goals]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    final = shared.result()
    assert (final.clear, final.hit, final.plates, final.kind) == (
        want.clear,
        want.hit,
        want.plates,
        want.kind,
    )
    assert final.states == want.states  # no step scanned twice


def test_a_new_thickness_keeps_the_zero_thickness_limits_but_not_the_thick_ones(
    session, monkeypatch
):
    calls = []
    scan = thick_module.scan_first_collision

    def counted(*args):
        calls.append(args[0].thickness)
        return scan(*args)

    monkeypatch.setattr(thick_module, "scan_first_collision", counted)
    design_checks(session.model)
    assert session.edit("plates", "thickness", 0.004) is None
    design_checks(session.model)
    assert calls == [0.006, 0.004]
    assert session.edit("plates", "thickness", 0.006) is None  # measured before: kept
    design_checks(session.model)
    assert calls == [0.006, 0.004]


def test_models_of_different_geometry_do_not_share_limits():
    vault = load_model(EXAMPLES / "vault.toml")
    cone = load_model(EXAMPLES / "cone.toml")
    assert not adopt_limits(cone, vault)
    assert vault.limits is not cone.limits
    assert math.isfinite(cone.overlap_alpha)
    assert "overlap_alpha" not in vault.limits


# -- the view: vertex buffers updated, not nodes rebuilt ----------------------------------------
class FakeHandle:
    """A viser scene node handle: its properties, and whether it was removed."""

    def __init__(self, name, **props):
        self.name, self.removed, self.visible = name, False, True
        self.__dict__.update(props)

    def remove(self):
        self.removed = True


class FakeScene:
    """The part of viser's SceneApi the studio's scene uses, recording the nodes added."""

    def __init__(self):
        self.added = []

    def _add(self, name, **props):
        handle = FakeHandle(name, **props)
        self.added.append(handle)
        return handle

    def add_mesh_simple(self, name, vertices, faces, **options):
        return self._add(name, vertices=vertices, faces=faces, color=options.get("color"))

    def add_line_segments(self, name, points, colors, **options):
        return self._add(name, points=points, colors=colors)

    def add_glb(self, name, glb_data, **options):
        return self._add(name, glb_data=glb_data)

    def add_grid(self, name, *, position, **props):
        return self._add(name, position=position, **props)


def test_a_new_model_of_the_same_shape_updates_the_buffers_of_the_scene(session):
    from compas_ccu.studio.scene import TOGGLES, StudioScene
    from compas_ccu.studio.view import view_state

    fake = FakeScene()
    scene = StudioScene(fake)
    layers = {key: True for key, _, _ in TOGGLES}  # every layer shown

    def draw(key):
        model = session.model
        scene.draw(view_state(model, 20.0, solids=True), model, key, layers)
        return model

    draw(1)
    nodes = len(fake.added)
    assert nodes > 10 and scene.added == nodes
    before = {h.name: h.vertices.copy() for h in fake.added if hasattr(h, "vertices")}
    faces = {h.name: h.faces for h in fake.added if hasattr(h, "faces")}
    grid = next(h for h in fake.added if h.name == "/ccu/grid")
    position = grid.position
    assert session.edit("crease", "rise", 0.8) is None  # new geometry, same shape
    model = draw(2)
    assert len(fake.added) == nodes and not any(h.removed for h in fake.added)
    for h in fake.added:
        if h.name in before:  # plates, solids, flat stack, cut patterns: new vertices
            assert h.vertices.shape == before[h.name].shape
            assert not np.array_equal(h.vertices, before[h.name]), h.name
        if h.name in faces:  # the same triangles: not sent again
            assert h.faces is faces[h.name], h.name
    plate = scene._handles["/ccu/plates/0"]
    expected = view_state(model, 20.0).vertices[0].astype(np.float32)
    assert np.array_equal(plate.vertices, expected)
    assert grid.position != position  # the ground moved with the lower rise
    assert session.edit("crease", "segments", 32) is None  # a new shape: rebuilt
    draw(3)
    assert len(fake.added) > nodes and all(h.removed for h in fake.added[:nodes])


def test_two_threads_asking_for_a_limit_measure_it_once(monkeypatch):
    import copy
    import pickle
    import threading

    calls = []

    def slow(mechanism, **options):
        calls.append(threading.get_ident())
        return overlap_limit(mechanism, **options)

    monkeypatch.setattr(ccu_model, "overlap_limit", slow)
    model = load_model(EXAMPLES / "vault.toml")
    found = []
    threads = [
        threading.Thread(target=lambda: found.append(model.collision_free_alpha)) for _ in range(3)
    ]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert len(calls) == 1 and len(set(found)) == 1
    # a copied or pickled model keeps the values, with locks of its own
    for other in (copy.deepcopy(model), pickle.loads(pickle.dumps(model.limits))):
        limits = other.limits if hasattr(other, "limits") else other
        assert limits["collision_free_alpha"] == found[0]
        assert limits.measure("overlap_alpha", lambda: None) == model.overlap_alpha
        assert "certificate" in model.limits and "certificate" not in limits  # made again


def test_the_view_of_an_edit_does_not_wait_for_its_path_limits(tmp_path, monkeypatch):
    """The view worker draws a new model at once; until the checks worker has measured the
    path limits the read-out says so and the slider has no overlap mark, then both are shown."""
    pytest.importorskip("viser")
    import threading

    import compas_ccu.studio.jobs as jobs
    from compas_ccu.model.self_intersection import measured_collision_free_alpha
    from compas_ccu.studio.app import Studio
    from studio_page import free_port

    shutil.copy(EXAMPLES / "vault.toml", tmp_path / "vault.toml")
    release = threading.Event()

    def held_checks(model, **options):
        assert release.wait(60)
        return design_checks(model, **options)

    monkeypatch.setattr(jobs, "design_checks", held_checks)
    session = StudioSession.start(tmp_path / "vault.toml", out=tmp_path / "out")
    app = Studio(session, port=free_port())
    try:
        release.set()
        assert app.wait_idle(120)
        release.clear()
        frames = app.frames
        assert app.apply_action(lambda: app.session.edit("crease", "rise", 0.8))
        model = app.session.model
        assert app._view.wait_idle(60) and app.frames > frames  # drawn, checks still held
        assert measured_collision_free_alpha(model) is None and not app._checker.idle
        assert "rise <b>0.800 m</b>" in app.status.content
        assert "checking the path" in app.status.content
        assert [m.label for m in app.slider._marks] == ["0", "design", "limit"]
        release.set()
        assert app.wait_idle(120)
        assert measured_collision_free_alpha(model) == pytest.approx(model.overlap_alpha)
        assert "checking the path" not in app.status.content and "beyond" not in app.status.content
        labels = {m.label: m.value for m in app.slider._marks}
        assert labels["overlap"] == pytest.approx(model.overlap_alpha, rel=1e-12)
        app.alpha = model.overlap_alpha + 1.0  # past the first overlap: the read-out says so
        app.redraw()
        assert app.wait_idle(60)
        assert f"beyond the overlap angle {model.overlap_alpha:.4g}°" in app.status.content
    finally:
        release.set()
        app.stop()
