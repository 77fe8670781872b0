"""The studio page's widgets: the α slider and its marks, the tabs, the design controls.

:class:`StudioWidgets` builds what the page shows once, when the studio
(:class:`~compas_ccu.studio.app.Studio`) starts: the status line, the α slider, the Deployment
folder (play, colour by, legend), and the tabs Design (one control per design key, by section),
Checks, View (the layer toggles), Cut patterns, File (recovery, undo / redo, save, export) and
Target. :func:`slider_marks` gives the marks of the slider.
"""

from __future__ import annotations

from compas_ccu.catalog import catalog_entries
from compas_ccu.model.self_intersection import measured_collision_free_alpha
from compas_ccu.studio.controls import (
    check_field_text,
    design_controls,
    edited_value,
    options,
    shown_value,
)
from compas_ccu.studio.export import EXPORTS
from compas_ccu.studio.scene import TOGGLES
from compas_ccu.studio.target_panel import TargetPanel
from compas_ccu.studio.view import COLORINGS

__all__ = ["StudioWidgets", "slider_marks", "set_content", "MARK_GAP"]


#: Slider marks closer than this fraction of the range share one label (the more telling one).
MARK_GAP = 0.08
_MARK_RANK = {"collision": 0, "crossing": 1, "overlap": 2, "design": 3, "limit": 4, "0": 5}


def slider_marks(model, collision, top: float, *, path: bool = True) -> list:
    """``[(alpha, label), ...]`` of the α slider: 0, the design α, the overlap angle, the angle
    where two plates first cross (when before the overlap), the thick plates' collision and the
    limit ``top``; of marks closer than :data:`MARK_GAP` of the range only the
    more telling one keeps its label (collision, overlap, design, limit, 0), so none overlap.
    With ``path=False`` the overlap and crossing angles are marked only if they are measured
    already (:func:`~compas_ccu.model.self_intersection.measured_collision_free_alpha`).

    >>> from compas_ccu.model import load_model
    >>> model = load_model("examples/vault.toml")
    >>> slider_marks(model, None, 88.95, path=False)
    [(0.0, '0'), (30.0, 'design'), (88.95, 'limit')]
    >>> slider_marks(model, None, 88.95)
    [(0.0, '0'), (30.0, 'design'), (68.15320448590005, 'overlap'), (88.95, 'limit')]
    """
    marks = [(0.0, "0"), (float(model.alpha_design), "design"), (float(top), "limit")]
    if path or measured_collision_free_alpha(model) is not None:
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


def set_content(html_handle, content: str) -> None:
    """Send HTML to the page only when it changed (every update re-renders the panel)."""
    if html_handle.content != content:
        html_handle.content = content


class StudioWidgets:
    """The widgets of the studio's page, built by :meth:`_build_gui` (a part of
    :class:`~compas_ccu.studio.app.Studio`: the handles are its attributes, their callbacks its
    methods)."""

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
