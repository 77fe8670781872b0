"""Process-level habits of ``ccu``: a reader that leaves, Ctrl-C and SIGTERM, stdout for results
and stderr for progress, OpenSees' exit message, an unreachable ``--scheduler``."""

from __future__ import annotations

import importlib.util
import json
import os
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

import compas_ccu
from compas_ccu import outputs
from compas_ccu.cli import main
from compas_ccu.cli.common import progress
from compas_ccu.cli.process import ReaderGuard, process_habits
from compas_ccu.errors import SweepError
from conftest import EXAMPLES

VAULT = str(EXAMPLES / "vault.toml")
SRC = str(Path(compas_ccu.__file__).resolve().parents[1])  # the package under test


def _env() -> dict:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([SRC, *filter(None, [env.get("PYTHONPATH")])])
    return env


def _ccu(*args, **kw):
    kw.setdefault("stdout", subprocess.PIPE)
    kw.setdefault("stderr", subprocess.PIPE)
    return subprocess.run(
        [sys.executable, "-m", "compas_ccu.cli", *map(str, args)],
        text=True,
        env=_env(),
        timeout=300,
        **kw,
    )


def _closed_pipe():
    """The write end of a pipe whose reader has already left."""
    read, write = os.pipe()
    os.close(read)
    return write


def _files(folder: Path) -> dict:
    files = (p for p in folder.rglob("*") if p.is_file())
    return {p.relative_to(folder).as_posix(): p.read_bytes() for p in files}


# -- a reader that leaves ------------------------------------------------------------------------


@pytest.mark.slow  # a ccu process of its own (1-2 s)
@pytest.mark.parametrize("argv", [["info", VAULT, "--json"], ["info", VAULT], ["--help"]])
def test_a_closed_stdout_is_not_an_error(argv):
    write = _closed_pipe()
    try:
        p = _ccu(*argv, stdout=write)
    finally:
        os.close(write)
    assert (p.returncode, p.stderr) == (0, "")


@pytest.mark.slow  # a ccu process of its own (1-2 s)
def test_a_closed_stdout_does_not_stop_the_work(tmp_path):
    write = _closed_pipe()
    try:
        p = _ccu("deploy", VAULT, "--out", tmp_path / "d", stdout=write)
    finally:
        os.close(write)
    assert (p.returncode, p.stderr) == (0, "")
    manifest = json.loads((tmp_path / "d" / outputs.MANIFEST).read_text())
    assert manifest["files"] == ["structure.compas.json", "structure.json", "structure.obj"]


