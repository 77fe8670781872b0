"""Hypothesis strategies over the whole design-file schema, and the outcome of one design.

:func:`designs` draws design documents across every section: every profile with its own keys,
every ruling type, every layout, plate sections, plane placements and targets, with realistic
values most of the time and extreme or malformed ones (zero, negative, NaN, infinities, huge
integers, wrong types, unknown keys, missing keys) some of the time. :func:`outcome` runs one
design through the library the way a user does and classifies what happened:

* ``ok``: the model builds and deploys, and the structure file it writes, read back, has
  invariants within 1e-9 of its size (the numbers a user gets, not the ones in memory);
* ``refused``: a :class:`compas_ccu.errors.CCUError` whose message is one line;
* ``bug``: anything else (another exception, a multi-line message, a message that says "this
  is a bug" or "please report", invariants beyond the bar, a non-finite number in a written
  file).

``tests/test_robustness.py`` runs a bounded slice in ``make test``; ``tools/fuzz.py`` (``make
fuzz``) runs the long campaign and prints the table of outcomes.
"""

from __future__ import annotations

import json
import math
import tempfile
from pathlib import Path

import numpy as np
from hypothesis import strategies as st

from compas_ccu.design import Design
from compas_ccu.errors import CCUError
from compas_ccu.io import write_structure_json
from compas_ccu.model import CCUModel
from compas_ccu.strips.intrinsics import QUAD_LENGTH_PAIRS

__all__ = [
    "designs",
    "outcome",
    "written_invariants",
    "toml_texts",
    "BAR",
    "asks_for_a_report",
]

#: The exactness bar of the written files, relative to the structure size.
BAR = 1e-9

#: Words that admit a defect of compas_ccu: a message holding one is a bug, whatever its type
#: or exit code (an input is refused by naming its cause, never by asking for a report).
BUG_WORDS = ("this is a bug", "please report")


def asks_for_a_report(text: str) -> bool:
    """Whether ``text`` (a message or a command's output) admits a bug of compas_ccu."""
    lowered = text.lower()
    return any(word in lowered for word in BUG_WORDS)


EXTREME = st.sampled_from(
    [0.0, -1.0, 1e-12, 1e-300, 1e12, 1e308, math.nan, math.inf, -math.inf, 10**400, "2", True]
)


def _number(low: float, high: float, wild: bool = False):
    """A float in [low, high]; in a wild design sometimes an extreme or malformed value."""
    fine = st.floats(low, high, allow_nan=False, allow_infinity=False)
    if not wild:
        return fine
    return st.one_of(fine, fine, fine, EXTREME)


def _maybe(strategy, p_none: int = 3):
    """``strategy`` or (about 1 in ``p_none``) nothing."""
    return st.one_of(st.none(), strategy) if p_none else strategy


def _points(n_min: int = 3, n_max: int = 12, span: float = 3.0):
    return st.lists(
        st.tuples(st.floats(-span, span), st.floats(-span, span)).map(list),
        min_size=n_min,
        max_size=n_max,
    )


@st.composite
def _arch_points(draw, n_min=3, n_max=10):
    """Control points of a plausible arch (x increasing, y above the chord)."""
    n = draw(st.integers(n_min, n_max))
    span = draw(st.floats(0.5, 5.0))
    xs = np.linspace(-span / 2, span / 2, n)
    rise = draw(st.floats(0.05, 2.0))
    wobble = draw(st.floats(0.0, 0.3))
    ys = rise * (1 - (2 * xs / span) ** 2) + wobble * np.sin(3.1 * xs)
    return [[float(x), float(y)] for x, y in zip(xs, ys)]


@st.composite
def _crease(draw, wild: bool) -> dict:
    profile = draw(
        st.sampled_from(["arc", "catenary", "elastica", "funicular", "spline", "polyline"])
    )
    c: dict = {"profile": profile}
    span = draw(_number(0.2, 8.0, wild))
    rise = draw(_number(0.02, 3.0, wild))
    if profile == "arc" and draw(st.booleans()):
        c["radius"] = draw(_number(0.3, 5.0, wild))
        c["angle"] = draw(_number(5.0, 300.0, wild))
    elif profile in ("arc", "catenary", "elastica", "funicular"):
        c["span"], c["rise"] = span, rise
        if profile == "funicular" and draw(st.booleans()):
            s = span if isinstance(span, float) and 0.1 < span < 100.0 else 2.0
            c["point_loads"] = draw(
                st.lists(
                    st.tuples(st.floats(-0.49 * s, 0.49 * s), st.floats(0.1, 5.0)).map(list),
                    min_size=1,
                    max_size=3,
                )
            )
    else:
        c["points"] = draw(st.one_of(_arch_points(), _points()) if wild else _arch_points())
    c["segments"] = draw(
        st.one_of(st.integers(2, 96), st.sampled_from([1, 0, -3, 2.5, 10**7, 200]))
        if wild
        else st.integers(2, 96)
    )
    if draw(st.integers(0, 3)) == 0:
        ends = [0.0, 1.0, 1.5] if wild else [0.0, 1.0]
        c["reference"] = draw(st.one_of(st.floats(0.0, 1.0), st.sampled_from(ends)))
    if draw(st.integers(0, 5)) == 0:
        c["state"] = draw(st.sampled_from(["flat", "deployed", "folded"] if wild else ["flat"]))
    return c


