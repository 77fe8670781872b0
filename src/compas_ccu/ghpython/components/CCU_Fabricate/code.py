# r: compas_ccu, ezdxf>=1.3, rhino3dm>=8.4, trimesh>=4, matplotlib>=3.7, compas_nest==0.1.0
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
        for text in result.warnings:  # e.g. no nester installed: the shelves nested the parts
            ghenv.Component.AddRuntimeMessage(  # noqa: F821
                Grasshopper.Kernel.GH_RuntimeMessageLevel.Warning, text
            )
        return result.files, result.info
