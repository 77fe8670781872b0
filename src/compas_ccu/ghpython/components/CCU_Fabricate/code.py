# r: compas_ccu
"""CCU Fabricate: write the workshop files (DXF, 3dm, OBJ / glTF, FOLD, sheets) into a folder."""

import Grasshopper

from compas_ccu.errors import CCUError
from compas_ccu.ghpython import fabricate_component


class CCUFabricate(Grasshopper.Kernel.GH_ScriptInstance):
    def RunScript(self, model, folder: str, thickness: float, run: bool):
        options = {} if thickness is None else {"thickness": thickness}
        try:
            result = fabricate_component(model, folder, run=bool(run), **options)
        except (CCUError, ModuleNotFoundError) as exc:
            ghenv.Component.AddRuntimeMessage(  # noqa: F821
                Grasshopper.Kernel.GH_RuntimeMessageLevel.Error, str(exc)
            )
            return None, str(exc)
        return result.files, result.info
