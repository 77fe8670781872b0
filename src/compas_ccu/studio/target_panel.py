"""The studio's *Target* tab: load a target or a scan, colour the structure by its distance to
it, and fit free design keys to it (:mod:`compas_ccu.studio.target` does the work).

The target is read in viser's callback thread (a 50,000-point file: well under a second); the
distances of every drawn state are measured by the view worker with the rest of the frame; a
fit runs in a background process (:class:`~compas_ccu.studio.export.BackgroundProcess`, like
the exports: :func:`~compas_ccu.fit.fit_design` holds the GIL for seconds), and its result is
offered as one undoable edit.
"""

from __future__ import annotations

import dataclasses
import logging

from compas_ccu.errors import CCUError
from compas_ccu.limits import LIMITS
from compas_ccu.studio.export import BackgroundProcess
from compas_ccu.studio.panels import message_html
from compas_ccu.studio.target import (
    TARGET_COLORING,
    USUAL_KEYS,
    apply_fit,
    colour_view,
    fit_html,
    fit_job,
    fit_request,
    load_target,
    suggested_free,
    target_html,
    target_state,
)
from compas_ccu.studio.view import COLORINGS

__all__ = ["TargetPanel"]

log = logging.getLogger(__name__)


class TargetPanel:
    """The Target tab of a :class:`~compas_ccu.studio.app.Studio` (built inside the tab).

    Parameters
    ----------
    studio : Studio
    gui : viser.GuiApi
    checks : viser.GuiHtmlHandle, optional
        The target's section of the checks panel (in the Checks tab).
    """

    def __init__(self, studio, gui, *, checks=None):
        self.studio = studio
        self.target = None
        self.state = None  # TargetState of the state drawn last
        self.request = None  # the FitRequest under way or offered
        self.outcome = None  # its result
        self.future = None
        self._process = BackgroundProcess()
        self.file = gui.add_text(
            "target file", "", hint="a mesh (.obj .stl .ply .off .3dm) or points (.xyz .csv "
            ".txt .pts .ply) in the design folder; lengths in m",
        )  # fmt: skip
        gui.add_button_group("target", ("Load", "Remove")).on_click(self._on_target)
        self.info = gui.add_html("")
        model = studio.session.model
        self.free = gui.add_text(
            "free keys", suggested_free(model) if model is not None else "",
            hint="KEY=LOWER:UPPER, ... as ccu fit --free: any real design key, e.g. "
            + ", ".join(USUAL_KEYS),
        )  # fmt: skip
        gui.add_button_group("fit", ("Fit", "Suggest bounds")).on_click(self._on_fit)
        self.apply_button = gui.add_button("Apply the fitted design", visible=False)
        self.apply_button.on_click(self._on_apply)
        self.result = gui.add_html("")
        self.checks = checks

    # -- the target ----------------------------------------------------------------------------
    def show_target(self, target) -> None:
        """Use ``target`` (None: none) and colour the plates by it."""
        self.target, self.state = target, None
        studio = self.studio
        menu = studio.coloring_menu
        if target is None:
            menu.options = COLORINGS
            if studio.coloring == TARGET_COLORING:
                studio.coloring = menu.value = COLORINGS[0]
            self.info.content = ""
            if self.checks is not None:
                self.checks.content = ""
        else:
            self.file.value = target.name
            menu.options = (*COLORINGS, TARGET_COLORING)
            studio.coloring = menu.value = TARGET_COLORING
            self.info.content = message_html(
                f"{target.name}: {len(target.target):,} points, read in "
                f"{target.seconds * 1000:.0f} ms; the plates are coloured by their distance to "
                "it (colour by: target distance)", "ok", size="0.85em",
            )  # fmt: skip
        studio.redraw()

    def _on_target(self, event) -> None:
        if event.target.value == "Remove":
            self.show_target(None)
            return
        try:
            target = load_target(self.studio.session.files, self.file.value)
        except CCUError as exc:
            self.info.content = message_html(str(exc), "fail", size="0.85em")
            return
        self.show_target(target)

    def colour(self, view, coloring: str) -> None:
        """Measure the drawn ``view`` against the target; colour its plates by the distance
        when ``coloring`` is the target colouring (called by the view worker every frame)."""
        target = self.target
        if target is None:
            self.state = None
            return
        self.state = target_state(target, view.vertices, view.plate_ids, view.alpha)
        if coloring == TARGET_COLORING:
            colour_view(view, self.state, target.name)

    def show_figures(self) -> None:
        """The checks panel's target section, of the state drawn last."""
        if self.checks is None:
            return
        content = "" if self.target is None else target_html(self.target, self.state)
        if self.checks.content != content:
            self.checks.content = content

    # -- the fit -------------------------------------------------------------------------------
    def _on_fit(self, event) -> None:
        session = self.studio.session
        if event.target.value == "Suggest bounds":
            if session.model is not None:
                self.free.value = suggested_free(session.model)
            return
        if self.future is not None and not self.future.done():
            self._say("a fit is under way", "info")
            return
        try:
            request = fit_request(session, self.target, self.free.value)
        except CCUError as exc:
            self._say(str(exc), "fail")
            return
        self.submit(request)

    def submit(self, request):
        """Run the fit of ``request`` in the background process; its result is offered."""
        self.request, self.outcome = request, None
        self.apply_button.visible = False
        n = len(request.target.target)
        self._say(f"fitting {request.free} to {n:,} target points (background process) ...",
                  "info")  # fmt: skip
        try:
            self.future = self._process.run(fit_job, **request.job(dataclasses.asdict(LIMITS)))
        except Exception as exc:  # the process cannot be started: said on the page
            log.error("studio fit process", exc_info=exc)
            self._say(f"the fit failed: {exc}", "fail")
            return None
        self.future.add_done_callback(lambda f: self._fitted(request, f))
        return self.future

    def _fitted(self, request, future) -> None:
        if future.cancelled() or request is not self.request:
            return
        try:
            outcome = future.result()
        except Exception as exc:  # a bug or a dead process: said on the page
            log.error("studio fit failed", exc_info=exc)
            outcome = {"error": f"{type(exc).__name__}: {exc}"}
        self.outcome = outcome
        self.result.content = fit_html(outcome)
        self.apply_button.visible = "error" not in outcome

    def _on_apply(self, _) -> None:
        request, outcome = self.request, self.outcome
        if request is None or outcome is None:
            return
        session, written = self.studio.session, []

        def refused(text: str) -> None:
            self.result.content = fit_html(outcome) + message_html(text, "fail", size="0.85em")

        def apply() -> None:
            written.append(apply_fit(session, request, outcome, out=session.files.out))

        if self.studio.apply_action(apply, panel=refused):
            self.apply_button.visible = False
            self.result.content = fit_html(outcome) + message_html(
                f"applied: one edit (Undo in the File tab goes back); fit.json: {written[0]}",
                "ok", size="0.85em",
            )  # fmt: skip

    def _say(self, text: str, status: str) -> None:
        self.result.content = message_html(text, status, size="0.85em")

    def stop(self) -> None:
        self._process.stop()
