# r: compas_ccu
"""CCU Checks: invariants, overlap, thick-plate collisions and bending of a design at an angle."""

import Grasshopper

from compas_ccu.errors import CCUError
from compas_ccu.ghpython import checks_component


class CCUChecks(Grasshopper.Kernel.GH_ScriptInstance):
    def RunScript(self, model, alpha: float, thickness: float):
        if model is None:
            return None, None, None
        try:
            result = checks_component(model, alpha, thickness=thickness)
        except CCUError as exc:
            ghenv.Component.AddRuntimeMessage(  # noqa: F821
                Grasshopper.Kernel.GH_RuntimeMessageLevel.Error, str(exc)
            )
            return False, str(exc), None
        if not result.ok:
            ghenv.Component.AddRuntimeMessage(  # noqa: F821
                Grasshopper.Kernel.GH_RuntimeMessageLevel.Warning, "a check failed: see report"
            )
        return result.ok, result.report, result.values
