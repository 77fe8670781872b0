# r: compas_ccu
"""CCU Design: a curved-crease design from a TOML file, or from a planar curve as the crease."""

import Grasshopper
import Rhino

from compas_ccu.errors import CCUError
from compas_ccu.ghpython import design_component, document_unit_scale


class CCUDesign(Grasshopper.Kernel.GH_ScriptInstance):
    def RunScript(
        self,
        path: str,
        crease: Rhino.Geometry.Curve,
        segments: int,
        width: float,
        plates: int,
        spacing: float,
        alpha: float,
    ):
        options = {"unit_scale": document_unit_scale()}
        for key, value in (("segments", segments), ("width", width), ("plates", plates),
                           ("spacing", spacing), ("alpha", alpha)):  # fmt: skip
            if value is not None:
                options[key] = value
        try:
            result = design_component(path=path, crease=crease, **options)
        except CCUError as exc:
            ghenv.Component.AddRuntimeMessage(  # noqa: F821
                Grasshopper.Kernel.GH_RuntimeMessageLevel.Error, str(exc)
            )
            return None, None, str(exc)
        return result.design, result.model, result.info
