"""``ccu studio`` as a command: it serves the page on this machine, warns for other hosts and
refuses what it cannot open, naming it."""

from __future__ import annotations

import subprocess
import sys
import threading
import time
import urllib.request

import pytest

from conftest import EXAMPLES
from studio_page import free_port

pytest.importorskip("viser")


def _ccu(*args, **options):
    return subprocess.Popen(
        [sys.executable, "-m", "compas_ccu.cli", "studio", *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        **options,
    )


def _ready(proc, timeout: float = 60.0) -> str:
    """The line ``compas_ccu studio: URL ...`` that ``ccu studio`` prints once it serves."""
    found = []

    def read():
        for line in proc.stdout:
            if line.startswith("compas_ccu studio: http"):
                found.append(line)
                return

    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    reader.join(timeout)
    assert found, f"ccu studio did not start within {timeout} s"
    return found[0]


def _get(url: str, timeout: float = 30.0) -> str:
    end = time.monotonic() + timeout
    while True:
        try:
            with urllib.request.urlopen(url, timeout=2) as r:
                return r.read().decode("utf-8", "replace")
        except OSError:
            if time.monotonic() > end:
                raise
            time.sleep(0.2)


@pytest.mark.slow  # a ccu studio process of its own (1-1.6 s)
def test_ccu_studio_serves_the_page_on_this_machine(tmp_path):
    port = free_port()
    proc = _ccu(str(EXAMPLES / "vault.toml"), "--out", str(tmp_path), "--port", str(port),
                "--no-browser")  # fmt: skip
    try:
        line = _ready(proc)
        page = _get(f"http://127.0.0.1:{port}/")
        assert "<html" in page.lower()
    finally:
        proc.terminate()
        _, err = proc.communicate(timeout=30)
    assert line.startswith(f"compas_ccu studio: http://127.0.0.1:{port}")
    assert "warning" not in err
    assert not any(tmp_path.iterdir())  # nothing written before an edit


@pytest.mark.slow  # a ccu studio process of its own (1-1.6 s)
def test_another_host_prints_a_warning(tmp_path):
    port = free_port()
    proc = _ccu("--out", str(tmp_path), "--port", str(port), "--host", "0.0.0.0", "--no-browser")
    try:
        _ready(proc)
        _get(f"http://127.0.0.1:{port}/")
    finally:
        proc.terminate()
        _, err = proc.communicate(timeout=30)
    assert "ccu: warning: --host 0.0.0.0: the studio is reachable from other machines" in err


@pytest.mark.slow  # a ccu studio process of its own (1-1.6 s)
@pytest.mark.parametrize(
    "args, message",
    [
        (["missing.toml"], "missing.toml: no such design file"),
        (["--port", "0"], "--port must be >= 1, got 0"),
        (["--allow-dir", "no/such/dir"], "--allow-dir no/such/dir: no such folder"),
    ],
)
def test_ccu_studio_refuses_with_one_line(tmp_path, args, message):
    proc = _ccu(*args, "--out", str(tmp_path / "o"), "--no-browser")
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 2, err
    assert message in err and err.count("\n") == 1
