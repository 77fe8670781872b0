"""The robustness campaign: thousands of generated and malformed designs, a table of outcomes.

    python tools/fuzz.py --designs 5000 [--seed 0] [--budget 20] [--json out.json]

(``make fuzz``). Every design comes from the hypothesis strategies of ``tests/strategies.py``
(the whole schema, realistic and extreme values, malformed sections) and is classified by
``strategies.outcome``: ok (written invariants within 1e-9 of the size), refused (a one-line
CCUError) or bug (anything else). A design that runs longer than ``--budget`` seconds is a
hang. Malformed design files (bad TOML, UTF-16, binary) and bad command lines go through
``ccu`` itself: exit 2 with one line and no output folder left is refused, anything else a bug.
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


class Hang(Exception):
    pass


def _alarm(signum, frame):
    raise Hang


def timed(budget: float, function, *args):
    """``function(*args)`` with a time budget (SIGALRM): (kind, detail)."""
    signal.signal(signal.SIGALRM, _alarm)
    signal.setitimer(signal.ITIMER_REAL, budget)
    try:
        return function(*args)
    except Hang:
        return "hang", f"more than {budget:g} s"
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)


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
    one_line = text.count("\n") == 0 and text.startswith("ccu: error: ")
    left_behind = out.exists()  # the campaign never creates it beforehand
    if code == 2 and (one_line or usage) and not left_behind:
        return "refused", re.sub(r"/tmp/\S+", "<file>", text.splitlines()[-1])[:70]
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


def table(rows: list) -> str:
    kinds = collections.Counter((r["source"], r["kind"]) for r in rows)
    lines = ["| source | ok | refused | bug | hang | total |", "|---|---|---|---|---|---|"]
    for source in ("design", "file", "argv"):
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
    parser.add_argument("--budget", type=float, default=20.0, help="seconds per design")
    parser.add_argument("--json", type=Path, default=None, help="write every outcome here")
    args = parser.parse_args(argv)
    start = time.perf_counter()
    rows = campaign(args.designs, args.seed, args.budget)
    print(table(rows))
    print(f"\n{len(rows)} cases in {time.perf_counter() - start:.0f} s")
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(rows, indent=1))
    return 1 if any(r["kind"] in ("bug", "hang") for r in rows) else 0


if __name__ == "__main__":
    sys.exit(main())
