"""The classes of the independent campaign (issue 27 item 6): each refused with one line naming
the cause and the value (exit 2 from ``ccu``, nothing written), or handled.

$INSUNITS codes, SPLINEs of coincident fit points, non-finite DXF coordinates, the point limit of
curve files, the work limit of every count option, finite and bounded float options, messages
that name the bound broken, and the Pareto front's relative tolerance.
"""

from __future__ import annotations

import argparse
import re
import time

import numpy as np
import pytest

from compas_ccu import limits
from compas_ccu.cli import COMMANDS, main
from compas_ccu.cli.parser import check_options, numbers
from compas_ccu.curves.readers import read_curve
from compas_ccu.design import Design, load_design
from compas_ccu.design.schema import SCHEMA
from compas_ccu.errors import DesignError, LimitError, OptionError, ProfileError
from compas_ccu.explore.pareto import pareto_mask
from compas_ccu.tolerances import OBJECTIVE_RELATIVE
from conftest import EXAMPLES

ezdxf = pytest.importorskip("ezdxf")

UNDERSTOOD = "understood: 0 (unitless), 1 (in), 2 (ft), 4 (mm), 5 (cm), 6 (m)"


def _run(argv, capsys):
    code = main([str(a) for a in argv])
    err = capsys.readouterr().err.strip()
    return code, err


def _refused(argv, capsys, out=None) -> str:
    """``ccu argv`` exits 2 with one line and leaves no ``out``; the message without prefix."""
    code, err = _run(argv, capsys)
    assert code == 2, err
    assert err.count("\n") == 0 and err.startswith("ccu: error: "), err
    if out is not None:
        assert not out.exists()
    return err[len("ccu: error: ") :]


def _dxf(path, *, units=6, spline=None, polyline=None, layer="0"):
    doc = ezdxf.new()
    doc.header["$INSUNITS"] = units
    msp = doc.modelspace()
    if spline is not None:
        msp.add_spline(fit_points=spline, dxfattribs={"layer": layer})
    if polyline is not None:
        msp.add_lwpolyline(polyline, dxfattribs={"layer": layer})
    doc.saveas(path)
    return path


ARCH = [(0.0, 0.0), (1.0, 0.5), (2.0, 0.0)]


# -- 1. $INSUNITS -----------------------------------------------------------------------------


@pytest.mark.parametrize("code", [3, 99, -1, 1_000_000])
def test_a_curve_dxf_with_an_unknown_insunits_code_is_refused_by_name(tmp_path, code):
    path = _dxf(tmp_path / "c.dxf", units=code, polyline=ARCH)
    with pytest.raises(ProfileError) as info:
        read_curve(path)
    assert str(info.value) == (
        f"{str(path)!r}: $INSUNITS = {code} is a unit code not understood; {UNDERSTOOD}; or "
        "give the file's units (m, cm, mm, in, ft)"
    )
    # given units override the file's code
    assert read_curve(path, units="mm").points[1].tolist() == [0.001, 0.0005, 0.0]


def test_the_understood_insunits_codes_read_in_their_unit(tmp_path):
    for code, unit, k in ((1, "in", 0.0254), (2, "ft", 0.3048), (4, "mm", 0.001), (6, "m", 1.0)):
        curve = read_curve(_dxf(tmp_path / f"c{code}.dxf", units=code, polyline=ARCH))
        assert curve.units == unit
        assert curve.points[1].tolist() == [1.0 * k, 0.5 * k, 0.0]


def test_ccu_import_refuses_a_plate_dxf_with_an_unknown_insunits_code(tmp_path, capsys):
    folder = tmp_path / "plates"
    folder.mkdir()
    _dxf(folder / "plate_0.dxf", units=99, polyline=ARCH, layer="CUT")
    out = tmp_path / "imported.toml"
    message = _refused(["import", folder, "--out", out], capsys, out)
    assert message == (
        f"'plate_0.dxf': $INSUNITS = 99 is a unit code not understood; {UNDERSTOOD}; or give "
        "the file's units (m, cm, mm, in, ft)"
    )


# -- 2. SPLINEs of coincident fit points -------------------------------------------------------


@pytest.mark.parametrize(
    "fit",
    [
        [(0, 0), (1, 0.5), (1, 0.5), (2, 0)],  # was LinAlgError: singular matrix
        [(0, 0), (0, 0), (1, 0.5), (2, 0)],  # was ZeroDivisionError
        [(0, 0), (1, 0.5), (2, 0), (2, 0), (2, 0)],
    ],
)
def test_coincident_spline_fit_points_are_dropped(tmp_path, fit):
    got = read_curve(_dxf(tmp_path / "dup.dxf", spline=fit)).points
    distinct = [p for k, p in enumerate(fit) if k == 0 or p != fit[k - 1]]
    want = read_curve(_dxf(tmp_path / "clean.dxf", spline=distinct)).points
    assert got.shape == want.shape and np.array_equal(got, want)


