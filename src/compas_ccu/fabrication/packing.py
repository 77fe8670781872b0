"""Deterministic strip packing: the same shapes, seed and steps give the same placements,
whatever the machine and its load.

:func:`strip_pack` packs true-shape parts into a strip of fixed height with spyrrow (the Python
bindings of sparrow). sparrow's search is a sequence of *steps* (separations: a layout at a
strip width is made free of overlaps, or not; then the strip is narrowed, or the layout is
disrupted), driven by one random generator seeded by ``seed`` (one worker thread). spyrrow
bounds the search by seconds only, so a busy machine searched fewer steps and the result
changed with the load. Here the search is bounded by a count of steps: spyrrow runs in a child
process (``nesting_worker.py``) that counts the steps on spyrrow's progress reports and sends
back the best layout reported up to step ``steps`` (or sooner: ``patience`` failed steps in
all, ``improvements`` improving reports in all when given, or a strip of width ``fit`` or
less); the child is then ended. The clock only guards:
a search that has not reached its stop within ``time_limit`` seconds is refused (a
:class:`~compas_ccu.errors.LimitError` naming the steps reached), never returned.

Measured (spyrrow 0.9.0, the vault's 40 parts in a 1218 mm strip, 540 steps): the same layout
hash at every step alone and with both cores busy with two other processes.
"""

from __future__ import annotations

import json
import math
import queue
import subprocess
import sys
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from compas_ccu.errors import GeometryError, LimitError, require
from compas_ccu.tolerances import EXACT_RELATIVE

__all__ = ["Packing", "strip_pack", "solver_version", "SOLVER", "PATIENCE"]

#: The solver's package.
SOLVER = "spyrrow"
#: Failed steps (in all, not only in a row) that end a search. A failed step means the strip
#: has become tight, and from there on one step costs seconds (measured on a 40-part vault
#: with a 0.9 m rise: 437 steps to the first failure in 18 s, the next 33 steps in 150 s for
#: 0.9 % of strip length), so the search stops at the second failure.
PATIENCE = 2

_WORKER = Path(__file__).with_name("nesting_worker.py")


@dataclass(frozen=True)
class Packing:
    """One strip packing.

    Attributes
    ----------
    placements : dict
        Part name -> ``(rotation, (tx, ty))``: degrees about the shape's origin, then mm.
    width : float
        The strip length the parts use, mm.
    density : float
        The parts' area over the strip's (as spyrrow reports it).
    steps : int
        The steps searched.
    stopped : str
        Why the search stopped: ``"steps"``, ``"patience"``, ``"improvements"`` or ``"fit"``.
    seed : int
        The solver's seed.
    solver, version : str
        The solver package and its version.
    """

    placements: dict
    width: float
    density: float
    steps: int
    stopped: str
    seed: int
    solver: str = SOLVER
    version: str = field(default="")


def solver_version() -> str:
    """The version of spyrrow (the solver the results depend on).

    Raises
    ------
    MissingExtraError
        spyrrow is not installed.
    """
    require(
        "spyrrow",
        "fab",
        what="nesting the parts onto sheets",
        note=" (or [fabrication] nesting = 'shelf', bounding boxes in rows)",
    )
    import spyrrow

    return str(getattr(spyrrow, "__version__", "unknown"))


def _least_height(pts: np.ndarray, orientations) -> float:
    """The least height across the strip ``pts`` can take in its allowed orientations (any
    rotation: the least width of its convex hull, along one of the hull's edges)."""
    if orientations is None:
        from scipy.spatial import ConvexHull

        hull = pts[ConvexHull(pts).vertices]
        edges = np.roll(hull, -1, axis=0) - hull
        normals = np.c_[-edges[:, 1], edges[:, 0]]
        normals /= np.linalg.norm(normals, axis=1)[:, None]
        return float(np.ptp(hull @ normals.T, axis=0).min())
    angles = np.radians(np.asarray(list(orientations) or [0.0], dtype=float))
    # the height after a rotation by a: the spread of x sin a + y cos a
    return float(min(np.ptp(pts[:, 0] * math.sin(a) + pts[:, 1] * math.cos(a)) for a in angles))


