#! python3
# r: compas_ccu
"""Rhino 8: pick a planar curve, make it the crease of a CCU pair and draw the deployed pair.

Run it in Rhino 8's ScriptEditor (docs/rhino.md): pick a planar open curve (the crease at the
design angle, e.g. an arch drawn in the Front view), give the design angle, the plate width and
the angle to deploy to. The plates (coloured by crease kind), the crease and the rulings are
drawn through COMPAS' scene (``compas_ccu.scene``: the Rhino scene objects), in the document's
units.
"""

import rhinoscriptsyntax as rs
from compas.scene import Scene

from compas_ccu.errors import CCUError
from compas_ccu.ghpython import design_component, document_unit_scale


def main():
    guid = rs.GetObject("Planar curve: the crease at the design angle", rs.filter.curve)
    if guid is None:
        return None
    curve = rs.coercecurve(guid)
    alpha_design = rs.GetReal("Design angle (degrees)", 30.0, 1.0, 89.0)
    width = rs.GetReal("Plate width (m)", 0.3, 0.001)
    segments = rs.GetInteger("Crease segments", 48, 2, 2000)
    if None in (alpha_design, width, segments):
        return None
    unit_scale = document_unit_scale()
    try:
        result = design_component(
            crease=curve,
            alpha=alpha_design,
            width=width,
            segments=segments,
            unit_scale=unit_scale,
        )
    except CCUError as exc:
        rs.MessageBox(str(exc), 0, "compas_ccu")
        return None
    alpha = rs.GetReal("Deploy to angle (degrees)", alpha_design, 0.0, result.model.alpha_limit)
    if alpha is None:
        return None
    print(result.info)
    scene = Scene()
    try:
        scene.add(result.model, alpha=alpha, scale=1.0 / unit_scale)
    except CCUError as exc:
        rs.MessageBox(str(exc), 0, "compas_ccu")
        return None
    return scene.draw()


if __name__ == "__main__":
    main()