@pytest.mark.parametrize("fit", [[(1, 1), (1, 1)], [(1, 1), (1, 1), (1, 1)]])
def test_a_spline_of_one_distinct_fit_point_is_refused_by_name(tmp_path, fit):
    with pytest.raises(ProfileError) as info:  # was IndexError
        read_curve(_dxf(tmp_path / "s.dxf", spline=fit))
    assert str(info.value) == (
        f"SPLINE #2F: its {len(fit)} fit points coincide (fewer than 2 distinct points) and it "
        "has no control points"
    )


def test_ccu_import_refuses_a_crease_spline_of_coincident_fit_points(tmp_path, capsys):
    folder = tmp_path / "plates"
    folder.mkdir()
    doc = ezdxf.new()
    doc.header["$INSUNITS"] = 4
    msp = doc.modelspace()
    outline = [(0, 0), (100, 0), (100, 50), (0, 50)]
    msp.add_lwpolyline(outline, close=True, dxfattribs={"layer": "CUT"})
    crease = msp.add_spline(fit_points=[(5, 5), (5, 5)], dxfattribs={"layer": "CREASE"})
    msp.add_line((10, 5), (10, 40), dxfattribs={"layer": "RULING_SCORE"})
    doc.saveas(folder / "plate_0.dxf")
    out = tmp_path / "imported.toml"
    message = _refused(["import", folder, "--out", out], capsys, out)
    assert message == (
        f"plate_0.dxf SPLINE #{crease.dxf.handle}: its 2 fit points coincide (fewer than 2 "
        "distinct points) and it has no control points"
    )


# -- 6. non-finite coordinates name the value --------------------------------------------------


@pytest.mark.parametrize("bad", ["nan", "inf", "-inf"])
def test_a_non_finite_dxf_coordinate_is_named(tmp_path, bad):
    path = _dxf(tmp_path / "c.dxf", polyline=[(0.0, 0.0), (1.25, 1.0), (2.0, 0.0)])
    path.write_text(path.read_text().replace("\n1.25\n", f"\n{bad}\n"))
    with pytest.raises(ProfileError) as info:  # was "fewer than 2 distinct points"
        read_curve(path)
    assert str(info.value) == (
        f"{str(path)!r}: LWPOLYLINE #2F on layer 0 has a non-finite coordinate at point 1: "
        f"[{float(bad)!r}, 1.0, 0.0]"
    )


# -- 5. the point limit and linear reading ----------------------------------------------------


@pytest.mark.slow  # a file at the point limit (~1.7 s)
def test_a_curve_file_above_the_point_limit_is_refused_before_parsing(tmp_path):
    path = tmp_path / "big.csv"
    t = np.linspace(0.0, np.pi, 1_000_001)
    np.savetxt(path, np.c_[2.0 * np.cos(t), np.sin(t)], delimiter=",", fmt="%.9f")
    start = time.perf_counter()
    with pytest.raises(LimitError) as info:
        read_curve(path)
    assert time.perf_counter() - start < 5.0  # was 40 s; a refusal before the work
    assert str(info.value) == (
        "1000001 lines of big.csv exceed the limit of 200000 points; raise it with --limit "
        "points=1000001 (Python: compas_ccu.limits.raised(points=1000001))"
    )


def test_a_dense_csv_is_parsed_by_numpy_as_the_lines_are(tmp_path):
    rng = np.random.default_rng(0)
    points = np.cumsum(rng.uniform(0.1, 1.0, (250_000, 2)), axis=0)
    path = tmp_path / "dense.csv"
    np.savetxt(path, points, delimiter=", ", fmt="%.17g", header="x, y")
    with limits.raised(points=300_000):
        curve = read_curve(path)
    assert np.array_equal(curve.points[:, :2], points) and not curve.points[:, 2].any()