@st.composite
def _rulings(draw, wild: bool) -> dict:
    kind = draw(st.sampled_from(["orthogonal", "cylindrical", "conical", "angle", "explicit"]))
    r: dict = {"type": kind}
    if draw(st.integers(0, 2)) == 0:
        sides = ["inside", "outside", "left", "right"] + (["up"] if wild else [])
        r["side"] = draw(st.sampled_from(sides))
    if kind == "cylindrical":
        r["direction"] = [draw(_number(-1.0, 1.0, wild)), draw(_number(-2.0, 2.0, wild))]
    elif kind == "conical":
        r["apex"] = [draw(_number(-3.0, 3.0, wild)), draw(_number(-6.0, 6.0, wild))]
    elif kind == "angle":
        r["gamma"] = draw(
            st.one_of(
                _number(30.0, 150.0, wild),
                st.lists(st.floats(40.0, 140.0), min_size=2, max_size=4).map(
                    lambda g: [[i / (len(g) - 1), v] for i, v in enumerate(g)]
                ),
            )
        )
        if draw(st.booleans()):
            r["alpha_field"] = draw(st.sampled_from(["ode", "constant"]))
    elif kind == "explicit":
        r["points"] = draw(_points(2, 30))
    return r


@st.composite
def _layout(draw, wild: bool) -> dict:
    kind = draw(st.sampled_from(["single", "single", "parallel", "inclined", "radial"]))
    lay: dict = {"type": kind}
    plates = draw(
        st.one_of(st.integers(2, 12), st.sampled_from([1, 0, 40, 10**6]))
        if wild
        else st.integers(2, 12)
    )
    if kind == "single":
        lay["width"] = draw(_number(0.05, 1.0, wild))
        if draw(st.integers(0, 3)) == 0:
            lay["quadrants"] = True
    elif kind in ("parallel", "inclined"):
        lay["plates"] = plates
        lay["spacing"] = draw(
            st.one_of(
                _number(0.01, 0.4, wild), st.lists(st.floats(0.01, 0.4), min_size=1, max_size=6)
            )
        )
        if kind == "inclined":
            lay["spacing_start"] = draw(_number(0.0, 0.4, wild))
            if draw(st.booleans()):
                lay["spacing_end"] = draw(_number(0.0, 0.4, wild))
    else:
        lay["plates"] = plates
        lay["angle"] = draw(_number(1.0, 60.0, wild))
        lay["axis"] = draw(_number(-6.0, 6.0, wild))
    if kind != "single" and draw(st.integers(0, 4)) == 0:
        lay["leading"] = draw(st.integers(-1, 14))
    return lay


