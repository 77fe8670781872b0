"""The studio's web app (viser): the design panel, the 3D view, the checks and the files.

The page is viser's three.js client, served from the viser wheel (no internet needed); the
scene and the controls live here in Python and reach every open tab over a websocket. All tabs
of one server share one session and one set of controls, so they always show the same design.

Three worker threads keep the page live (:class:`~compas_ccu.studio.workers.LatestWorker`): the
*view* worker redeploys and redraws at the slider angle (the latest angle wins, so a drag never
queues up), the *checks* worker measures the key figures and the collision check of a new model,
and the *relax* worker computes the relaxed state of a layout whose creases leave their planes
(the page says "relaxing" until it is drawn). Edits run in viser's callback threads under the
session's lock. An export runs in a separate process (:class:`~compas_ccu.studio.export.
ExportProcess`), so the nesting and the report's pictures never stall the page.

:class:`Studio` is put together from its parts: the server, its lifecycle and bringing the page
up to date with the session are here; the widgets are :mod:`compas_ccu.studio.widgets`, what
they do :mod:`compas_ccu.studio.events`, and the workers' jobs :mod:`compas_ccu.studio.jobs`.
"""

from __future__ import annotations

import threading
import time
import webbrowser

import numpy as np

from compas_ccu.errors import CCUError
from compas_ccu.studio.controls import applies, parse_value, shown_value
from compas_ccu.studio.events import PLAY_FPS, PLAY_SECONDS, StudioEvents
from compas_ccu.studio.export import ExportProcess
from compas_ccu.studio.jobs import (
    EXACT,
    RELAX_ABOVE,
    RELAXED,
    RELAXED_KEPT,
    RELAXING,
    StudioJobs,
)
from compas_ccu.studio.panels import message_html, status_html
from compas_ccu.studio.scene import StudioScene
from compas_ccu.studio.view import COLORINGS
from compas_ccu.studio.widgets import MARK_GAP, StudioWidgets, set_content, slider_marks
from compas_ccu.studio.workers import LatestWorker

__all__ = [
    "Studio",
    "LOOPBACK",
    "slider_marks",
    # the constants of the parts, importable from here too
    "MARK_GAP",
    "PLAY_FPS",
    "PLAY_SECONDS",
    "RELAX_ABOVE",
    "RELAXED_KEPT",
    "EXACT",
    "RELAXING",
    "RELAXED",
]

#: The hosts that keep the studio on this machine.
LOOPBACK = ("127.0.0.1", "localhost", "::1")