@pytest.mark.parametrize(
    "text, rows",
    [
        ("x,y\n0,0\n500,250\n1000,0\n", [[0, 0, 0], [500, 250, 0], [1000, 0, 0]]),
        ("# a comment\n\n 1;2 # x\n3\t4\n", [[1, 2, 0], [3, 4, 0]]),
        ("1,2\n3,4,5\n", [[1, 2, 0], [3, 4, 5]]),  # mixed 2 and 3 columns: line by line
        ("a\nb\n1,2\n3,4\n", [[1, 2, 0], [3, 4, 0]]),
        ("1,2\r\n3,4\r\n", [[1, 2, 0], [3, 4, 0]]),
        ("0 0 0\n1 1 1\n", [[0, 0, 0], [1, 1, 1]]),
    ],
)
def test_csv_forms(tmp_path, text, rows):
    path = tmp_path / "c.csv"
    path.write_text(text)
    assert read_curve(path).points.tolist() == [[float(v) for v in r] for r in rows]


@pytest.mark.parametrize(
    "text, message",
    [
        ("1,2\nnan,3\n", "line 2: a point is 2 or 3 finite numbers, got 'nan,3'"),
        ("1,2\n3\n", "line 2: a point is 2 or 3 finite numbers, got '3'"),
        ("1,2\n3,x\n", "line 2: not numbers: '3,x'"),
    ],
)
def test_csv_errors_name_the_line(tmp_path, text, message):
    path = tmp_path / "c.csv"
    path.write_text(text)
    with pytest.raises(ProfileError) as info:
        read_curve(path)
    assert str(info.value) == f"{str(path)!r} {message}"


def test_a_dxf_above_the_point_limit_is_refused_before_ezdxf_parses_it(tmp_path):
    t = np.linspace(0.0, np.pi, 200)
    path = _dxf(tmp_path / "c.dxf", polyline=np.c_[np.cos(t), np.sin(t)].tolist())
    with limits.raised(points=100), pytest.raises(LimitError) as info:
        read_curve(path)
    assert str(info.value).startswith("2") and "points (coordinate tags) in c.dxf exceed the "
    assert "limit of 100 points; raise it with --limit points=" in str(info.value)
    assert len(read_curve(path).points) == 200  # the default limit reads it


def test_a_design_naming_a_huge_curve_file_is_refused_naming_the_file(tmp_path, capsys):
    np.savetxt(tmp_path / "c.csv", np.c_[np.linspace(-1, 1, 200_001), np.zeros(200_001)])
    (tmp_path / "d.toml").write_text(
        '[crease]\nprofile = "polyline"\npoints = "c.csv"\n[rulings]\ntype = "orthogonal"\n'
        "[deployment]\nalpha = 30.0\n[layout]\nwidth = 0.3\n"
    )
    message = _refused(["deploy", tmp_path / "d.toml", "--out", tmp_path / "o"], capsys)
    assert message.startswith("200001 lines of c.csv exceed the limit of 200000 points")


# -- 3. every count option against a work limit ------------------------------------------------

#: Integer options that are no count of work, with the bound they have instead.
NOT_COUNTS = {("figures", "--dpi"), ("optimize", "--seed"), ("studio", "--port")}
NOT_COUNTS |= {("sheet", "--columns")}  # at most the number of designs (checked by the command)
# the nesting's seed, and its steps per packing: bounded as the design file's keys
# (fabrication.nesting_seed, nesting_steps <= 100000), the time guarded by nesting_time
NOT_COUNTS |= {("fabricate", "--nesting-seed"), ("fabricate", "--nesting-steps")}
# the fits' seeds and sizes (points, evaluations, mesh samples): bounded (docs/fit.md)
NOT_COUNTS |= {("asbuilt", o) for o in ("--sample", "--max-evaluations", "--samples", "--seed")}
NOT_COUNTS |= {("fit", o) for o in ("--points", "--max-evaluations", "--samples", "--seed")}


def _int_options():
    for command in COMMANDS:
        for o in command.options:
            if o.settings.get("type") is int:
                yield command, o


def _namespace(command, **values):
    args = argparse.Namespace(**{o.dest: o.settings.get("default") for o in command.options})
    for k, v in values.items():
        setattr(args, k, v)
    return args


def test_every_integer_option_of_every_command_is_a_limited_count_or_bounded():
    counted = []
    for command, o in _int_options():
        key = (command.name, o.flags[-1])
        if key in NOT_COUNTS:
            assert o.maximum is not None or key == ("sheet", "--columns"), key
            continue
        assert o.limit is not None, f"ccu {command.name} {o.flags[-1]} counts against no limit"
        assert o.minimum is not None and o.minimum >= 1, key
        counted.append(key)
    assert sorted(counted) == sorted(  # a new count option is added here (with its limit)
        [
            ("path", "--steps"), ("animate", "--frames"), ("view", "--steps"),
            ("planarity", "--steps"), ("catalog", "--steps"), ("validate", "--steps"),
            ("explore", "--workers"), ("optimize", "--trials"), ("optimize", "--workers"),
            ("scale", "--steps"), ("report", "--steps"), ("report", "--frames"),
        ]
    )  # fmt: skip


