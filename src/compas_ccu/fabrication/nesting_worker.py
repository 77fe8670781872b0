"""The process one strip packing of :func:`compas_ccu.fabrication.packing.strip_pack` runs in.

Run as a script (``python nesting_worker.py``, no ``compas_ccu`` import needed): it reads one
problem as JSON from stdin, runs spyrrow's solver in a thread with a progress queue, counts
the exploration steps (separations: every ``ExplFeas`` and ``ExplInfeas`` report, the first
``ExplFeas`` being the initial solution) and writes JSON lines to stdout: ``{"steps": k}``
while it searches, then one ``{"done": ...}`` with the best feasible solution reported up to
the step where the search stops, or one ``{"error": ...}``. Then it exits at once (the solver
thread is a daemon: the process ending stops it).

The search stops at the first of, counted on the reports alone (never on the clock):

* ``steps`` steps;
* ``patience`` infeasible steps in all (once the strip is tight, each step costs seconds);
* ``improvements`` improving reports in all (``ExplImproving``), when given;
* a feasible strip of width ``fit`` or less, when ``fit`` is given.

The reports arrive in the solver's order, whenever the queue is drained, so what is sent back
depends on the problem, the seed and spyrrow's version only.
"""

import json
import os
import sys
import threading
import time

#: Seconds between two drains of the progress queue (the latency of stopping, not a result).
POLL = 0.01


def _send(message: dict) -> None:
    sys.stdout.write(json.dumps(message) + "\n")
    sys.stdout.flush()


def _solution(report_solution) -> dict:
    return {
        "width": float(report_solution.width),
        "density": float(report_solution.density),
        "placed": [
            [p.id, float(p.rotation), float(p.translation[0]), float(p.translation[1])]
            for p in report_solution.placed_items
        ],
    }


def search(problem: dict) -> dict:
    """Run the search of ``problem`` (the JSON :func:`strip_pack` sends) and return the
    ``done`` message (or an ``error`` one)."""
    import spyrrow as sp

    items = [
        sp.Item(
            it["id"],
            [tuple(p) for p in it["shape"]],
            demand=1,
            allowed_orientations=it["orientations"],
        )
        for it in problem["items"]
    ]
    instance = sp.StripPackingInstance("ccu", strip_height=problem["height"], items=items)
    gap = problem["gap"]
    config = sp.StripPackingConfig(
        early_termination=False,  # the exploration never ends by itself: the steps end it
        total_computation_time=int(problem["total_time"]),
        min_items_separation=gap if gap > 0 else None,
        seed=int(problem["seed"]),
        num_workers=1,
    )
    queue = sp.ProgressQueue()
    failure = []

    def solve():
        try:
            instance.solve(config, progress=queue)
        except BaseException as exc:  # sparrow panics (a PanicException) on a bad instance
            failure.append(f"{type(exc).__name__}: {exc}")

    thread = threading.Thread(target=solve, daemon=True)
    thread.start()
    steps, fails, improved, best, reported = 0, 0, 0, None, -1
    feasible, infeasible = sp.ReportType.ExplFeas, sp.ReportType.ExplInfeas
    improving = sp.ReportType.ExplImproving
    limit, patience, fit = int(problem["steps"]), int(problem["patience"]), problem["fit"]
    budget = problem.get("improvements")
    while True:
        ended = not thread.is_alive()  # drained once more after the thread ended
        for kind, solution in queue.drain():
            if kind == improving:
                improved += 1
                if budget is not None and best is not None and improved >= budget:
                    return {"done": True, "steps": steps, "stopped": "improvements",
                            **_solution(best)}  # fmt: skip
                continue
            if kind not in (feasible, infeasible):
                continue  # compression, final
            steps += 1
            if kind == feasible:
                best = solution
                if fit is not None and solution.width <= fit:
                    return {"done": True, "steps": steps, "stopped": "fit", **_solution(best)}
            else:
                fails += 1
            if best is not None and (steps >= limit or fails >= patience):
                stopped = "steps" if steps >= limit else "patience"
                return {"done": True, "steps": steps, "stopped": stopped, **_solution(best)}
        if failure:
            return {"error": failure[0], "steps": steps}
        if ended:
            return {"error": "the solver ended before the search did", "steps": steps}
        if steps != reported:
            _send({"steps": steps})
            reported = steps
        time.sleep(POLL)


def main() -> None:
    problem = json.loads(sys.stdin.read())
    try:
        message = search(problem)
    except Exception as exc:  # reported to the parent, which raises it as one line
        message = {"error": f"{type(exc).__name__}: {exc}", "steps": 0}
    _send(message)
    os._exit(0)  # at once: the solver thread would run on to its time budget


if __name__ == "__main__":
    main()