class Studio(StudioWidgets, StudioEvents, StudioJobs):
    """The studio of one :class:`~compas_ccu.studio.session.StudioSession`.

    Parameters
    ----------
    session : StudioSession
    host : str
        Interface to listen on (default: this machine only).
    port : int
        Port (the next free one is taken if it is busy).
    target : StudioTarget, optional
        A target or scan to colour the structure by (``ccu studio --target``; the Target tab
        loads one from the design folder).

    Examples
    --------
    In a notebook::

        studio = Studio(StudioSession.start("examples/vault.toml", out="out/studio"))
        studio.show()   # the live studio inline
    """

    def __init__(self, session, *, host: str = "127.0.0.1", port: int = 8080, target=None):
        import viser

        self.session = session
        self.server = viser.ViserServer(host=host, port=port, label="compas_ccu studio")
        self.server.gui.configure_theme(control_width="large", dark_mode=False, show_logo=False)
        self.server.scene.set_up_direction("+z")
        # no shadow maps: a frame costs a third (software WebGL on machines without a GPU)
        self.server.scene.configure_default_lights(enabled=True, cast_shadow=False)
        self.server.scene.configure_environment_map(hdri=None)
        self.server.scene.add_light_hemisphere(
            "/light/sky", sky_color=(255, 255, 255), ground_color=(150, 150, 150), intensity=2.2
        )
        self.scene = StudioScene(self.server.scene)
        self.coloring = COLORINGS[0]
        self.alpha = None
        self.state = "starting"
        self.message = ""
        self.checks = None
        self.frames = 0
        self.render_seconds = 0.0  # Python time of all frames (benchmarks)
        self.last_view = None
        self.last_export = None  # (pid, written) of the last export
        self._exporter = ExportProcess()
        self._checks_generation = -1
        self._thick = (None, None)  # (generation, ThickModel or the error)
        self._thick_lock = threading.Lock()
        self.checks_shown = 0  # checks panels shown (tests, benchmarks)
        self._relaxed = {}  # (generation, alpha) -> vertices
        self._playing = threading.Event()
        self._stopped = False
        self._build_gui()
        self._view = LatestWorker(self._render, name="studio-view", on_error=self._failed)
        self._checker = LatestWorker(self._measure, name="studio-checks", on_error=self._failed)
        self._relaxer = LatestWorker(self._relax, name="studio-relax", on_error=self._failed)
        # the recovery copy of a change is written when its checks panel is shown (the checks
        # worker; at once for a change without a new model)
        session.defer_recovery = True
        self.server.on_client_connect(self._on_connect)
        self._sync_panel()
        self._model_changed(reset_alpha=True)
        if target is not None:
            self.target_panel.show_target(target)

    # -- lifecycle -----------------------------------------------------------------------------
    @property
    def url(self) -> str:
        """The page's address."""
        host = self.server.get_host()
        host = "127.0.0.1" if host in ("0.0.0.0", "::", "") else host
        return f"http://{host}:{self.server.get_port()}"

    def open_browser(self) -> None:
        webbrowser.open(self.url)

    def show(self, height: int = 700):
        """The live studio inline in a Jupyter notebook (an IFrame of the running server)."""
        from IPython.display import IFrame

        return IFrame(self.url, width="100%", height=height)

    def wait_idle(self, timeout: float = 30.0) -> bool:
        """Wait until the view, the checks and the relaxation are drawn (tests, benchmarks)."""
        end = time.monotonic() + timeout
        for worker in (self._view, self._checker, self._relaxer, self._view):
            if not worker.wait_idle(max(0.0, end - time.monotonic())):
                return False
        return True

    def stop(self) -> None:
        """Stop the workers and the server (a second call does nothing)."""
        if self._stopped:
            return
        self._stopped = True
        self._playing.clear()
        for worker in (self._view, self._checker, self._relaxer):
            worker.stop()
        self.session.write_recovery()  # a change whose checks were not measured yet
        self.session.defer_recovery = False  # the session on its own writes every change
        self._exporter.stop()
        self.target_panel.stop()
        self.server.stop()

    def _on_connect(self, client) -> None:
        model = self.session.model
        if model is not None:
            self._aim(client.camera, model)

    @staticmethod
    def _aim(camera, model) -> None:
        """Look at the design state from the front, above and to the side."""
        v = model.vertices([model.alpha_design])[0].reshape(-1, 3)
        lo, hi = v.min(axis=0), v.max(axis=0)
        centre = 0.5 * (lo + hi)
        size = float(np.linalg.norm(hi - lo))
        camera.position = tuple(centre + size * np.array([0.6, -0.9, 0.5]))
        camera.look_at = tuple(centre)

    # -- the page ------------------------------------------------------------------------------
    # -- callbacks (from the page) -------------------------------------------------------------
    def redraw(self) -> None:
        """Draw the current state again (the view worker)."""
        if not self._stopped:
            self._view.submit()

    def apply_action(self, action, *, panel="file") -> bool:
        """Run a session action, then bring the page up to date; a refused action is said in
        ``panel`` ("file", "design" or a function of the message) and changes nothing."""
        try:
            with self.session.lock:
                before = self.session.generation
                action()
                changed = self.session.generation != before
        except CCUError as exc:
            if callable(panel):
                panel(str(exc))
            elif panel == "design":
                self.design_error.content = message_html(str(exc), "fail", size="0.9em")
            else:
                self._say(str(exc), "fail")
            return False
        self._sync_panel()
        if changed:
            self._model_changed()  # the checks worker writes the recovery copy
        else:
            self.session.write_recovery()
            self._status()
        return True

    # -- bringing the page up to date ----------------------------------------------------------
    def _say(self, text: str, status: str) -> None:
        self.file_panel.content = message_html(text, status, size="0.9em")

    def _sync_panel(self) -> None:
        """Values, visibility and inline errors of every control, from the session."""
        s = self.session
        with s.lock:
            document, problem, name, saved = s.document, s.problem, s.name, s.saved
            pending, offered = s.pending, s.recovery is not None
            values = {k: s.value(c.section, c.name) for k, (c, _, _) in self.controls.items()}
        for key, (control, handle, error) in self.controls.items():
            value = values[key]
            shown = shown_value(control, value)
            if control.widget == "text" and parse_value(control, handle.value) == value:
                shown = handle.value  # keep the text being typed if it means the same value
            if handle.value != shown:
                handle.value = shown
            visible = applies(control, document)
            if handle.visible != visible:
                handle.visible = visible
            mine = problem is not None and problem.key == key
            if mine:
                error.content = message_html(problem.message, "fail")
            if error.visible != mine:
                error.visible = mine
        if problem is None:
            self.design_error.content = ""
        else:
            own = problem.key not in self.controls
            text = (problem.message + " — " if own else "") + "the last valid model is shown"
            if pending:
                text += " (not applied: " + ", ".join(pending) + ")"
            self.design_error.content = message_html(text, "fail", size="0.9em")
        if saved and self.save_name.value != name:
            self.save_name.value = name
        if self.recovery_choice.visible != offered:
            self.recovery_choice.visible = offered

    def _model_changed(self, *, reset_alpha: bool = False) -> None:
        model = self.session.model
        if model is None:
            self.session.write_recovery()
            self._status()
            return
        if reset_alpha or self.alpha is None:
            self.alpha = model.alpha_design
            self._aim(self.server.initial_camera, model)
        self.slider.max = float(np.floor(model.alpha_limit * 100) / 100)
        self.alpha = min(self.alpha, self.slider.max)
        self.slider.value = round(self.alpha, 2)
        # the path limits are the checks worker's (it sets every mark with the panel): the view
        # worker starts at once, not after the path scan
        self._marks(model, None, path=False)
        self.checks_panel.content = "<i>measuring ...</i>"
        self.patterns_panel.content = "<i>drawing ...</i>"
        self._view.submit()
        self._checker.submit(self.session.generation, model)
        self._status()

    def _marks(self, model, collision, *, path: bool = True) -> None:
        """The slider's marks: design, overlap and collision angles, the limit (``path=False``:
        the overlap and crossing angles only if they are measured already)."""
        from viser._messages import GuiSliderMark

        marks = slider_marks(model, collision, self.slider.max, path=path)
        self.slider._marks = tuple(GuiSliderMark(v, t) for v, t in marks)

    def _status(self) -> None:
        s = self.session
        current = self.checks is not None and self._checks_generation == s.generation
        set_content(
            self.status,
            status_html(
                s,
                self.last_view,
                state=self.state,
                message=self.message,
                failed=self.checks.failed if current else (),
            ),
        )

    # -- workers -------------------------------------------------------------------------------
