# r: compas_ccu
"""CCU Deploy: the plates at a reflection angle (slider) as meshes or surfaces, and the creases."""

import Grasshopper
import System

from compas_ccu.errors import CCUError
from compas_ccu.ghpython import deploy_component, document_unit_scale


def _colors(rgbs):
    return [System.Drawing.Color.FromArgb(r, g, b) for r, g, b in rgbs]


class CCUDeploy(Grasshopper.Kernel.GH_ScriptInstance):
    def RunScript(self, model, alpha: float, surfaces: bool, flat: bool, rulings: bool):
        if model is None:
            return (None,) * 7
        try:
            result = deploy_component(
                model,
                alpha,
                surfaces=bool(surfaces),
                state="flat" if flat else "deployed",
                rulings=True if rulings is None else bool(rulings),
                unit_scale=document_unit_scale(),
            )
        except CCUError as exc:
            ghenv.Component.AddRuntimeMessage(  # noqa: F821
                Grasshopper.Kernel.GH_RuntimeMessageLevel.Error, str(exc)
            )
            return (None,) * 6 + (str(exc),)
        return (
            result.structure,
            result.plates,
            result.creases,
            result.rulings,
            _colors(result.plate_colors),
            _colors(result.crease_colors),
            result.info,
        )
