# r: compas_ccu
"""CCU Cut patterns: every plate's cut pattern as curves on the XY plane, by layer."""

import Grasshopper

from compas_ccu.errors import CCUError
from compas_ccu.ghpython import cut_patterns_component, document_unit_scale


class CCUCutPatterns(Grasshopper.Kernel.GH_ScriptInstance):
    def RunScript(self, model, thickness: float, gap: float):
        if model is None:
            return (None,) * 6
        try:
            result = cut_patterns_component(
                model,
                thickness=thickness,
                gap=0.05 if gap is None else gap,
                unit_scale=document_unit_scale(),
            )
        except CCUError as exc:
            ghenv.Component.AddRuntimeMessage(  # noqa: F821
                Grasshopper.Kernel.GH_RuntimeMessageLevel.Error, str(exc)
            )
            return (None,) * 6
        layers = result.by_layer
        return (
            result.curves,
            result.layers,
            result.plates,
            layers["CUT"],
            layers["CREASE"],
            layers["RULING_SCORE"],
        )
