"""The studio's *Target* tab: load a target or a scan, colour the structure by its distance to
it, and fit free design keys to it (:mod:`compas_ccu.studio.target` does the work).

A target named in the design folder is read in viser's callback thread (a 50,000-point file:
well under a second); one uploaded from the user's computer is written into the design folder's
``targets/`` (:mod:`compas_ccu.studio.target_upload`) and read in a background process of its
own (a scan of up to 200 MB takes seconds, which in the studio's process would stall the page);
the distances of every drawn state are measured by the view worker with the rest of the frame; a
fit runs in a background process (:class:`~compas_ccu.studio.export.BackgroundProcess`, like
the exports: :func:`~compas_ccu.fit.fit_design` holds the GIL for seconds), and its result is
offered as one undoable edit.
"""

from __future__ import annotations

import dataclasses
import logging

from compas_ccu.errors import CCUError
from compas_ccu.fit.points import FORMATS
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
from compas_ccu.studio.target_upload import (
    UPLOAD_BYTES,
    UPLOAD_FOLDER,
    discard_upload,
    read_upload,
    save_upload,
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
        self._reader = BackgroundProcess()  # reads uploads (a fit under way does not delay it)
        self._pending = None  # the upload being read; a later Load, Remove or upload wins
        self.file = gui.add_text(
            "target file", "", hint="a mesh (.obj .stl .ply .off .3dm) or points (.xyz .csv "
            ".txt .pts .ply) in the design folder; lengths in m",
        )  # fmt: skip
        gui.add_button_group("target", ("Load", "Remove")).on_click(self._on_target)
        self.upload = gui.add_upload_button(
            "Upload a target ...", mime_type=",".join(FORMATS),
            hint=f"a mesh or points from your computer (at most {UPLOAD_BYTES / 1e6:.0f} MB), "
            f"kept in the design folder's {UPLOAD_FOLDER}/",
        )  # fmt: skip
        self.upload.on_upload(self._on_upload)
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
    def show_target(self, target, *, note: str = "") -> None:
        """Use ``target`` (None: none) and colour the plates by it (``note``: said first)."""
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
                f"{note}{target.name}: {len(target.target):,} points, read in "
                f"{target.seconds * 1000:.0f} ms; the plates are coloured by their distance to "
                "it (colour by: target distance)", "ok", size="0.85em",
            )  # fmt: skip
        studio.redraw()

    def _on_target(self, event) -> None:
        self._pending = None  # an upload still being read is not shown over this
        if event.target.value == "Remove":
            self.show_target(None)
            return
        try:
            target = load_target(self.studio.session.files, self.file.value)
        except CCUError as exc:
            self.info.content = message_html(str(exc), "fail", size="0.85em")
            return
        self.show_target(target)

    def _on_upload(self, event):
        """Write the uploaded file into the design folder and read it (the future of
        :meth:`read_upload`; None: refused, said on the page)."""
        file = event.target.value
        files = self.studio.session.files
        try:
            name = save_upload(files, file.name, file.content)
        except CCUError as exc:
            self.info.content = message_html(str(exc), "fail", size="0.85em")
            return None
        n = len(file.content)
        return self.read_upload(name, f"{n / 1e6:.1f} MB" if n >= 100_000 else f"{n:,} bytes")

    def read_upload(self, name: str, size: str = ""):
        """Read the uploaded target ``name`` (in the design folder) in the reading process;
        it is shown when read, or refused in one line and removed.

        Returns
        -------
        concurrent.futures.Future or None
            Of :func:`~compas_ccu.studio.target_upload.read_upload`'s outcome (None: the
            process cannot be started).
        """
        files = self.studio.session.files
        token = self._pending = object()
        self.info.content = message_html(
            f"uploaded as {name}{f' ({size})' if size else ''}; reading it (background "
            "process) ...", "info", size="0.85em",
        )  # fmt: skip
        try:
            future = self._reader.run(read_upload, files, name)
        except Exception as exc:  # the process cannot be started: said on the page
            log.error("studio target process", exc_info=exc)
            discard_upload(files, name)
            self.info.content = message_html(f"{name!r} was not read: {exc}", "fail",
                                             size="0.85em")  # fmt: skip
            return None
        future.add_done_callback(lambda f: self._uploaded(name, token, f))
        return future

    def _uploaded(self, name: str, token, future) -> None:
        if future.cancelled():  # the studio stops
            return
        try:
            outcome = future.result()
        except Exception as exc:  # a dead process (out of memory?): said on the page
            log.error("studio target read failed", exc_info=exc)
            discard_upload(self.studio.session.files, name)
            outcome = {"error": f"{name!r} was not read and was removed ({type(exc).__name__}: "
                                f"{exc})"}  # fmt: skip
        if token is not self._pending:  # a later Load, Remove or upload
            return
        if "error" in outcome:
            self.info.content = message_html(outcome["error"], "fail", size="0.85em")
        else:
            self.show_target(outcome["target"], note=f"uploaded as {name}; ")
        if self._pending is token:
            self._pending = None

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
        self._reader.stop()