def strip_pack(
    shapes: dict,
    orientations: dict,
    *,
    height: float,
    gap: float,
    seed: int = 0,
    steps: int = 500,
    time_limit: float = 600.0,
    fit: float | None = None,
    patience: int = PATIENCE,
    improvements: int | None = None,
) -> Packing:
    """Pack ``shapes`` into a strip ``height`` high, as short as the search finds.

    Parameters
    ----------
    shapes : dict
        Part name -> (m, 2) outline, mm (centred: the rotations are about its origin).
    orientations : dict
        Part name -> the allowed rotations (degrees), or None for any.
    height : float
        The strip's height, mm: every part lies within ``0 <= y <= height``.
    gap : float
        Least distance between two parts, mm (not kept from the strip's edges).
    seed : int
        The solver's random seed: another seed searches other layouts.
    steps : int
        The steps searched (the result of a step never depends on time).
    time_limit : float
        Seconds the search may take before it is refused: a safety limit, not a budget.
    fit : float, optional
        Stop at the first layout at most this long, mm (the question "do they fit?").
    patience : int
        Failed steps (in all) that end the search.
    improvements : int, optional
        Improving reports (in all) that end the search: sparrow reports one each time a
        separation of overlapping parts gets closer to feasible, so a search that needs many
        is in a tight strip where a step costs seconds (the hinge strips on the roll).

    Returns
    -------
    Packing

    Raises
    ------
    GeometryError
        A part is higher than the strip in every allowed orientation (named), or the solver
        failed.
    LimitError
        The search did not stop within ``time_limit`` (the steps reached are named).
    """
    steps, patience, seed = int(steps), int(patience), int(seed)
    if steps < 1 or patience < 1:
        raise ValueError(f"steps and patience must be >= 1, got {steps} and {patience}")
    if improvements is not None and int(improvements) < 1:
        raise ValueError(f"improvements must be >= 1, got {improvements}")
    if not (math.isfinite(time_limit) and time_limit > 0):
        raise ValueError(f"time_limit must be > 0 s, got {time_limit!r}")
    version = solver_version()
    if not shapes:
        return Packing({}, 0.0, 0.0, 0, "steps", seed, SOLVER, version)
    for name in sorted(shapes):
        least = _least_height(np.asarray(shapes[name], dtype=float), orientations[name])
        if least > height + EXACT_RELATIVE:
            raise GeometryError(
                f"part {name} is at least {least:.1f} mm high in its allowed orientations, "
                f"more than the strip of {height:.1f} mm"
            )
    # sparrow keeps the separation from the strip's edges too: widen the strip by it on both
    # sides and move the result back, so the parts may reach the strip's edges
    pad = float(gap) if gap > 0 else 0.0
    problem = {
        "items": [
            {
                "id": name,
                "shape": np.asarray(pts, dtype=float).tolist(),
                "orientations": None
                if orientations[name] is None
                else [float(a) for a in orientations[name]],
            }
            for name, pts in shapes.items()
        ],
        "height": float(height) + 2.0 * pad,
        "gap": float(gap),
        "seed": seed,
        "steps": steps,
        "patience": patience,
        "improvements": None if improvements is None else int(improvements),
        "fit": None if fit is None else float(fit) + 2.0 * pad,
        # the solver's own budget, never reached: the child is ended first
        "total_time": int(math.ceil(time_limit)) * 2 + 60,
    }
    message, reached = _run(problem, time_limit)
    what = f"{len(shapes)} part{'s' if len(shapes) != 1 else ''}"
    if message is None:
        raise LimitError(
            f"the nesting of {what} reached {reached} of {steps} search steps in the time "
            f"limit of {time_limit:g} s; raise [fabrication] nesting_time or lower "
            "nesting_steps"
        )
    if "error" in message:
        raise GeometryError(
            f"the nesting ({SOLVER} {version}) failed on the parts {', '.join(sorted(shapes))} "
            f"in a strip {height:g} mm wide: {message['error']}"
        )
    placements = {
        name: (float(rot), (float(tx) - pad, float(ty) - pad))
        for name, rot, tx, ty in message["placed"]
    }
    return Packing(
        placements=placements,
        width=float(message["width"]) - 2.0 * pad,
        density=float(message["density"]),
        steps=int(message["steps"]),
        stopped=str(message["stopped"]),
        seed=seed,
        solver=SOLVER,
        version=version,
    )


def _run(problem: dict, time_limit: float):
    """The worker's ``done`` / ``error`` message, or (None, steps reached) after
    ``time_limit`` seconds."""
    proc = subprocess.Popen(
        [sys.executable, str(_WORKER)],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
    )
    lines: queue.Queue = queue.Queue()

    def read():
        for line in proc.stdout:
            lines.put(line)
        lines.put(None)

    reader = threading.Thread(target=read, daemon=True)
    reached = 0
    try:
        reader.start()
        proc.stdin.write(json.dumps(problem))
        proc.stdin.close()
        deadline = time.monotonic() + time_limit  # the safety limit: never decides a result
        while True:
            left = deadline - time.monotonic()
            if left <= 0:
                return None, reached
            try:
                line = lines.get(timeout=left)
            except queue.Empty:
                return None, reached
            if line is None:
                return {"error": f"the nesting process ended (exit {proc.wait()})"}, reached
            message = json.loads(line)
            if "done" in message or "error" in message:
                return message, int(message.get("steps", reached))
            reached = int(message.get("steps", reached))
    finally:
        if proc.poll() is None:
            proc.kill()
        proc.wait()
        proc.stdout.close()
