"""The studio's background jobs: draw the view, relax a state, measure the checks.

:class:`StudioJobs` holds what the three worker threads of the studio
(:class:`~compas_ccu.studio.app.Studio`) run (:class:`~compas_ccu.studio.workers.LatestWorker`):
the *view* job redeploys and redraws at the slider angle, the *relax* job computes the relaxed
state of a layout whose creases leave their planes, the *checks* job measures the key figures,
the collision check and the cut patterns of a new model.
"""

from __future__ import annotations

import logging
import time

from compas_ccu.design.schema import design_sheet
from compas_ccu.errors import CCUError
from compas_ccu.studio.checks import design_checks
from compas_ccu.studio.panels import checks_html, patterns_html
from compas_ccu.studio.view import COLORINGS, cut_patterns_svg, legend_html, view_state
from compas_ccu.studio.widgets import set_content
from compas_ccu.thickness import ThickModel
from compas_ccu.tolerances import EXACT_RELATIVE

__all__ = ["StudioJobs", "RELAX_ABOVE", "RELAXED_KEPT", "EXACT", "RELAXING", "RELAXED"]

log = logging.getLogger("compas_ccu.studio.app")  # one log for the app

#: Relative crease planarity above which a state is relaxed.
RELAX_ABOVE = EXACT_RELATIVE
#: Relaxed states kept (per model).
RELAXED_KEPT = 64
EXACT = "exact kinematics"
RELAXING = "relaxing ... (the rigid-ruling model is shown)"
RELAXED = "relaxed model (the creases leave their planes; least-squares relaxation)"


class StudioJobs:
    """The jobs of the studio's workers (a part of :class:`~compas_ccu.studio.app.Studio`)."""

    def _failed(self, exc: BaseException) -> None:
        log.error("studio job failed", exc_info=exc)
        self.message = f"{type(exc).__name__}: {exc}"
        self._status()

    def _thick_model(self, generation, model):
        """The thick plates of ``model`` (or the error that refused them), built once for the
        view and the checks of a generation (whichever asks first)."""
        with self._thick_lock:
            gen, thick = self._thick
            if gen != generation:
                try:
                    thick = ThickModel(model)
                except CCUError as exc:  # the checks panel says why
                    thick = exc
                self._thick = (generation, thick)
        return thick

    def _render(self) -> None:
        t0 = time.perf_counter()
        with self.session.lock:
            model, generation = self.session.model, self.session.generation
        if model is None:
            return
        alpha = min(max(float(self.alpha), 0.0), model.alpha_limit)
        layers = {k: bool(box.value) for k, box in self.layers.items()}
        coloring = self.coloring
        thick = None  # built here only when drawn: else the checks worker builds it
        if layers["solids"] or coloring == "bending utilisation":
            thick = self._thick_model(generation, model)
            thick = None if isinstance(thick, Exception) else thick
        relaxed = self._relaxed.get((generation, round(alpha, 6)))
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
        set_content(self.legend, legend_html(view.legend))
        self.target_panel.show_figures()
        self.last_view = view
        self._status()
        self.server.flush()  # sent now, not at the end of viser's 1/60 s window
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
        """The checks panel of a new model, as soon as its figures are measured; then its cut
        patterns and the recovery copy of the change (neither is on the way to the panel)."""
        try:
            checks = design_checks(model, thick=self._thick_model(generation, model))
            if self.session.generation != generation:
                return
            self.checks = checks
            self._checks_generation = generation
            with self.server.atomic():  # the panel, the marks and the status line in one go
                self._marks(model, checks.collision)
                self.checks_panel.content = checks_html(checks)
                self._status()
            self.server.flush()
            self.checks_shown += 1
            svg, too_large = cut_patterns_svg(model, sheet=design_sheet(model.design.values))
            if self.session.generation == generation:
                self.patterns_panel.content = patterns_html(svg, too_large)
        finally:
            self.session.write_recovery()
