"""The robustness campaign: thousands of generated and malformed designs, a table of outcomes.

    python tools/fuzz.py --designs 5000 [--seed 0] [--budget 20] [--json out.json]

(``make fuzz``). Every design comes from the hypothesis strategies of ``tests/strategies.py``
(the whole schema, realistic and extreme values, malformed sections) and is classified by
``strategies.outcome``: ok (written invariants within 1e-9 of the size), refused (a one-line
CCUError) or bug (anything else). A design that takes more than ``--budget`` CPU seconds is a
hang. Malformed design files (bad TOML, UTF-16, binary) and bad command lines go through
``ccu`` itself: exit 2 with one line and no output folder left is refused (and exit 3 with the
failed checks named, ``ccu fabricate``'s documented outcome, or ``ccu optimize``'s: no feasible
design, the least violating trials listed), anything else a bug.
Any message that says "this is a bug" or "please report" is a bug, whatever its exit code.
The exit status is 1 if any bug or hang was found.
"""

from __future__ import annotations

import argparse
import collections
import contextlib
import io
import json
import re
import signal
import sys
import tempfile
import time
from pathlib import Path

from hypothesis import HealthCheck, Phase, given, seed, settings
from hypothesis import strategies as st

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

import strategies  # noqa: E402
from compas_ccu.cli import main as ccu  # noqa: E402


class Hang(BaseException):  # not caught by the CLI's handler of unexpected errors
    pass


def _alarm(signum, frame):
    raise Hang


def timed(budget: float, function, *args):
    """``function(*args)`` with a budget of ``budget`` seconds of this process's CPU time
    (SIGPROF): (kind, detail). CPU time, not the clock: on a busy machine (or at ``nice`` 19
    beside other jobs) a design that waits for a core is not a hang."""
    signal.signal(signal.SIGPROF, _alarm)
    signal.setitimer(signal.ITIMER_PROF, budget)
    try:
        return function(*args)
    except Hang:
        return "hang", f"more than {budget:g} s of CPU"
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0)


def cli_outcome(argv: list, out: Path) -> tuple:
    """Run ``ccu`` in-process: exit 0 ok, exit 2 with one line and no ``out`` left refused."""
    err, out_text = io.StringIO(), io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(out_text):
        try:
            code = ccu(argv)
        except SystemExit as exc:  # argparse usage errors
            code = exc.code
    text = err.getvalue().strip()
    said = text + "\n" + out_text.getvalue()
    if strategies.asks_for_a_report(said):  # whatever the exit code
        return "bug", f"exit {code}, asks for a report: {said.strip()[-300:]}"
    if code == 0:
        return "ok", "exit 0"
    # argparse's own usage errors are "usage: ..." lines and one "error:" line
    last = text.splitlines()[-1] if text else ""
    usage = text.startswith("usage:") and last.startswith("ccu") and "error:" in last
    # the refusal is one line, the last: progress and warnings ("ccu: warning: ...") on stderr
    # may come before it, but no traceback and no second error
    lines = text.splitlines()
    one_line = (
        bool(lines)
        and lines[-1].startswith("ccu: error: ")
        and sum(line.startswith("ccu: error: ") for line in lines) == 1
        and not any(line.startswith("Traceback") for line in lines)
    )
    left_behind = out.exists()  # the campaign never creates it beforehand
    if code == 2 and (one_line or usage) and not left_behind:
        return "refused", re.sub(r"/tmp/\S+", "<file>", text.splitlines()[-1])[:70]
    # a check that fails (ccu fabricate without --allow-exceeded): the documented exit 3, the
    # files written for inspection and the failed checks named, no traceback; ccu optimize's
    # documented exit 3: no feasible design, the least violating trials listed
    if code == 3 and lines and "exit status 3" in lines[-1] and "Traceback" not in text:
        return "refused", "a check failed: exit 3, the files written for inspection"
    if code == 3 and "ccu optimize: no feasible design" in text and "Traceback" not in text:
        return "refused", "no feasible design: exit 3, the least violating trials listed"
    return "bug", f"exit {code}: {text[-300:]}"


