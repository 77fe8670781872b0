"""Sweeps on Dask: expected rows, identical numbers in-process and on a cluster, resuming,
killed workers, errors, the summary and the ``ccu explore`` command."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from compas_ccu.cli import main
from compas_ccu.design import load_design
from compas_ccu.errors import SweepError
from compas_ccu.explore import load_sweep, run_sweep
from compas_ccu.explore.results import Journal, read_table
from compas_ccu.explore.run import local_cluster
from compas_ccu.model import CCUModel
from conftest import EXAMPLES
from imagecheck import assert_picture, load_rgb

pytestmark = pytest.mark.slow
distributed = pytest.importorskip("distributed")

# columns that depend on where and when a variant ran, not on its numbers
PLACE = ("seconds", "t_model", "t_path", "t_thickness", "t_collisions", "t_fe", "worker", "run")

SWEEP = """
[sweep]
name = "small"
base = "base.toml"
best = 3

[parameters]
"crease.rise" = [0.8, 1.0, 1.2, -1.0]        # -1: an impossible design (DesignError)
"plates.thickness" = [0.006, 0.008, 0.1]     # 0.1 m: thicker than half a plate (GeometryError)

[checks]
path_states = 5
"""


def write_base(folder: Path, *, segments=16, plates=4, spacing=0.05) -> None:
    """The vault with fewer segments and plates; 50 mm plane spacing: plates ~0.1 m wide."""
    text = (EXAMPLES / "vault.toml").read_text()
    text = text.replace("spacing = 0.12", f"spacing = {spacing}")
    text = text.replace("segments = 64", f"segments = {segments}")
    text = text.replace("plates = 10", f"plates = {plates}")
    (folder / "base.toml").write_text(text)


@pytest.fixture(scope="module")
def small(tmp_path_factory):
    folder = tmp_path_factory.mktemp("sweep")
    write_base(folder)
    (folder / "sweep.toml").write_text(SWEEP)
    return load_sweep(folder / "sweep.toml")


@pytest.fixture(scope="module")
def cluster():
    """A local cluster of 2 worker processes, shared by the tests of this module."""
    c = local_cluster(2)
    client = distributed.Client(c)
    yield c, client
    client.close()
    c.close()


@pytest.fixture(scope="module")
def on_cluster(small, cluster, tmp_path_factory):
    out = tmp_path_factory.mktemp("cluster")
    return run_sweep(small, out, client=cluster[1], progress=False)


def numbers(row: dict) -> dict:
    return {k: v for k, v in row.items() if k not in PLACE}


def test_a_small_sweep_on_a_local_cluster_gives_the_expected_rows(on_cluster, small):
    r = on_cluster
    assert (r.total, r.computed, r.reused, r.interrupted) == (12, 12, 0, False)
    assert [row["variant"] for row in r.rows] == [v.id for v in small.variants]
    assert [row["index"] for row in r.rows] == list(range(12))
    by = {(row["crease.rise"], row["plates.thickness"]): row for row in r.rows}
    for rise in (0.8, 1.0, 1.2):
        for t in (0.006, 0.008):
            row = by[(rise, t)]
            assert row["status"] == "ok" and row["error"] is None
            assert row["rise"] == pytest.approx(rise, abs=1e-12)  # the deployed crease is given
            assert row["stack_height"] == pytest.approx(4 * t, abs=1e-15)
            assert row["plates"] == 4 and row["run"] == 1
        bad = by[(rise, 0.1)]
        assert (bad["status"], bad["stage"], bad["error_type"]) == (
            "failed",
            "thickness",
            "GeometryError",
        )
        assert "more than half the narrowest plate width" in bad["error"]
        assert bad["span"] == pytest.approx(2.5, abs=1e-12)  # measured before the failing stage
    for t in (0.006, 0.008, 0.1):
        bad = by[(-1.0, t)]
        assert (bad["stage"], bad["error_type"]) == ("model", "DesignError")
        assert bad["error"].startswith("crease.rise: ") and "> 0" in bad["error"]
        assert bad["span"] is None
    assert r.failed == 6
    # the Parquet table holds the same rows, with the parameters first and the metric types kept
    table = read_table(r.out / "results.parquet")
    assert table == r.rows
    import pyarrow.parquet as pq

    schema = pq.read_schema(r.out / "results.parquet")
    assert schema.names[:6] == [
        "variant",
        "index",
        "crease.rise",
        "plates.thickness",
        "status",
        "stage",
    ]
    assert (
        str(schema.field("plates").type) == "int64"
        and str(schema.field("global_curvature").type) == "string"
    )
    assert json.loads(schema.metadata[b"ccu.sweep"])["fingerprint"] == small.fingerprint


def test_in_process_and_on_the_cluster_the_numbers_are_identical(on_cluster, small, tmp_path):
    local = run_sweep(small, tmp_path, in_process=True, progress=False, summary=False)
    assert local.scheduler == "in-process" and local.computed == 12
    assert [numbers(r) for r in local.rows] == [numbers(r) for r in on_cluster.rows]
    assert len({r["worker"] for r in local.rows}) == 1


def test_the_summary_files(on_cluster, small):
    s, out = on_cluster.summary, on_cluster.out
    assert (s["variants"], s["ok"], s["failed"]) == (12, 6, 6)
    assert s["errors"] == {"DesignError": 3, "GeometryError": 3}
    assert s["failed_stage"] == {"model": 3, "thickness": 3}
    # the 8 mm plates of every arch exceed the EC5 design bending strength (plate stress)
    rows = {r["variant"]: r for r in on_cluster.rows}
    over = sorted(
        (r["crease.rise"], r["plates.thickness"])
        for r in rows.values()
        if r["status"] == "ok" and r["bending_utilisation"] > 1.0
    )
    assert over == [(0.8, 0.008), (1.0, 0.008), (1.2, 0.008)]
    assert s["feasible"] == 3 and s["run"]["computed"] == 12
    assert json.loads((out / "summary.json").read_text())["pareto"] == s["pareto"]
    # Pareto of (rise max, bending min, stack min): every feasible row trades off or wins
    rows = {r["variant"]: r for r in on_cluster.rows}
    front = [rows[v] for v in s["pareto"]]
    assert {r["plates.thickness"] for r in front} == {0.006}  # thinner: less bending, less stack
    assert len(s["best"]) == 3 and [b["rank"] for b in s["best"]] == [1, 2, 3]
    for b in s["best"]:
        folder = Path(b["folder"])
        design = load_design(folder / "design.toml")
        row = rows[b["variant"]]
        structure = CCUModel(design).deploy()
        assert structure.metrics["rise"] == row["rise"]  # the file reproduces the variant
        from compas_ccu.io import read_structure_json

        assert read_structure_json(folder / "structure.json").metrics["rise"] == row["rise"]
        assert (folder / "structure.obj").stat().st_size > 0
    for name in ("design_space", "pareto"):
        assert_picture(load_rgb(out / "plots" / f"{name}.png"), min_ink=0.02, min_colours=30)


def test_the_sweep_resumes_and_computes_only_what_is_missing(small, tmp_path):
    first = run_sweep(small, tmp_path, in_process=True, progress=False, summary=False)
    journal = (tmp_path / "journal.jsonl").read_text().splitlines()
    # keep 5 finished rows, and a line cut off by a kill in the middle of writing
    (tmp_path / "journal.jsonl").write_text("\n".join(journal[:5]) + "\n" + journal[5][:40])
    again = run_sweep(small, tmp_path, in_process=True, progress=False, summary=False)
    assert (again.reused, again.computed) == (5, 7)
    runs = [r["run"] for r in again.rows]
    assert runs == [1] * 5 + [2] * 7  # the first five were not recomputed
    assert [numbers(r) for r in again.rows] == [numbers(r) for r in first.rows]
    lines = (tmp_path / "journal.jsonl").read_text().splitlines()
    assert len(lines) == 13 and len(Journal(tmp_path / "journal.jsonl").read()) == 12  # + the cut
    nothing = run_sweep(small, tmp_path, in_process=True, progress=False, summary=False)
    assert (nothing.reused, nothing.computed, nothing.seconds) == (12, 0, 0.0)


def test_a_grown_sweep_reuses_its_variants(small, tmp_path):
    run_sweep(small, tmp_path, in_process=True, progress=False, summary=False)
    text = (small.base_path.parent / "sweep.toml").read_text()
    grown = tmp_path / "grown.toml"
    grown.write_text(
        text.replace("[0.8, 1.0, 1.2, -1.0]", "[0.8, 0.9, 1.0, 1.2, -1.0]").replace(
            'base = "base.toml"', f'base = "{small.base_path}"'
        )
    )
    r = run_sweep(load_sweep(grown), tmp_path, in_process=True, progress=False, summary=False)
    assert (r.total, r.reused, r.computed) == (15, 12, 3)
    assert {row["crease.rise"] for row in r.rows if row["run"] == 2} == {0.9}


def test_cluster_failures_are_computed_again_on_resume(small, tmp_path):
    run_sweep(small, tmp_path, in_process=True, progress=False, summary=False)
    rows = Journal(tmp_path / "journal.jsonl").read()
    victim = small.variants[0].id
    lost = {**rows[victim], "status": "failed", "stage": "cluster", "error_type": "KilledWorker"}
    Journal(tmp_path / "journal.jsonl").append(lost)
    r = run_sweep(small, tmp_path, in_process=True, progress=False, summary=False)
    assert (r.reused, r.computed) == (11, 1) and r.rows[0]["status"] == "ok"


def test_a_folder_of_another_sweep_is_refused(small, tmp_path):
    run_sweep(small, tmp_path, in_process=True, progress=False, summary=False)
    doc = dict(small.document, checks={"path_states": 7})
    other = type(small)(doc, base_dir=small.base_path.parent)
    with pytest.raises(SweepError, match=r"holds results of a different sweep .* fingerprint"):
        run_sweep(other, tmp_path, in_process=True, progress=False)


def test_a_killed_worker_loses_no_result(cluster, tmp_path):
    """Kill one of the two worker processes mid-sweep: Dask restarts it and recomputes what it
    held; every variant ends up in the table exactly once."""
    _, client = cluster
    write_base(tmp_path, segments=32, plates=6, spacing=0.12)
    text = (
        SWEEP.replace("-1.0]", "1.4]")
        .replace(", 0.1]", ", 0.010]")
        .replace("path_states = 5", "path_states = 9\ncollisions = true")
    )
    (tmp_path / "sweep.toml").write_text(text)
    s = load_sweep(tmp_path / "sweep.toml")
    out = tmp_path / "out"
    journal = out / "journal.jsonl"
    killed = {}

    def kill_one():
        while not (journal.exists() and len(journal.read_text().splitlines()) >= 2):
            time.sleep(0.02)
        pids = client.run(os.getpid)
        worker, pid = sorted(pids.items())[0]
        os.kill(pid, signal.SIGKILL)
        killed[worker] = pid

    thread = threading.Thread(target=kill_one, daemon=True)
    thread.start()
    r = run_sweep(s, out, client=client, progress=False, summary=False, window=3)
    thread.join(timeout=30)
    assert killed, "no worker was killed"
    failed = [
        (row.get("stage"), row.get("error_type"), row.get("error"))
        for row in r.rows
        if row["status"] != "ok"
    ]
    assert r.computed == 12 and failed == []
    ids = [json.loads(line)["variant"] for line in journal.read_text().splitlines()]
    assert sorted(ids) == sorted(v.id for v in s.variants)  # each result written once
    client.wait_for_workers(2, timeout=30)  # the nanny restarted it


def test_an_existing_cluster_by_address(small, cluster, on_cluster, tmp_path):
    r = run_sweep(
        small, tmp_path, scheduler=cluster[0].scheduler_address, progress=False, summary=False
    )
    assert r.scheduler == cluster[0].scheduler_address and r.workers == 2
    assert [numbers(x) for x in r.rows] == [numbers(x) for x in on_cluster.rows]


def test_scheduler_errors(small, tmp_path, monkeypatch):
    import compas_ccu.explore.cluster as cluster

    monkeypatch.setattr(cluster, "CONNECT_TIMEOUT", "1s")
    with pytest.raises(
        SweepError, match=r"cannot connect to the Dask scheduler at 'tcp://127.0.0.1:9'"
    ):
        run_sweep(small, tmp_path, scheduler="tcp://127.0.0.1:9", progress=False)
    with pytest.raises(SweepError, match=r"--workers sizes the local cluster"):
        run_sweep(small, tmp_path, scheduler="tcp://127.0.0.1:9", workers=2, progress=False)
    with pytest.raises(SweepError, match=r"--workers must be >= 1, got 0"):
        run_sweep(small, tmp_path / "b", workers=0, progress=False)


def ccu(*args, **kw):
    return subprocess.run(
        [sys.executable, "-m", "compas_ccu.cli", *map(str, args)],
        capture_output=True,
        text=True,
        cwd=Path(__file__).resolve().parents[1],
        **kw,
    )


def test_ccu_explore_on_a_local_cluster(small, on_cluster, tmp_path):
    p = ccu("explore", small.base_path.parent / "sweep.toml", "--out", tmp_path, "--workers", "2")
    assert p.returncode == 0, p.stderr
    assert (
        "sweep small: 12 variants (grid) of base.toml over crease.rise, plates.thickness"
        in p.stdout
    )
    assert "computed 12 variants in" in p.stdout and "on 2 local Dask workers" in p.stdout
    assert "12 variants: 6 ok, 6 failed (3 DesignError, 3 GeometryError); 3 feasible" in p.stdout
    assert "best 1: crease.rise = " in p.stdout
    rows = read_table(tmp_path / "results.parquet")
    assert [numbers(r) for r in rows] == [numbers(r) for r in on_cluster.rows]
    assert "variant/s" in p.stderr  # the progress bar
    again = ccu("explore", small.base_path.parent / "sweep.toml", "--out", tmp_path, "--quiet")
    assert again.returncode == 0 and again.stdout == ""


def test_ccu_explore_interrupted_resumes_without_recomputing(tmp_path):
    """Ctrl-C (SIGINT) and SIGTERM stop the run cleanly: the finished rows are in the table, and
    the same command computes only the rest."""
    write_base(tmp_path, segments=48, plates=6, spacing=0.12)
    text = SWEEP.replace("-1.0]", "1.4]").replace(", 0.1]", ", 0.010]")
    (tmp_path / "sweep.toml").write_text(
        text.replace("path_states = 5", "path_states = 11\ncollisions = true")
    )
    out = tmp_path / "out"
    for sig in (signal.SIGINT, signal.SIGTERM):
        proc = subprocess.Popen(
            [
                sys.executable,
                "-m",
                "compas_ccu.cli",
                "explore",
                tmp_path / "sweep.toml",
                "--out",
                out,
                "--workers",
                "1",
            ],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            cwd=Path(__file__).resolve().parents[1],
        )
        journal = out / "journal.jsonl"
        deadline = time.time() + 120
        start = len(journal.read_text().splitlines()) if journal.exists() else 0
        while time.time() < deadline and (
            not journal.exists() or len(journal.read_text().splitlines()) < start + 2
        ):
            time.sleep(0.05)
        proc.send_signal(sig)
        stdout, stderr = proc.communicate(timeout=60)
        assert proc.returncode == 130, stderr
        saved = read_table(out / "results.parquet")
        assert f"interrupted with {len(saved)} of 12 variants saved" in stderr
        assert start + 2 <= len(saved) < 12
    before = {r["variant"]: r for r in saved}
    p = ccu("explore", tmp_path / "sweep.toml", "--out", out, "--in-process", "--no-plots")
    assert p.returncode == 0, p.stderr
    assert f"{len(before)} variants were already in {out} (not recomputed)" in p.stdout
    assert f"computed {12 - len(before)} variants" in p.stdout
    rows = read_table(out / "results.parquet")
    assert len(rows) == 12 and all(r["status"] == "ok" for r in rows)
    for r in rows:
        if r["variant"] in before:
            assert r == before[r["variant"]]  # same run, same numbers: not recomputed
        else:
            assert r["run"] == 3


def test_ccu_explore_bad_input_exit_2(tmp_path):
    (tmp_path / "s.toml").write_text('[sweep]\nbase = "nope.toml"\n')
    p = ccu("explore", tmp_path / "s.toml", "--out", tmp_path / "o")
    assert p.returncode == 2 and "sweep.base: base design: cannot read design file" in p.stderr
    write_base(tmp_path)
    (tmp_path / "s.toml").write_text(SWEEP)
    p = ccu(
        "explore", tmp_path / "s.toml", "--out", tmp_path / "o", "--in-process", "--workers", "2"
    )
    assert p.returncode == 2 and "--in-process runs without Dask" in p.stderr
    assert not (tmp_path / "o").exists()


def test_example_sweep_stage_names_match_the_table(small):
    from compas_ccu.explore.run import columns

    names, declared = columns(small)
    assert names[-8:] == [
        "seconds",
        "t_model",
        "t_path",
        "t_thickness",
        "t_collisions",
        "t_fe",
        "worker",
        "run",
    ]
    assert set(declared) <= set(names) and np.all(
        [declared[k] in ("float", "int", "bool", "str") for k in declared]
    )


def test_an_fe_sweep_on_the_cluster(cluster, tmp_path):
    """Kratos runs inside the Dask workers; FE metrics land in the table."""
    s = load_sweep(EXAMPLES / "sweeps" / "cone-fe.toml")
    assert s.fe == {"engine": "kratos", "element_size": 0.2, "steps": 4, "checks": True}
    s.variants = s.variants[:2]
    r = run_sweep(s, tmp_path, client=cluster[1], progress=False, plots=False)
    assert [row["status"] for row in r.rows] == ["ok", "ok"], [row["error"] for row in r.rows]
    for row in r.rows:
        assert 0.0 < row["fe_deviation_percent"] < 1.0 and row["fe_elements"] > 0
        assert 0.0 < row["fe_utilisation"] < 1.0 and row["fe_buckling_factor"] > 1.0
        assert row["t_fe"] > row["t_model"]
    assert r.summary["objectives"] == {"rise": "max", "fe_utilisation": "min"}


def test_bad_workers_are_refused_before_anything_is_written(tmp_path, capsys):
    out = tmp_path / "out"
    assert (
        main(
            [
                "explore",
                str(EXAMPLES / "sweeps" / "vault.toml"),
                "--out",
                str(out),
                "--workers",
                "0",
            ]
        )
        == 2
    )
    assert "--workers must be >= 1, got 0" in capsys.readouterr().err
    assert not out.exists()
    with pytest.raises(SweepError, match=r"--workers must be >= 1, got 0"):
        run_sweep(load_sweep(EXAMPLES / "sweeps" / "vault.toml"), out, workers=0)
    assert not out.exists()
