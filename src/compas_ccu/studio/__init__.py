"""The live design studio: edit a design in the browser and see it deploy, checked (``ccu studio``).

:class:`StudioSession` (the design being edited, its history, its last valid model and its files)
is plain Python; :class:`compas_ccu.studio.app.Studio` shows it as a web app built on viser (the
``studio`` extra). ``import compas_ccu`` imports neither.
"""

from __future__ import annotations

from compas_ccu.studio.session import Problem, StudioSession

__all__ = ["StudioSession", "Problem"]
