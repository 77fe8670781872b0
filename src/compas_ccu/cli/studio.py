"""``ccu studio``: the live design studio in the browser (the ``studio`` extra)."""

from __future__ import annotations

import sys
import threading
from pathlib import Path

from compas_ccu.cli.common import VIZ, need_extra
from compas_ccu.cli.parser import Command, option
from compas_ccu.design.units import LENGTH_UNITS
from compas_ccu.errors import OptionError
from compas_ccu.studio.app import LOOPBACK, Studio
from compas_ccu.studio.session import StudioSession
from compas_ccu.studio.target import load_target

__all__ = ["COMMANDS", "STUDIO"]

#: Modules of the studio extra.
STUDIO = ("viser", "tomlkit")


def studio(args) -> int:
    need_extra("studio", "studio", STUDIO)
    need_extra("studio", "viz", VIZ)
    if args.port > 65535:
        raise OptionError(f"--port must be <= 65535, got {args.port}")
    if args.host not in LOOPBACK:
        print(
            f"ccu: warning: --host {args.host}: the studio is reachable from other machines; "
            "anyone who can reach it can edit and save designs in the design folder",
            file=sys.stderr,
        )
    for folder in args.allow_dir or ():
        if not Path(folder).expanduser().is_dir():
            raise OptionError(f"--allow-dir {folder}: no such folder")
    session = StudioSession.start(args.design, out=args.out, allowed=args.allow_dir or ())
    target = None
    if args.target is not None:
        target = load_target(session.files, args.target, command_line=True, units=args.units)
    app = Studio(session, host=args.host, port=args.port, target=target)
    print(
        f"compas_ccu studio: {app.url}  (design folder {session.files.design_folder}, "
        f"output folder {session.files.out}; Ctrl-C stops)",
        flush=True,
    )
    if session.notice:
        print(f"ccu: {session.notice}", flush=True)
    if not args.no_browser:
        app.open_browser()
    stop = threading.Event()
    try:
        while not stop.wait(0.5):
            pass
    except KeyboardInterrupt:
        print("compas_ccu studio: stopped", flush=True)
    finally:
        app.stop()
    return 0


COMMANDS = (
    Command(
        "studio",
        "Start the design studio on a local web server and open it in the browser: every "
        "design key as a control, the structure deploying live with a slider, the checks "
        "updated as you edit, undo / redo, save and export (docs/studio.md). Designs are "
        "opened from and saved into the folder of DESIGN (or --out without one); exports and "
        "the recovery copy go into --out.",
        (
            option(
                "design",
                nargs="?",
                default=None,
                help="design TOML file (default: a catalog design)",
            ),
            option("--out", default="out/studio", help="output folder (default out/studio)"),
            option(
                "--port",
                type=int,
                default=8080,
                minimum=1,
                maximum=65535,
                help="port (default 8080; the next free one if busy)",
            ),
            option(
                "--host",
                default="127.0.0.1",
                help="interface to listen on (default 127.0.0.1: this machine only)",
            ),
            option("--no-browser", action="store_true", help="do not open a browser"),
            option(
                "--target",
                default=None,
                metavar="FILE",
                help="a target surface or point cloud (as ccu fit reads them): the plates are "
                "coloured by their distance to it; the Target tab fits free keys to it",
            ),
            option(
                "--units",
                default="m",
                choices=tuple(LENGTH_UNITS),
                help="length units of the --target file's coordinates (default m)",
            ),
            option(
                "--allow-dir",
                action="append",
                metavar="DIR",
                help="a further folder curve files named by a design may be read from "
                "(repeatable; default: the design folder only)",
            ),
        ),
        studio,
    ),
)