@pytest.mark.parametrize(
    "command, o",
    [(c, o) for c, o in _int_options() if o.limit is not None],
    ids=lambda x: getattr(x, "name", None) or x.flags[-1],
)
def test_every_count_option_refuses_a_count_beyond_its_limit(command, o):
    huge = 10**7 if o.limit != "workers" else 10**4
    with pytest.raises(LimitError) as info:
        check_options(command, _namespace(command, **{o.dest: huge}))
    assert f"({o.flags[-1]} {huge}) exceed the limit of" in str(info.value)
    assert f"raise it with --limit {o.limit}=" in str(info.value)
    with limits.raised(**{o.limit: 10**8}):
        check_options(command, _namespace(command, **{o.dest: huge}))  # raised: accepted
    with pytest.raises(OptionError):
        check_options(command, _namespace(command, **{o.dest: 0 if o.minimum > 0 else -1}))


def test_ccu_scale_steps_has_a_work_limit(tmp_path, capsys):
    out = tmp_path / "scale"
    argv = ["scale", EXAMPLES / "cone.toml", "--to", "3", "--steps", 10**7, "--out", out]
    assert _refused(argv, capsys, out) == (
        "10000001 variants (--steps 10000000) exceed the limit of 1000000 variants; raise it "
        "with --limit variants=10000001 (Python: compas_ccu.limits.raised(variants=10000001))"
    )


# -- 4. finite, positive and bounded float options ---------------------------------------------


def _float_options():
    for command in COMMANDS:
        for o in command.options:
            if o.settings.get("type") is float:
                yield command, o


@pytest.mark.parametrize(
    "command, o", list(_float_options()), ids=lambda x: getattr(x, "name", None) or x.flags[-1]
)
@pytest.mark.parametrize("bad", [float("nan"), float("inf"), -float("inf")])
def test_every_float_option_refuses_non_finite_values(command, o, bad):
    value = [bad, 1.0] if o.settings.get("nargs") == 2 else bad
    value = [value] if o.settings.get("action") == "append" else value
    with pytest.raises(OptionError) as info:
        check_options(command, _namespace(command, **{o.dest: value}))
    assert str(info.value) == f"{o.flags[-1]} must be a finite number, got {bad!r}"


def test_float_options_name_the_bound_they_break():
    by_name = {(c.name, o.flags[-1]): (c, o) for c, o in _float_options()}
    cases = [
        ("scale", "--to", 0.0, "--to must be > 0, got 0.0"),
        ("scale", "--to", 1e300, "--to must be <= 1e6, got 1e+300"),
        ("fabricate", "--thickness", -0.01, "--thickness must be > 0, got -0.01"),
        ("fabricate", "--thickness", 0.5, "--thickness must be <= 0.1, got 0.5"),
        ("fabricate", "--kerf", -1.0, "--kerf must be >= 0, got -1.0"),
        ("validate", "--element-size", 0.0, "--element-size must be > 0, got 0.0"),
        ("validate", "--element-size", 1e300, "--element-size must be <= 1e6, got 1e+300"),
        ("animate", "--fps", 1e6, "--fps must be <= 1000, got 1000000.0"),
        ("import", "--reference", 1.5, "--reference must be <= 1, got 1.5"),
    ]
    for name, flag, value, message in cases:
        command, o = by_name[(name, flag)]
        with pytest.raises(OptionError) as info:
            check_options(command, _namespace(command, **{o.dest: value}))
        assert str(info.value) == message
    command, o = by_name[("fabricate", "--sheet")]
    with pytest.raises(OptionError) as info:
        check_options(command, _namespace(command, sheet=[[2.44, 1.22], [2.0, 0.0]]))
    assert str(info.value) == "--sheet must be > 0, got 0.0"


