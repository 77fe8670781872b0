"""Shared fixtures: canonical strips and designs."""

from __future__ import annotations

import os
import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import settings

from compas_ccu.design import Design
from compas_ccu.fea.engines import get_engine
from compas_ccu.kinematics.invariants import overlapping_creases
from compas_ccu.model import load_model

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"

#: The quick loop (``make test-fast`` sets ``CCU_QUICK_TESTS=1``) runs a third of each property
#: test's hypothesis examples; ``make test`` and CI run them all.
QUICK = os.environ.get("CCU_QUICK_TESTS", "") not in ("", "0")


def property_examples(full: int) -> int:
    """The hypothesis examples of a property test: ``full``, or a third of it (at least 10) in
    the quick loop.

    Examples
    --------
    >>> property_examples(60) in (60, 20)
    True
    """
    return max(10, full // 3) if QUICK else full


if QUICK:  # the property tests without their own count: a third of hypothesis's 100
    settings.register_profile("quick", max_examples=property_examples(100))
    settings.load_profile("quick")


def arc_strip(n: int, radius: float = 1.0, angle: float = np.pi / 2, width: float = 0.2):
    """Annular-sector cut pattern: crease of radius R, radial rulings (plate inside, on the left).

    Returns near, far : (n + 1, 2).
    """
    t = np.linspace(0.0, angle, n + 1)
    near = radius * np.c_[np.cos(t), np.sin(t)]
    return near, near * (1.0 - width / radius)


def circumradius_error(points, radius: float) -> float:
    """Largest distance of ``points`` (k, 3) from the circle of ``radius`` through the first,
    middle and last (the circle's centre solved in their plane)."""
    a, b, c = points[0], points[len(points) // 2], points[-1]
    normal = np.cross(b - a, c - a)
    normal /= np.linalg.norm(normal)
    m = np.array([b - a, c - a, normal])
    rhs = np.array([(b - a) @ (b + a) / 2.0, (c - a) @ (c + a) / 2.0, normal @ a])
    centre = np.linalg.solve(m, rhs)
    return float(np.abs(np.linalg.norm(points - centre, axis=1) - radius).max())


def wavy_strip(n: int, seed: int = 0):
    """A general strip: spiral-like crease, rulings leaning by varying angles (plate left)."""
    rng = np.random.default_rng(seed)
    s = np.linspace(0.0, 1.0, n + 1)
    turn = 0.9 + 0.5 * np.sin(3.0 * s + rng.uniform(0, 1))
    theta = np.r_[0.0, np.cumsum(turn[1:-1] * (1.6 / n))]
    h = 1.5 / n
    near = np.zeros((n + 1, 2))
    near[1:] = np.cumsum(h * np.c_[np.cos(theta), np.sin(theta)], axis=0)
    tang = np.r_[theta[:1], 0.5 * (theta[:-1] + theta[1:]), theta[-1:]]
    gamma = np.pi / 2 + 0.35 * np.sin(2.0 * s + rng.uniform(0, 1))
    direction = np.c_[np.cos(tang + gamma), np.sin(tang + gamma)]
    return near, near + (0.15 + 0.05 * s)[:, None] * direction


@pytest.fixture(scope="session")
def vault_model():
    return load_model(EXAMPLES / "vault.toml")


@pytest.fixture(scope="session")
def vault_fab_data(vault_model):
    """Fabrication data of the vault's geometry in 8 mm plywood, 50 mm hinge strips."""
    from compas_ccu.fabrication import fabrication_data

    return fabrication_data(vault_model, thickness=0.008, material="plywood", hinge_width=0.05)


@pytest.fixture(scope="session")
def overbent_model():
    """The vault in 8 mm plywood on the default sheets (examples/overbent.toml): it fails its
    bending checks and every plate is spliced."""
    return load_model(EXAMPLES / "overbent.toml")


@pytest.fixture(scope="session")
def overbent_fab_data(overbent_model):
    """Fabrication data of the 8 mm vault: 8 mm plywood, 50 mm hinge strips."""
    from compas_ccu.fabrication import fabrication_data

    return fabrication_data(overbent_model, thickness=0.008, material="plywood", hinge_width=0.05)


@pytest.fixture(scope="session")
def cone_model():
    return load_model(EXAMPLES / "cone.toml")


@pytest.fixture(scope="session")
def quadrants_model():
    return load_model(EXAMPLES / "quadrants.toml")


def make_design(**sections) -> Design:
    """A design from keyword sections, defaulting to a small single-crease arc."""
    doc = {
        "crease": {"profile": "arc", "span": 2.0, "rise": 0.6, "segments": 32},
        "rulings": {"type": "orthogonal"},
        "deployment": {"alpha": 30.0},
        "layout": {"type": "single", "width": 0.3},
    }
    for name, values in sections.items():
        if name == "crease" and values.get("profile", "arc") != "arc":
            doc[name] = {"segments": 32, **values}  # other profiles take other keys
        else:
            doc[name] = {**doc.get(name, {}), **values}
    return Design(doc)


@pytest.fixture(params=["kratos", "opensees"])
def engine(request):
    """Each FE backend in turn (both are installed by `make setup`: the tests must run)."""
    module = get_engine(request.param)
    ok, info = module.available()
    assert ok, info
    return module


def captured_plate_contacts(thick, alphas, *, report=False):
    """The arguments ``ThickModel.collisions(alphas)`` passes to ``plate_contacts``: without
    ``smallest`` (the full check of every pair) unless ``report``."""
    import compas_ccu.thickness.collision_check as collision_check

    seen = {}
    original = collision_check.plate_contacts

    def spy(*args, **kwargs):
        seen["call"] = (args, kwargs)
        return original(*args, **kwargs)

    collision_check.plate_contacts = spy
    try:
        thick.collisions(alphas)
    finally:
        collision_check.plate_contacts = original
    args, kwargs = seen["call"]
    if not report:
        kwargs = {key: value for key, value in kwargs.items() if key != "smallest"}
    return args, kwargs


def sequential_overlap_limit(mechanism, bisections=40):
    """The overlap limit as plainly as it is defined: one deploy and one overlap test of every
    crease per bisection of ``[0, alpha_limit]`` (the oracle of
    :func:`compas_ccu.kinematics.invariants.overlap_limit`, which must find the same angle)."""
    limit = mechanism.alpha_limit
    if not overlapping_creases(mechanism, mechanism.deploy(limit)).any():
        return limit
    lo, hi = 0.0, limit
    for _ in range(bisections):
        mid = 0.5 * (lo + hi)
        if overlapping_creases(mechanism, mechanism.deploy(np.array([mid]))).any():
            hi = mid
        else:
            lo = mid
    return lo


#: docstring examples that fabricate a design with the default true-shape nesting (seconds
#: each): slow, their behaviour has fast tests (tests/test_design_patterns.py: the cone's round
#: trip through ``ccu import``)
SLOW_DOCTESTS = {
    "compas_ccu.fabrication.import_documents.import_design",
    "compas_ccu.fabrication.import_documents.import_structure",
    "compas_ccu.viz.report.write_report",  # a whole report of the vault (~4 s)
}


#: A test module marked slow as a whole (``pytestmark = pytest.mark.slow`` or a list starting
#: with it, at the start of a line).
WHOLLY_SLOW = re.compile(r"^pytestmark = \[?pytest\.mark\.slow\b", re.MULTILINE)


def pytest_ignore_collect(collection_path, config):
    """The quick loop (``-m "not slow"``) does not import a test module marked slow as a whole:
    deselecting its tests after the import would still pay its imports in every worker (Dask's
    ``distributed`` alone ~0.45 s)."""
    if (
        config.getoption("markexpr", "") == "not slow"
        and collection_path.suffix == ".py"
        and collection_path.name.startswith("test_")
        and WHOLLY_SLOW.search(collection_path.read_text(encoding="utf-8"))
    ):
        return True
    return None


def pytest_collection_modifyitems(config, items):
    """Mark the docstring examples of :data:`SLOW_DOCTESTS` slow (a doctest takes no marks), and
    put the tests of an ``in_order`` module back in file order (pytest-randomly shuffles before
    this hook runs; the module keeps its place in the shuffled run)."""
    for item in items:
        if item.name in SLOW_DOCTESTS:
            item.add_marker(pytest.mark.slow)
    in_file_order(items)


def in_file_order(items) -> None:
    """Sort, in place, the items of every module marked ``in_order`` by their line, each into
    the slots its module's items hold."""
    slots = {}
    for index, item in enumerate(items):
        if item.get_closest_marker("in_order") is not None:
            slots.setdefault(item.location[0], []).append(index)
    for indices in slots.values():
        ordered = sorted((items[i] for i in indices), key=lambda item: item.location[1])
        for index, item in zip(indices, ordered):
            items[index] = item


def pytest_terminal_summary(terminalreporter, config):
    """End the run with pytest-randomly's seed (its header line is hidden by ``-q``): a failure
    that depends on the order is reproduced with that seed (``make test-fast SEED=N``)."""
    seed = config.getoption("randomly_seed", None)
    if isinstance(seed, int) and config.pluginmanager.hasplugin("randomly"):
        terminalreporter.write_line(f"test order: --randomly-seed={seed}")
