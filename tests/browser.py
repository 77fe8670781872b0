"""The browser of the page tests: Debian's chromium (``make browser``) driven by playwright."""

from __future__ import annotations

import os
import shutil

import pytest

#: Headless chromium as the tests run it (no GPU: WebGL falls back to software).
CHROMIUM_ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
    "--disable-quic",
]


def chromium() -> str | None:
    """The Chromium executable (``CCU_CHROMIUM`` or ``chromium`` on the PATH), or None; with
    ``CCU_SKIP_BROWSER=1`` the calling test is skipped."""
    if os.environ.get("CCU_SKIP_BROWSER") == "1":
        pytest.skip("CCU_SKIP_BROWSER=1: browser tests skipped")
    return os.environ.get("CCU_CHROMIUM") or shutil.which("chromium")