@pytest.mark.parametrize(
    "option, text, message",
    [
        ("--sheet", ["nan", "1.22"], "--sheet must be a finite number, got nan"),
        ("--sheet", ["2.44", "inf"], "--sheet must be a finite number, got inf"),
        ("--sheet", ["2.44", "0"], "--sheet must be > 0, got 0.0"),
        ("--sheet", ["1e300", "1"], "--sheet must be <= 100, got 1e+300"),
        ("--thickness", "0.008,nan", "--thickness must be finite numbers, got '0.008,nan'"),
        ("--thickness", "inf", "--thickness must be finite numbers, got 'inf'"),
        ("--thickness", "0.008,1e300", "--thickness must be numbers <= 0.1, got '0.008,1e300'"),
    ],
)
def test_ccu_scale_refuses_non_finite_and_out_of_range_sheet_and_thickness(
    tmp_path, capsys, option, text, message
):
    out = tmp_path / "scale"
    texts = text if isinstance(text, list) else [text]  # --sheet LENGTH WIDTH: two numbers
    argv = ["scale", EXAMPLES / "cone.toml", "--to", "3", option, *texts, "--out", out]
    assert _refused(argv, capsys, out) == message


def test_numbers_parses_the_text_of_an_option():
    assert numbers("2.44x1.22", "--sheet", count=2) == [2.44, 1.22]
    assert numbers(" 0.008, 0.01 ,", "--thickness") == [0.008, 0.01]
    with pytest.raises(OptionError, match=r"^--t must be numbers separated by commas, e.g. 0.5,1"):
        numbers("a,b", "--t")


def test_the_scale_study_refuses_non_finite_values_in_python():
    from compas_ccu.explore.scale import scale_study

    doc = load_design(EXAMPLES / "cone.toml").metric_document()
    for kwargs, message in [
        ({"to_span": float("inf")}, "the target span must be a finite number > 0 m, got inf"),
        ({"to_span": 3.0, "sheet": (float("nan"), 1.0)}, "the sheet must be two finite lengths"),
        ({"to_span": 3.0, "steps": 10**7}, "10000001 spans (steps 10000000 + the base) exceed"),
    ]:
        with pytest.raises((OptionError, LimitError), match="^" + re.escape(message)):
            scale_study(doc, 2.0, **{"steps": 2, **kwargs})


# -- 6. messages name the bound broken ---------------------------------------------------------


def test_every_schema_bound_is_named_in_its_message():
    for section, keys in SCHEMA.items():
        for name, key in keys.items():
            if name.startswith("_") or key.check is None or key.kind != "float":
                continue
            if not key.check(1e300):  # an upper bound: the message names it
                assert any(t in key.check_doc for t in ("<", "...")), (section, name)


def test_a_curve_file_scale_of_1e300_names_the_upper_bound():
    doc = {
        "crease": {"profile": "polyline", "points": {"file": "c.csv", "scale": 1e300}},
        "rulings": {"type": "orthogonal"},
        "deployment": {"alpha": 30.0},
        "layout": {"width": 0.3},
    }
    with pytest.raises(DesignError) as info:
        Design(doc)
    assert str(info.value) == "crease.points.scale: must be > 0 and <= 1e6, got 1e+300"


def test_a_price_of_1e300_names_the_upper_bound():
    doc = load_design(EXAMPLES / "cone.toml").metric_document()
    doc = {**doc, "fabrication": {"sheet_price": 1e300}}
    with pytest.raises(DesignError) as info:
        Design(doc)
    assert str(info.value) == "fabrication.sheet_price: must be >= 0 and <= 1e9, got 1e+300"


# -- 7. the Pareto front's relative tolerance --------------------------------------------------


def test_a_design_better_only_by_round_off_is_dominated():
    # better by 3e-16 m in the first objective, worse by 4 in the second: dominated
    assert pareto_mask([[1.0, 1.0], [1.0 - 3e-16, 5.0]], ["min", "min"]).tolist() == [True, False]
    # better by more than the tolerance: on the front
    d = 10 * OBJECTIVE_RELATIVE
    assert pareto_mask([[1.0, 1.0], [1.0 - d, 5.0]], ["min", "min"]).tolist() == [True, True]
    # equal within the tolerance: neither dominates
    e = 0.1 * OBJECTIVE_RELATIVE
    assert pareto_mask([[1.0, 2.0], [1.0 + e, 2.0 - e]], ["min", "max"]).tolist() == [True, True]


def test_the_pareto_tolerance_is_relative_to_each_objectives_scale():
    # a span of 2000 m against 2000 + 1e-7 m: round-off at that scale (1e-9 x 2000 = 2e-6)
    v = np.array([[2000.0, 1.0], [2000.0 + 1e-7, 0.5e-3], [2000.0 - 1e-7, 0.5]])
    assert pareto_mask(v, ["max", "min"]).tolist() == [False, True, False]
    # an infinite objective does not widen the tolerance
    w = np.array([[1.0, np.inf], [1.0 - 1e-6, 2.0], [1.0, 1.0]])
    assert pareto_mask(w, ["min", "min"]).tolist() == [False, True, True]
