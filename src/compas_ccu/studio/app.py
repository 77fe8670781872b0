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
"""

from __future__ import annotations

import logging
import threading
import time
import webbrowser

import numpy as np

from compas_ccu.catalog import catalog_entries
from compas_ccu.design.schema import design_sheet
from compas_ccu.errors import CCUError
from compas_ccu.studio.checks import design_checks
from compas_ccu.studio.controls import (
    applies,
    check_field_text,
    design_controls,
    edited_value,
    options,
    parse_value,
    shown_value,
)
from compas_ccu.studio.export import EXPORTS, ExportProcess
from compas_ccu.studio.panels import checks_html, message_html, patterns_html, status_html
from compas_ccu.studio.scene import TOGGLES, StudioScene
from compas_ccu.studio.target_panel import TargetPanel
from compas_ccu.studio.view import COLORINGS, cut_patterns_svg, legend_html, view_state
from compas_ccu.studio.workers import LatestWorker
from compas_ccu.thickness import ThickModel

__all__ = ["Studio", "LOOPBACK", "slider_marks"]

log = logging.getLogger(__name__)

#: The hosts that keep the studio on this machine.
LOOPBACK = ("127.0.0.1", "localhost", "::1")
#: Relative crease planarity above which a state is relaxed.
RELAX_ABOVE = 1e-9
#: Frames per second of "play", and the seconds of one sweep from the flat stack up.
PLAY_FPS = 30
PLAY_SECONDS = 2.5
#: Relaxed states kept (per model).
RELAXED_KEPT = 64
EXACT = "exact kinematics"
RELAXING = "relaxing ... (the rigid-ruling model is shown)"
RELAXED = "relaxed model (the creases leave their planes; least-squares relaxation)"


#: Slider marks closer than this fraction of the range share one label (the more telling one).
MARK_GAP = 0.08
_MARK_RANK = {"collision": 0, "crossing": 1, "overlap": 2, "design": 3, "limit": 4, "0": 5}


def slider_marks(model, collision, top: float) -> list:
    """``[(alpha, label), ...]`` of the α slider: 0, the design α, the overlap angle, the angle
    where two plates first cross (when before the overlap), the thick plates' collision and the
    limit ``top``; of marks closer than :data:`MARK_GAP` of the range only the
    more telling one keeps its label (collision, overlap, design, limit, 0), so none overlap.

    >>> from compas_ccu.model import load_model
    >>> slider_marks(load_model("examples/vault.toml"), None, 88.95)
    [(0.0, '0'), (30.0, 'design'), (68.15320448590005, 'overlap'), (88.95, 'limit')]
    """
    marks = [(0.0, "0"), (float(model.alpha_design), "design"), (float(top), "limit")]
    if model.overlap_alpha < model.alpha_limit:
        marks.append((float(model.overlap_alpha), "overlap"))
    if model.collision_free_alpha < model.overlap_alpha:  # two plates cross first
        marks.append((float(model.collision_free_alpha), "crossing"))
    if collision is not None:
        marks.append((float(collision["alpha"]), "collision"))
    labelled = []
    for value, label in sorted(marks, key=lambda m: _MARK_RANK[m[1]]):
        if all(abs(value - v) >= MARK_GAP * top for v, _ in labelled):
            labelled.append((value, label))
    shown = set(labelled)
    return [(v, t if (v, t) in shown else "") for v, t in sorted(marks)]


def _set(html_handle, content: str) -> None:
    """Send HTML to the page only when it changed (every update re-renders the panel)."""
    if html_handle.content != content:
        html_handle.content = content


class Studio:
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
        self._relaxed = {}  # (generation, alpha) -> vertices
        self._playing = threading.Event()
        self._stopped = False
        self._build_gui()
        self._view = LatestWorker(self._render, name="studio-view", on_error=self._failed)
        self._checker = LatestWorker(self._measure, name="studio-checks", on_error=self._failed)
        self._relaxer = LatestWorker(self._relax, name="studio-relax", on_error=self._failed)
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
    def _build_gui(self) -> None:
        gui = self.server.gui
        self.status = gui.add_html("")
        self.slider = gui.add_slider("α [deg]", min=0.0, max=89.0, step=0.05, initial_value=30.0)
        self.slider.on_update(self._on_slider)
        with gui.add_folder("Deployment"):
            self.play = gui.add_checkbox("play", False, hint="deploy to the limit and back")
            self.play.on_update(self._on_play)
            self.coloring_menu = gui.add_dropdown("colour by", COLORINGS)
            self.coloring_menu.on_update(self._on_coloring)
            self.legend = gui.add_html("")
        tabs = gui.add_tab_group()
        with tabs.add_tab("Design"):
            self._build_design_tab(gui)
        with tabs.add_tab("Checks"):
            self.checks_panel = gui.add_html("<i>measuring ...</i>")
            target_checks = gui.add_html("")
        with tabs.add_tab("View"):
            self.layers = {}
            for key, label, default in TOGGLES:
                self.layers[key] = gui.add_checkbox(label, default)
                self.layers[key].on_update(lambda _: self._view.submit())
        with tabs.add_tab("Cut patterns"):
            self.patterns_panel = gui.add_html("")
        with tabs.add_tab("File"):
            self._build_file_tab(gui)
        with tabs.add_tab("Target"):
            self.target_panel = TargetPanel(self, gui, checks=target_checks)

    def _build_design_tab(self, gui) -> None:
        self.open_menu = gui.add_dropdown("open", self._open_options())
        gui.add_button("Open").on_click(self._on_open)
        upload = gui.add_upload_button("Open a TOML file ...", mime_type=".toml")
        upload.on_upload(self._on_upload)
        self.design_error = gui.add_html("")
        self.controls = {}
        sections = {}
        for control in design_controls():
            sections.setdefault(control.section, []).append(control)
        for section, controls in sections.items():
            with gui.add_folder(f"[{section}]", expand_by_default=section in ("crease", "layout")):
                for control in controls:
                    self.controls[control.key] = self._add_control(gui, control)

    def _open_options(self) -> tuple:
        """The designs the Open menu offers: the design folder's files, then the catalog."""
        files = [f"file: {n}" for n in self.session.files.designs()]
        return tuple(files + [f"catalog: {e.name}" for e in catalog_entries()])

    def _add_control(self, gui, control):
        shown = shown_value(control, self.session.value(control.section, control.name))
        if control.widget == "dropdown":
            handle = gui.add_dropdown(
                control.label, options(control), initial_value=shown, hint=control.hint
            )
        elif control.widget == "checkbox":
            handle = gui.add_checkbox(control.label, shown, hint=control.hint)
        else:
            handle = gui.add_text(control.label, shown, hint=control.hint)
        error = gui.add_html("", visible=False)

        def on_update(event) -> None:
            if event.client is None:  # set from Python: a refresh of the panel
                return

            def edit():
                check_field_text(control, handle.value)
                value = edited_value(control, handle.value)
                self.session.edit(control.section, control.name, value)

            self.apply_action(edit, panel="design")

        handle.on_update(on_update)
        return control, handle, error

    def _build_file_tab(self, gui) -> None:
        self.recovery_choice = gui.add_button_group(
            "recovery copy", ("Restore it", "Keep the file"), visible=False,
            hint="a recovery copy older than the file (it changed since): restore it or keep "
            "the file",
        )  # fmt: skip
        self.recovery_choice.on_click(self._on_recovery)
        gui.add_button_group("history", ("Undo", "Redo")).on_click(self._on_history)
        gui.add_button("Save").on_click(lambda _: self._save(self.session.save))
        self.save_name = gui.add_text("save as", self.session.name, hint="a name in the folder")
        gui.add_button("Save as").on_click(
            lambda _: self._save(lambda: self.session.save_as(self.save_name.value))
        )
        self.export_what = {w: gui.add_checkbox(f"export {w}", w != "report") for w in EXPORTS}
        gui.add_button("Export").on_click(self._on_export)
        self.file_panel = gui.add_html("")

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
            self._model_changed()
        else:
            self._status()
        return True

    def _on_slider(self, event) -> None:
        if event.client is None:
            return
        self.alpha = float(self.slider.value)
        self._view.submit()

    def _on_play(self, _) -> None:
        if self.play.value and not self._playing.is_set():
            self._playing.set()
            threading.Thread(target=self._play, name="studio-play", daemon=True).start()
        elif not self.play.value:
            self._playing.clear()

    def _play(self) -> None:
        direction = 1.0
        while self._playing.is_set() and self.session.model is not None:
            model = self.session.model
            top = min(model.alpha_limit, model.collision_free_alpha) * 0.999
            alpha = (self.alpha or 0.0) + direction * top / (PLAY_SECONDS * PLAY_FPS)
            if not 0.0 < alpha < top:
                direction = -direction
                alpha = min(max(alpha, 0.0), top)
            self.alpha = alpha
            self.slider.value = round(alpha, 2)
            self._view.submit()
            time.sleep(1.0 / PLAY_FPS)

    def _on_coloring(self, _) -> None:
        self.coloring = self.coloring_menu.value
        self._view.submit()

    def _on_open(self, _) -> None:
        kind, _, name = self.open_menu.value.partition(": ")
        opener = self.session.open_file if kind == "file" else self.session.open_catalog
        if self.apply_action(lambda: opener(name), panel="design"):
            self._reset_view()

    def _on_upload(self, event) -> None:
        file = event.target.value
        if self.apply_action(
            lambda: self.session.open_upload(file.name, file.content), panel="design"
        ):
            self._reset_view()

    def _reset_view(self) -> None:
        model = self.session.model
        if model is None:
            return
        self.alpha = model.alpha_design
        self.slider.value = round(self.alpha, 2)
        self._aim(self.server.initial_camera, model)
        for client in self.server.get_clients().values():
            self._aim(client.camera, model)
        self._view.submit()

    def _on_history(self, event) -> None:
        which = event.target.value
        done = []
        self.apply_action(
            lambda: done.append(self.session.undo() if which == "Undo" else self.session.redo())
        )
        if done and not done[0]:
            self._say(f"nothing to {which.lower()}", "info")

    def _on_recovery(self, event) -> None:
        s = self.session
        action = s.restore_recovery if event.target.value == "Restore it" else s.discard_recovery
        if self.apply_action(action):
            self._say(s.notice, "ok")
            self._reset_view()

    def _save(self, action) -> None:
        try:
            path = action()
        except (CCUError, OSError) as exc:
            self._say(f"not saved: {exc}", "fail")
            return
        problem = self.session.problem
        text = f"saved {path}" + (
            f" (the design has an error: {problem.message})" if problem else ""
        )
        self._say(text, "warn" if problem else "ok")
        self.save_name.value = self.session.name
        self.open_menu.options = self._open_options()
        self._status()

    def _on_export(self, _) -> None:
        s = self.session
        if s.problem is not None:
            self._say(f"fix the design before exporting: {s.problem.message}", "fail")
            return
        with s.lock:
            model, alpha, text = s.model, self.alpha, s.text()
        what = [w for w, box in self.export_what.items() if box.value]
        self._say(f"exporting {', '.join(what)} ...", "info")
        self.last_export = None
        try:
            future = self._exporter.submit(model, s.files.out, alpha=alpha, what=what,
                                           design_text=text)  # fmt: skip
        except Exception as exc:  # the process cannot be started: said on the page
            log.error("studio export process", exc_info=exc)
            self._say(f"export failed: {exc}", "fail")
            return None
        future.add_done_callback(self._exported)
        return future

    def _exported(self, future) -> None:
        if future.cancelled():
            return
        try:
            pid, written = future.result()
        except Exception as exc:  # shown on the page; the server carries on
            log.error("studio export failed", exc_info=exc)
            self._say(f"export failed: {exc}", "fail")
            return
        self.last_export = (pid, written)
        self._say("exported " + ", ".join(f"{k} to {v}" for k, v in written.items()), "ok")

    def _failed(self, exc: BaseException) -> None:
        log.error("studio job failed", exc_info=exc)
        self.message = f"{type(exc).__name__}: {exc}"
        self._status()

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
            self._status()
            return
        if reset_alpha or self.alpha is None:
            self.alpha = model.alpha_design
            self._aim(self.server.initial_camera, model)
        self.slider.max = float(np.floor(model.alpha_limit * 100) / 100)
        self.alpha = min(self.alpha, self.slider.max)
        self.slider.value = round(self.alpha, 2)
        self._marks(model, None)
        self.checks_panel.content = "<i>measuring ...</i>"
        self.patterns_panel.content = "<i>drawing ...</i>"
        self._view.submit()
        self._checker.submit(self.session.generation, model)
        self._status()

    def _marks(self, model, collision) -> None:
        """The slider's marks: design, overlap and collision angles, the limit."""
        from viser._messages import GuiSliderMark

        self.slider._marks = tuple(
            GuiSliderMark(v, t) for v, t in slider_marks(model, collision, self.slider.max)
        )

    def _status(self) -> None:
        s = self.session
        current = self.checks is not None and self._checks_generation == s.generation
        _set(
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
    def _thick_model(self, generation, model):
        gen, thick = self._thick
        if gen != generation:
            try:
                thick = ThickModel(model)
            except CCUError as exc:  # the checks panel says why
                thick = exc
            self._thick = (generation, thick)
        return None if isinstance(thick, Exception) else thick

    def _render(self) -> None:
        t0 = time.perf_counter()
        with self.session.lock:
            model, generation = self.session.model, self.session.generation
        if model is None:
            return
        alpha = min(max(float(self.alpha), 0.0), model.alpha_limit)
        layers = {k: bool(box.value) for k, box in self.layers.items()}
        thick = self._thick_model(generation, model)
        relaxed = self._relaxed.get((generation, round(alpha, 6)))
        coloring = self.coloring
        view = view_state(
            model, alpha, coloring=coloring if coloring in COLORINGS else COLORINGS[0],
            vertices=relaxed, thick=thick, solids=layers["solids"],
        )  # fmt: skip
        self.target_panel.colour(view, coloring)
        if relaxed is not None:
            self.state = RELAXED
        elif model.geometry.planes is not None and self._leaves_planes(model, alpha):
            self.state = RELAXING
            self._relaxer.submit(generation, model, alpha)
        else:
            self.state = EXACT
        with self.server.atomic():
            self.scene.draw(view, model, generation, layers)
        _set(self.legend, legend_html(view.legend))
        self.target_panel.show_figures()
        self.last_view = view
        self._status()
        self.render_seconds += time.perf_counter() - t0
        self.frames += 1

    @staticmethod
    def _leaves_planes(model, alpha: float) -> bool:
        planarity = model.crease_planarity([alpha])
        return bool(planarity.size) and float(planarity.max()) > RELAX_ABOVE * model.size

    def _relax(self, generation, model, alpha) -> None:
        key = (generation, round(alpha, 6))
        if key in self._relaxed:
            return
        structure, _ = model.relax(alpha)
        kept = {k: v for k, v in self._relaxed.items() if k[0] == generation}
        if len(kept) >= RELAXED_KEPT:
            kept.clear()
        kept[key] = structure.deployed
        self._relaxed = kept
        if self.session.generation == generation and round(self.alpha or 0.0, 6) == key[1]:
            self._view.submit()

    def _measure(self, generation, model) -> None:
        checks = design_checks(model)
        svg, too_large = cut_patterns_svg(model, sheet=design_sheet(model.design.values))
        if self.session.generation != generation:
            return
        self.checks = checks
        self._checks_generation = generation
        self._marks(model, checks.collision)
        self.checks_panel.content = checks_html(checks)
        self.patterns_panel.content = patterns_html(svg, too_large)
        self._status()