def campaign(designs: int, seed_value: int, budget: float) -> list:
    rows = []

    @settings(
        max_examples=designs,
        database=None,
        derandomize=False,
        deadline=None,
        phases=[Phase.generate],
        suppress_health_check=list(HealthCheck),
    )
    @seed(seed_value)
    @given(doc=strategies.designs())
    def one(doc):
        start = time.perf_counter()
        kind, detail = timed(budget, strategies.outcome, doc)
        rows.append(
            {
                "source": "design",
                "kind": kind,
                "detail": detail,
                "seconds": time.perf_counter() - start,
                "design": repr(doc),
            }
        )

    @settings(
        max_examples=max(designs // 20, 10),
        database=None,
        deadline=None,
        phases=[Phase.generate],
        suppress_health_check=list(HealthCheck),
    )
    @given(
        data=strategies.toml_texts(),
        argv=st.sampled_from(
            [
                ["info"],
                ["deploy", "--out", "{out}"],
                ["path", "--steps", "3", "--out", "{out}"],
            ]
        ),
    )
    def files(data, argv):
        with tempfile.TemporaryDirectory() as folder:
            design = Path(folder) / "design.toml"
            design.write_bytes(data)
            out = Path(folder) / "out"
            args = [argv[0], str(design)] + [a.replace("{out}", str(out)) for a in argv[1:]]
            kind, detail = timed(budget, cli_outcome, args, out)
        rows.append({"source": "file", "kind": kind, "detail": detail, "design": repr(data)[:200]})

    bad_argv = [
        ["deploy", str(ROOT / "examples/cone.toml"), "--alpha", "nan", "--out", "{out}"],
        ["deploy", str(ROOT / "examples/cone.toml"), "--alpha", "95", "--out", "{out}"],
        ["path", str(ROOT / "examples/cone.toml"), "--steps", "0", "--out", "{out}"],
        ["path", str(ROOT / "examples/cone.toml"), "--steps", "1000000000", "--out", "{out}"],
        ["deploy", str(ROOT / "examples/cone.toml"), "--out", ""],
        ["fabricate", str(ROOT / "examples/cone.toml"), "--hinge-width", "1e6", "--out", "{out}"],
        ["deploy", str(ROOT / "examples/cone.toml"), "--out", "{out}", "--limit", "x=1"],
        ["info", "/nonexistent/design.toml"],
        ["deploy"],
    ]

    def arguments():
        for argv in bad_argv:
            with tempfile.TemporaryDirectory() as folder:
                out = Path(folder) / "out"
                args = [a.replace("{out}", str(out)) for a in argv]
                kind, detail = timed(budget, cli_outcome, args, out)
            rows.append(
                {"source": "argv", "kind": kind, "detail": detail, "design": " ".join(argv)}
            )

    one()
    files()
    arguments()
    return rows


# -- malformed input files and option values (issue 27 item 6) --------------------------------
#
# Four generators of their own, each case run through ``ccu`` and classified by cli_outcome:
# plate DXFs for ``ccu import`` (a fabricated cone's plate file mutated: $INSUNITS codes,
# non-finite or huge coordinates, truncation, missing layers, a crease SPLINE of coincident
# fit points), crease DXFs named by a design (random entities and unit codes), big curve files
# (CSV and DXF of 10^4 ... 10^6 points) and bad values of every number option of every command.

INPUT_SOURCES = ("plate-dxf", "crease-dxf", "curve-size", "option")

#: Values no number option takes (each case sets one option to one of them).
BAD_NUMBERS = ("nan", "inf", "-inf", "-1", "1e300", "-1e300", "10000000", "1000000000000", "x")

DESIGN_TEXT = """[crease]
profile = "polyline"
points = {points}
[rulings]
type = "orthogonal"
[deployment]
alpha = 30.0
[layout]
width = 0.3
"""


def _dxf_with(entities, units: int):
    import ezdxf

    doc = ezdxf.new()
    doc.header["$INSUNITS"] = units
    msp = doc.modelspace()
    for kind, data in entities:
        if kind == "lwpolyline":
            msp.add_lwpolyline(data)
        elif kind == "spline":
            msp.add_spline(fit_points=data)
        elif kind == "control":
            if len(data) > 3:
                msp.add_open_spline(data)
            else:
                msp.add_spline(fit_points=data)
        elif kind == "arc":
            msp.add_arc(*data)
        elif kind == "lines":
            for a, b in zip(data[:-1], data[1:]):
                msp.add_line(a, b)
    return doc


def _crease_points(rng, n: int) -> list:
    xs = sorted(rng.uniform(-1, 1) for _ in range(n))
    pts = [(x, 0.5 * rng.random() * (1.0 - x * x)) for x in xs]
    mode = rng.random()
    if mode < 0.3:  # coincident neighbours
        k = rng.randrange(len(pts))
        pts[k:k] = [pts[k]] * rng.randint(1, 3)
    elif mode < 0.4:  # all the same
        pts = [pts[0]] * len(pts)
    return pts


def crease_dxf_case(rng, folder: Path) -> list:
    """A design naming a crease DXF of one random entity (argv of ``ccu deploy``)."""
    kind = rng.choice(("lwpolyline", "spline", "spline", "control", "arc", "lines"))
    n = rng.choice((1, 2, 3, 4, 7, 20))
    if kind == "arc":
        data = ((0.0, 0.0), rng.choice((0.0, 1e-300, 1.0, 1e300)), 0.0, rng.uniform(0, 360))
    else:
        data = _crease_points(rng, n)
    units = rng.choice((0, 1, 2, 3, 4, 5, 6, 7, 14, 21, 99, -1, 1000000))
    doc = _dxf_with([(kind, data)], units)
    path = folder / "crease.dxf"
    doc.saveas(path)
    if rng.random() < 0.2:  # a non-finite or huge coordinate
        text = path.read_text().splitlines(keepends=True)
        spots = [k for k, line in enumerate(text[:-1]) if line.strip() == "10"]
        if spots:
            text[rng.choice(spots) + 1] = rng.choice(("nan\n", "inf\n", "-inf\n", "1e300\n"))
            path.write_text("".join(text))
    given = rng.choice(('"crease.dxf"', '{ file = "crease.dxf", units = "mm" }'))
    (folder / "design.toml").write_text(DESIGN_TEXT.format(points=given))
    return ["deploy", str(folder / "design.toml"), "--out", str(folder / "out")]


def plate_dxf_case(rng, folder: Path, plates: Path) -> list:
    """A fabricated cone's plate folder with one plate file mutated (argv of ``ccu import``)."""
    import shutil

    target = folder / "plates"
    shutil.copytree(plates, target)
    path = target / "plate_0.dxf"
    text = path.read_text()
    lines = text.splitlines(keepends=True)
    mode = rng.choice(("units", "units", "coordinate", "truncate", "layer", "spline", "bytes"))
    if mode == "units":
        k = lines.index("$INSUNITS\n")
        lines[k + 2] = f"{rng.choice((0, 1, 3, 7, 14, 17, 21, 99, -1, 1000000))}\n"
        path.write_text("".join(lines))
    elif mode == "coordinate":
        spots = [k for k, line in enumerate(lines[:-1]) if line.strip() in ("10", "20")]
        lines[rng.choice(spots) + 1] = rng.choice(("nan\n", "inf\n", "1e300\n", "-1e300\n"))
        path.write_text("".join(lines))
    elif mode == "truncate":
        path.write_text(text[: rng.randrange(len(text))])
    elif mode == "layer":
        layer = rng.choice(("CUT", "CREASE", "RULING_SCORE"))
        path.write_text(text.replace(f"\n{layer}\n", "\nOTHER\n"))
    elif mode == "spline":
        import ezdxf

        doc = ezdxf.readfile(path)
        msp = doc.modelspace()
        crease = next(e for e in msp if e.dxf.layer == "CREASE")
        pts = [tuple(p)[:2] for p in crease.vertices()] if crease.dxftype() == "LWPOLYLINE" else []
        pts = pts[:: max(1, len(pts) // 8)] or [(0.0, 0.0), (1.0, 0.0)]
        k = rng.randrange(len(pts))
        pts[k:k] = [pts[k]] * rng.randint(1, 3)
        if rng.random() < 0.3:
            pts = pts[:1] * len(pts)
        msp.delete_entity(crease)
        msp.add_spline(fit_points=pts, dxfattribs={"layer": "CREASE"})
        doc.saveas(path)
    else:
        path.write_bytes(bytes(rng.randrange(256) for _ in range(rng.randrange(1, 4000))))
    return ["import", str(target), "--out", str(folder / "out.toml")]


def curve_size_case(rng, folder: Path) -> list:
    """A design naming a curve file of 10^4 ... 10^6 points (CSV, or DXF LINE chains / one
    LWPOLYLINE written as text)."""
    import numpy as np

    n = rng.choice((10_000, 100_000, 250_000, 1_000_000))
    t = np.linspace(0.0, np.pi, n)
    xy = np.c_[2.0 * np.cos(t), np.sin(t)]
    kind = rng.choice(("csv", "csv", "lwpolyline", "lines"))
    if kind == "csv":
        name = "crease.csv"
        np.savetxt(folder / name, xy, delimiter=",", fmt="%.9f")
    else:
        name = "crease.dxf"
        if kind == "lines" and n > 20_000:
            n, xy = 20_000, xy[:: len(xy) // 20_000][:20_000]
        doc = _dxf_with([("lwpolyline", [(0.0, 0.0), (1.0, 0.0)])], 6)
        doc.saveas(folder / name)
        text = (folder / name).read_text()
        head, _, tail = text.partition("LWPOLYLINE\n")
        body, _, rest = tail.partition("\n  0\n")
        if kind == "lwpolyline":  # the vertex count (90) and the vertices (10, 20) replaced
            keep = body.split("\n 90\n")[0]
            vertices = "".join(f" 10\n{x:.9f}\n 20\n{y:.9f}\n" for x, y in xy)
            body = f"{keep}\n 90\n{n}\n 70\n0\n{vertices}".rstrip("\n")
            (folder / name).write_text(f"{head}LWPOLYLINE\n{body}\n  0\n{rest}")
        else:  # LINE entities in the LWPOLYLINE's place
            lines = "".join(
                f"  0\nLINE\n  8\n0\n 10\n{a[0]:.9f}\n 20\n{a[1]:.9f}\n 11\n{b[0]:.9f}\n"
                f" 21\n{b[1]:.9f}\n"
                for a, b in zip(xy[:-1], xy[1:])
            )
            (folder / name).write_text(head + lines[4:] + "  0\n" + rest)
    (folder / "design.toml").write_text(DESIGN_TEXT.format(points=f'"{name}"'))
    return ["deploy", str(folder / "design.toml"), "--out", str(folder / "out")]


def option_cases(plates: Path) -> list:
    """Every number option of every command set to every value of BAD_NUMBERS, the other
    arguments valid: (argv with ``{out}``)."""
    from compas_ccu.cli import COMMANDS

    cone = str(ROOT / "examples/cone.toml")
    positional = {
        "design": cone,
        "designs": cone,
        "sweep": str(ROOT / "examples/sweeps/vault.toml"),
        "study": str(ROOT / "examples/optimize/vault-sheets.toml"),
        "folder": str(plates),
    }
    cases = []
    for command in COMMANDS:
        base = [command.name]
        for o in command.options:
            if not o.flags[0].startswith("-"):
                base.append(positional.get(o.dest, cone))
        if any(o.flags[-1] == "--out" for o in command.options):
            base += ["--out", "{out}.toml" if command.name == "import" else "{out}"]
        if command.name in ("explore", "optimize"):
            base += ["--in-process"]  # never a local cluster of a bad size
        if command.name == "optimize":
            base += ["--trials", "2"]  # a valid seed is a whole study: keep it two trials
        if command.name == "scale":
            base += ["--to", "3"]
        for o in command.options:
            kind = o.settings.get("type")
            if kind not in (int, float) or o.flags[-1] == "--to" and command.name != "scale":
                continue
            for value in BAD_NUMBERS:
                if command.name == "validate" and value in ("10000000", "1000000000000"):
                    continue  # a large but valid load is a whole nonlinear FE run, not a refusal
                flag = o.flags[-1]
                args = [a for a in base]
                if flag == "--to":
                    args = args[:-2]
                extra = [flag, value] + ([value] if o.settings.get("nargs") == 2 else [])
                cases.append(args + extra)
        if command.name == "scale":  # the options that hold numbers in their text
            for value in ("nanx1", "infx1.22", "2.44x0", "1e300x1", "2.44"):
                cases.append(base + ["--sheet", value])
            for value in ("nan", "inf", "0.008,nan", "-1", "1e300"):
                cases.append(base + ["--thickness-law", "given", "--thickness", value])
    return cases


def input_campaign(count: int, seed_value: int, budget: float) -> list:
    """``count`` cases of the plate, crease and curve-size generators (in the ratio 2 : 6 : 1)
    and as many of :func:`option_cases` (evenly spaced; all of them from ``count`` >= their
    number, 334): rows of the outcome table."""
    import random

    rng = random.Random(seed_value)
    rows = []
    with tempfile.TemporaryDirectory() as cache:
        plates = Path(cache) / "fab"
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            ccu(["fabricate", str(ROOT / "examples/cone.toml"), "--nesting", "shelf",
                 "--allow-exceeded", "--quiet", "--out", str(plates)])  # fmt: skip

        def run(source, make):
            with tempfile.TemporaryDirectory() as folder:
                argv = make(Path(folder))
                out = Path(argv[-1])
                start = time.perf_counter()
                kind, detail = timed(budget, cli_outcome, argv, out)
                rows.append({"source": source, "kind": kind, "detail": detail,
                             "seconds": time.perf_counter() - start,
                             "design": " ".join(argv)[-200:]})  # fmt: skip

        plan = ["plate-dxf"] * 2 + ["crease-dxf"] * 6 + ["curve-size"]
        for k in range(count):
            source = plan[k % len(plan)]
            case_rng = random.Random(rng.random())
            if source == "plate-dxf":
                run(source, lambda f, r=case_rng: plate_dxf_case(r, f, plates / "plates"))
            elif source == "crease-dxf":
                run(source, lambda f, r=case_rng: crease_dxf_case(r, f))
            else:
                run(source, lambda f, r=case_rng: curve_size_case(r, f))
        options = option_cases(plates / "plates")
        step = -(-len(options) // count) if count else len(options) + 1
        for argv in options[::step]:  # all of them from count >= len(options)
            run("option", lambda f, a=argv: [x.replace("{out}", str(f / "out")) for x in a])
    return rows


def table(rows: list) -> str:
    kinds = collections.Counter((r["source"], r["kind"]) for r in rows)
    lines = ["| source | ok | refused | bug | hang | total |", "|---|---|---|---|---|---|"]
    for source in ("design", "file", "argv") + INPUT_SOURCES:
        n = {k: kinds.get((source, k), 0) for k in ("ok", "refused", "bug", "hang")}
        lines.append(
            f"| {source} | {n['ok']} | {n['refused']} | {n['bug']} | {n['hang']} | "
            f"{sum(n.values())} |"
        )
    reasons = collections.Counter(r["detail"] for r in rows if r["kind"] == "refused")
    lines += ["", "Most common refusals:"] + [f"- {n} x {d}" for d, n in reasons.most_common(12)]
    bugs = [r for r in rows if r["kind"] in ("bug", "hang")]
    lines += ["", f"Bugs and hangs: {len(bugs)}"] + [
        f"- {r['kind']}: {r['detail'][:200]} <- {r['design'][:200]}" for r in bugs[:20]
    ]
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--designs", type=int, default=5000)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--budget", type=float, default=20.0, help="CPU seconds per design")
    parser.add_argument("--json", type=Path, default=None, help="write every outcome here")
    parser.add_argument(
        "--inputs", type=int, default=None, help="input-file cases (default: designs / 5)"
    )
    args = parser.parse_args(argv)
    start = time.perf_counter()
    rows = campaign(args.designs, args.seed, args.budget) if args.designs else []
    inputs = args.designs // 5 if args.inputs is None else args.inputs
    rows += input_campaign(inputs, args.seed, args.budget)
    print(table(rows))
    print(f"\n{len(rows)} cases in {time.perf_counter() - start:.0f} s")
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(rows, indent=1))
    return 1 if any(r["kind"] in ("bug", "hang") for r in rows) else 0


if __name__ == "__main__":
    sys.exit(main())