@st.composite
def designs(draw) -> dict:
    """A design document (dict, as parsed from TOML) across the whole schema."""
    # hypothesis favours the simplest draw (0): the ordinary case comes first everywhere
    wild = draw(st.integers(0, 9)) >= 7  # about 3 in 10 designs get extreme / malformed values
    doc = {
        "crease": draw(_crease(wild)),
        "rulings": draw(_rulings(wild)),
        "deployment": {"alpha": draw(_number(2.0, 80.0, wild))},
        "layout": draw(_layout(wild)),
    }
    if draw(st.integers(0, 3)) == 0:
        doc["plates"] = {
            "thickness": draw(_number(0.001, 0.03, wild)),
            "material": draw(
                st.sampled_from(["plywood", "gfrp", "aluminium"] + (["balsa"] if wild else []))
            ),
            "hinge_width": draw(_number(0.01, 0.1, wild)),
        }
        if doc["plates"]["material"] == "gfrp" and not wild:
            # gfrp has no default design factors (docs/thickness.md, "Design values")
            doc["design_code"] = {"gamma_M": 1.3, "k_mod": 0.5}
    if draw(st.integers(0, 3)) == 0:
        doc["plane"] = {
            "origin": [draw(_number(-1e7, 1e7, wild)), draw(_number(-10.0, 10.0, wild)), 0.0],
            "xaxis": draw(
                st.sampled_from([[1, 0, 0], [0, 1, 0], [1, 1, 0]] + ([[0, 0, 0]] if wild else []))
            ),
            "yaxis": draw(st.sampled_from([[0, 0, 1], [0, 1, 0], [1e-200, 0, 1e-200]])),
        }
    if doc["layout"]["type"] in ("parallel", "inclined") and draw(st.integers(0, 5)) == 0:
        doc["target"] = {"apex": [[0.0, 1.0], [0.3, 1.2], [0.6, 1.3]]}
    if doc["layout"]["type"] != "single" and not wild:
        doc["crease"].pop("state", None)  # crease planes are placed at the deployed state
    if doc["rulings"]["type"] == "explicit" and not wild:
        # a cut pattern as flat_design writes it: a polyline kept vertex by vertex, ruling ends
        # beside it, one crease
        points = draw(_arch_points(4, 12))
        doc["crease"] = {"profile": "polyline", "points": points, "state": "flat"}
        doc["crease"]["segments"] = len(points) - 1
        width = draw(st.floats(0.05, 0.4))
        doc["rulings"]["points"] = [[x, y - width] for x, y in points]
        doc["layout"] = {"type": "single"}
    malformed = draw(st.integers(0, 12)) if wild else 0
    if malformed == 12:
        doc[draw(st.sampled_from(["crease", "rulings", "layout"]))]["spam"] = 1
    elif malformed == 11:
        doc.pop(draw(st.sampled_from(["crease", "rulings", "deployment"])))
    elif malformed == 10:
        doc["deployment"]["alpha"] = draw(st.sampled_from(["30", [30], None and 0, 90.0]))
    return doc


def toml_texts():
    """Design file contents a user may save by mistake: bad TOML, other encodings, binary."""
    good = '[crease]\nprofile = "arc"\nspan = 2.5\nrise = 1.0\n'
    return st.one_of(
        st.binary(max_size=200),
        st.just(good.encode("utf-16")),
        st.just(good.encode("utf-8")[:-7]),
        st.just(b"[crease\nprofile = arc\n"),
        st.text(max_size=120).map(lambda t: t.encode("utf-8")),
    )


def written_invariants(path: Path) -> float:
    """Largest invariant error of a written ``structure.json``, relative to its size: quad
    side / diagonal lengths (deployed vs cut), quad planarity and hinge coincidence."""
    data = json.loads(
        path.read_text(encoding="utf-8"),
        parse_constant=lambda c: (_ for _ in ()).throw(ValueError(f"non-finite {c}")),
    )
    plates = {p["id"]: p for p in data["plates"]}
    points = np.concatenate([np.asarray(p["deployed"], float) for p in plates.values()])
    size = float(np.linalg.norm(np.ptp(points, axis=0)))
    worst, pairs = 0.0, QUAD_LENGTH_PAIRS
    for p in plates.values():
        faces = np.asarray(p["faces"])
        cut, built = np.asarray(p["flat"], float)[faces], np.asarray(p["deployed"], float)[faces]
        lengths = [
            np.linalg.norm(q[:, pairs[:, 1]] - q[:, pairs[:, 0]], axis=-1) for q in (cut, built)
        ]
        worst = max(worst, float(np.abs(lengths[0] - lengths[1]).max()))
        a, b, c, d = (built[:, i] for i in range(4))
        normal = np.cross(c - a, d - b)
        normal /= np.linalg.norm(normal, axis=-1, keepdims=True)
        worst = max(worst, float(np.abs(np.einsum("ij,ij->i", b - a, normal)).max()))
    for crease in data["creases"]:
        (a, b), (ia, ib) = crease["plates"], crease["vertices"]
        pa = np.asarray(plates[a]["deployed"], float)[ia]
        pb = np.asarray(plates[b]["deployed"], float)[ib]
        worst = max(worst, float(np.linalg.norm(pa - pb, axis=1).max()))
    return worst / size


def outcome(document: dict) -> tuple:
    """(kind, detail) of one design: ``ok``, ``refused`` or ``bug`` (module docstring)."""
    try:
        model = CCUModel(Design(document))
        structure = model.deploy()
        with tempfile.TemporaryDirectory() as folder:
            path = write_structure_json(structure, Path(folder) / "structure.json")
            error = written_invariants(path)
        if not error <= BAR:
            return "bug", f"written invariants {error:.2e} of the size"
        return "ok", f"{len(structure.plate_ids)} plates"
    except CCUError as exc:
        message = str(exc)
        if "\n" in message or not message.strip():
            return "bug", f"{type(exc).__name__} message not one line: {message!r}"
        if asks_for_a_report(message):
            return "bug", f"{type(exc).__name__} asks for a report: {message}"
        return "refused", type(exc).__name__
    except Exception as exc:  # noqa: BLE001 - classifying is the point
        return "bug", f"{type(exc).__name__}: {exc}"
