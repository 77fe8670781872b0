"""What the studio page's widgets do: the α slider, play, colour by, open, undo, save, export.

:class:`StudioEvents` holds the callbacks of the widgets
(:class:`~compas_ccu.studio.widgets.StudioWidgets`; a part of
:class:`~compas_ccu.studio.app.Studio`). They run in viser's callback threads; an edit of the
session goes through :meth:`~compas_ccu.studio.app.Studio.apply_action` (under the session's
lock), a new angle or colouring asks the view worker for a frame, and an export runs in its own
process.
"""

from __future__ import annotations

import logging
import threading
import time

from compas_ccu.errors import CCUError
from compas_ccu.studio.export import export_warnings

__all__ = ["StudioEvents", "PLAY_FPS", "PLAY_SECONDS"]

log = logging.getLogger("compas_ccu.studio.app")  # one log for the app

#: Frames per second of "play", and the seconds of one sweep from the flat stack up.
PLAY_FPS = 30
PLAY_SECONDS = 2.5


class StudioEvents:
    """The callbacks of the studio's widgets (a part of :class:`~compas_ccu.studio.app.Studio`)."""

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
        text = "exported " + ", ".join(f"{k} to {v}" for k, v in written.items())
        notes = export_warnings(written)  # e.g. no nester installed: shelves nested the parts
        self._say("; ".join([text, *(f"warning: {n}" for n in notes)]), "warn" if notes else "ok")