@pytest.mark.slow  # a ccu process of its own (1-2 s)
def test_head_reads_the_first_line_and_ccu_exits_quietly():
    p = subprocess.Popen(
        [sys.executable, "-m", "compas_ccu.cli", "info", VAULT, "--json"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        env=_env(),
    )
    first = p.stdout.readline()
    p.stdout.close()  # like head -1
    err = p.stderr.read()
    assert (first, p.wait(timeout=300), err) == (b"{\n", 0, b"")


def test_a_reader_guard_turns_a_broken_pipe_into_a_sink():
    class Broken:
        def write(self, text):
            raise BrokenPipeError(32, "Broken pipe")

        def flush(self):
            raise BrokenPipeError(32, "Broken pipe")

        encoding = "utf-8"

    guard = ReaderGuard(Broken())
    assert guard.write("abc") == 3 and guard.left  # no file descriptor: only the flag
    guard.flush()
    guard.writelines(["a", "b"])
    assert guard.encoding == "utf-8"


def test_process_habits_restore_the_streams_and_the_sigterm_handler():
    before = sys.stdout, sys.stderr, signal.getsignal(signal.SIGTERM)
    with process_habits():
        assert isinstance(sys.stdout, ReaderGuard) and isinstance(sys.stderr, ReaderGuard)
        assert signal.getsignal(signal.SIGTERM) is not before[2]
    assert (sys.stdout, sys.stderr, signal.getsignal(signal.SIGTERM)) == before


# -- stdout is data, stderr is progress --------------------------------------------------------


def test_info_json_is_the_only_thing_on_stdout():
    p = _ccu("info", VAULT, "--json")
    assert (p.returncode, p.stderr) == (0, "")
    data = json.loads(p.stdout)
    assert data["format"] == "ccu.info"
    assert data["key_figures"]["plates"] == 10


def test_progress_goes_to_stderr_and_results_to_stdout(tmp_path, capsys):
    argv = ["catalog", "--only", "fig09a-arc", "--steps", "2", "--no-figures", "--no-relax"]
    assert main([*argv, "--out", str(tmp_path / "c")]) == 0
    captured = capsys.readouterr()
    assert captured.err == "measuring fig09a-arc\n"
    lines = captured.out.splitlines()
    assert lines[0].startswith("fig09a-arc ") and "measured monoclastic" in lines[0]
    assert lines[1] == f"wrote 5 files into {tmp_path / 'c'} (table: catalog.md)"
    assert main([*argv, "--out", str(tmp_path / "q"), "--quiet"]) == 0
    assert capsys.readouterr() == ("", "")


def test_progress_respects_quiet(capsys):
    class Args:
        quiet = False

    progress(Args, "validating vault ...")
    Args.quiet = True
    progress(Args, "not shown")
    assert capsys.readouterr() == ("", "validating vault ...\n")


# -- Ctrl-C and SIGTERM ------------------------------------------------------------------------


def _default_sigint():  # a test runner may ignore SIGINT; ccu then would too
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _stop_path(out: Path, sig) -> subprocess.CompletedProcess:
    """Start ``ccu path --steps 1000 --out OUT`` and send ``sig`` once its staging folder exists."""
    p = subprocess.Popen(
        [sys.executable, "-m", "compas_ccu.cli", "path", VAULT, "--steps", "1000", "--out", out],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=_env(),
        preexec_fn=_default_sigint,
    )
    staging = f".{out.name}.ccu-staging-{p.pid}"
    deadline = time.monotonic() + 120
    while not (out.parent / staging).exists():
        assert p.poll() is None, p.communicate()
        assert time.monotonic() < deadline, "no staging folder"
        time.sleep(0.02)
    time.sleep(0.3)  # into the work
    p.send_signal(sig)
    stdout, stderr = p.communicate(timeout=120)
    assert not (out.parent / staging).exists()
    return subprocess.CompletedProcess(p.args, p.returncode, stdout, stderr)


@pytest.mark.slow  # a ccu process of its own (1-2 s)
@pytest.mark.parametrize(
    "sig, status, line",
    [(signal.SIGINT, 130, "ccu: interrupted\n"), (signal.SIGTERM, 143, "ccu: terminated\n")],
)
def test_a_signal_is_one_line_and_keeps_the_previous_run(tmp_path, sig, status, line):
    out = tmp_path / "p"
    assert _ccu("path", VAULT, "--steps", "2", "--out", out, "--quiet").returncode == 0
    before = _files(out)
    assert len(before) == 5  # path.csv, 3 states, the manifest
    p = _stop_path(out, sig)
    assert (p.returncode, p.stdout, p.stderr) == (status, "", line)
    assert _files(out) == before
    assert sorted(q.name for q in tmp_path.iterdir()) == ["p"]


@pytest.mark.slow  # a ccu process of its own (1-2 s)
def test_a_signal_before_the_first_run_leaves_no_folder(tmp_path):
    p = _stop_path(tmp_path / "fresh", signal.SIGTERM)
    assert (p.returncode, p.stderr) == (143, "ccu: terminated\n")
    assert list(tmp_path.iterdir()) == []


@pytest.fixture
def python_sigint():
    """SIGINT raises KeyboardInterrupt for the test, as in an interactive shell: a runner started
    in the background (``cmd &`` without job control) inherits SIGINT ignored, and Python keeps it
    ignored, so these tests would see no signal at all."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


def test_a_signal_during_the_commit_waits_for_it(tmp_path, monkeypatch, python_sigint):
    commit = outputs._commit

    def interrupted_commit(stage, out):
        # raise_signal: to this (the main) thread, handled before it returns; os.kill on the
        # process may reach another thread (pytest-xdist's) that a busy machine runs late
        signal.raise_signal(signal.SIGINT)  # held until the files are in
        return commit(stage, out)

    monkeypatch.setattr(outputs, "_commit", interrupted_commit)
    out = tmp_path / "run"
    with pytest.raises(KeyboardInterrupt):
        with outputs.staged_folder(out) as stage:
            (stage / "a.txt").write_text("one")
            (stage / "b.txt").write_text("two")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run"]  # no staging folder
    assert _files(out) == {
        "a.txt": b"one",
        "b.txt": b"two",
        outputs.MANIFEST: json.dumps(
            {"format": "ccu.files", "version": 1, "files": ["a.txt", "b.txt"]}, indent=1
        ).encode()
        + b"\n",
    }


def test_signals_held_delivers_the_first_signal_after_the_block(python_sigint):
    ran = []
    with pytest.raises(KeyboardInterrupt):
        with outputs.signals_held():
            signal.raise_signal(signal.SIGINT)  # to this thread (see above)
            ran.append("after the signal")
    assert ran == ["after the signal"]
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_signals_held_leaves_an_ignored_signal_ignored():
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)  # as under nohup or `cmd &`
    try:
        ran = []
        with outputs.signals_held():
            assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
            signal.raise_signal(signal.SIGINT)
            ran.append("after the signal")
        assert ran == ["after the signal"]
        assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
    finally:
        signal.signal(signal.SIGINT, previous)


# -- OpenSees --------------------------------------------------------------------------------------


@pytest.mark.slow  # a ccu process of its own (1-2 s)
def test_opensees_exit_message_does_not_reach_the_user():
    if importlib.util.find_spec("openseespy") is None:  # not imported here: it would print
        pytest.skip("openseespy is not installed")
    plain = [sys.executable, "-c", "import openseespy.opensees"]
    bare = subprocess.run(plain, capture_output=True, text=True, timeout=120)
    if "Process 0 Terminating" not in bare.stdout + bare.stderr:
        pytest.skip("this OpenSeesPy prints nothing at exit")
    code = (
        "import sys; from compas_ccu.fea.engines import opensees; "
        "print(opensees.available()[0]); ops = opensees._import_opensees(); ops.wipe(); "
        "print('last line', file=sys.stderr)"
    )
    p = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=_env(), timeout=120
    )
    assert (p.returncode, p.stdout, p.stderr) == (0, "True\n", "last line\n")


# -- --scheduler --------------------------------------------------------------------------------


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]  # closed again: nothing listens there


@pytest.mark.slow  # a ccu process of its own (1-2 s)
@pytest.mark.parametrize(
    "argv",
    [
        ["explore", EXAMPLES / "sweeps" / "vault.toml"],
        ["optimize", EXAMPLES / "optimize" / "vault-sheets.toml"],
    ],
)
def test_a_refused_scheduler_is_one_line_and_leaves_no_folder(tmp_path, argv):
    pytest.importorskip("distributed")
    address = f"tcp://127.0.0.1:{_free_port()}"
    p = _ccu(*argv, "--scheduler", address, "--out", tmp_path / "x")
    assert p.returncode == 2
    assert p.stderr == (
        f"ccu: error: cannot connect to the Dask scheduler at '{address}': Connection refused\n"
    )
    assert list(tmp_path.iterdir()) == []


def test_a_scheduler_address_is_checked_before_anything_is_written(tmp_path):
    pytest.importorskip("distributed")
    from compas_ccu.explore import load_sweep, run_sweep
    from compas_ccu.explore.run import reach_scheduler

    not_an_address = "is not a Dask scheduler address"
    with pytest.raises(SweepError, match=rf"^--scheduler 'foo://x:1' {not_an_address}: unknown"):
        reach_scheduler("foo://x:1")
    with pytest.raises(SweepError, match=rf"^--scheduler 'tcp://nohost' {not_an_address}: miss"):
        reach_scheduler("tcp://nohost")
    start = time.monotonic()
    address = f"tcp://127.0.0.1:{_free_port()}"
    with pytest.raises(SweepError, match="Connection refused"):
        reach_scheduler(address)
    assert time.monotonic() - start < 5.0  # not Dask's 20 s of retries

    # a server that accepts the connection but is not a Dask scheduler
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(4)

    server.settimeout(0.2)
    done = threading.Event()

    def answer():  # the probe's connection, then Dask's: garbage to both
        while not done.is_set():
            try:
                conn, _ = server.accept()
            except OSError:  # a timeout: look at done again
                continue
            conn.sendall(b"\xff" * 64)
            conn.close()

    thread = threading.Thread(target=answer, daemon=True)
    thread.start()
    address = f"tcp://127.0.0.1:{server.getsockname()[1]}"
    sweep = load_sweep(EXAMPLES / "sweeps" / "vault.toml")
    try:
        with pytest.raises(
            SweepError,
            match=rf"^cannot connect to the Dask scheduler at '{address}': it does not answer as a "
            "Dask scheduler",
        ):
            run_sweep(sweep, tmp_path / "x", scheduler=address, progress=False)
    finally:
        done.set()
        thread.join(timeout=10)
        server.close()
    assert list(tmp_path.iterdir()) == []
